// The CPU denoiser's time alone (issue 31: 1920x1080 in <= 2 s on 2 cores): renders a scene
// once with half films and features (or reads a film saved by an earlier run, so that runs of
// different builds denoise the same input), then denoises it several times, printing each
// run's wall time and the process's CPU time (user + sys) over it. --out keeps the denoised
// image (raw floats) and --compare reports the largest difference from one kept before.
//
//   denoise_bench SCENE.json [--spp N] [--size WxH] [--threads N] [--runs N] [--film FILE]
//                 [--out FILE] [--compare FILE]
// Prints the least wall and CPU time over the runs too (the machine may be shared).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "src/denoise/denoiser.h"
#include "src/io/scene_loader.h"
#include "src/scene/scene.h"

using namespace pt;

namespace {

template <typename T>
void Put(std::ofstream& f, const std::vector<T>& v) {
  uint64_t n = v.size();
  f.write(reinterpret_cast<const char*>(&n), sizeof(n));
  f.write(reinterpret_cast<const char*>(v.data()), std::streamsize(n * sizeof(T)));
}

template <typename T>
bool Get(std::ifstream& f, std::vector<T>& v) {
  uint64_t n = 0;
  if (!f.read(reinterpret_cast<char*>(&n), sizeof(n))) return false;
  v.resize(n);
  return bool(f.read(reinterpret_cast<char*>(v.data()), std::streamsize(n * sizeof(T))));
}

void SaveFilm(const std::string& path, const FilmImage& img) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(&img.width), sizeof(int) * 2);
  Put(f, img.rgb), Put(f, img.variance), Put(f, img.samples), Put(f, img.albedo);
  Put(f, img.normal), Put(f, img.depth), Put(f, img.evenRgb), Put(f, img.evenSamples);
}

bool LoadFilm(const std::string& path, FilmImage& img) {
  std::ifstream f(path, std::ios::binary);
  if (!f.read(reinterpret_cast<char*>(&img.width), sizeof(int) * 2)) return false;
  return Get(f, img.rgb) && Get(f, img.variance) && Get(f, img.samples) &&
         Get(f, img.albedo) && Get(f, img.normal) && Get(f, img.depth) &&
         Get(f, img.evenRgb) && Get(f, img.evenSamples);
}

double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto s = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return s(u.ru_utime) + s(u.ru_stime);
}

void Compare(const std::string& path, const std::vector<float>& now) {
  std::vector<float> before;
  std::ifstream f(path, std::ios::binary);
  if (!Get(f, before) || before.size() != now.size()) {
    std::printf("compare: %s unreadable or of another size\n", path.c_str());
    return;
  }
  double maxAbs = 0.0, maxRel = 0.0;
  size_t differing = 0;
  for (size_t i = 0; i < now.size(); ++i) {
    double d = std::fabs(double(now[i]) - double(before[i]));
    differing += now[i] != before[i];
    maxAbs = std::max(maxAbs, d);
    maxRel = std::max(maxRel, d / (std::fabs(double(before[i])) + 1e-3));
  }
  std::printf("compare: %zu of %zu values differ, max abs %.3g, max rel %.3g\n", differing,
              now.size(), maxAbs, maxRel);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: denoise_bench SCENE.json [--spp N] [--threads N] [--runs N] "
                         "[--film FILE] [--out FILE] [--compare FILE]\n");
    return 2;
  }
  int spp = 4, threads = 2, runs = 3, width = 0, height = 0;
  std::string film, out, compare;
  for (int i = 2; i + 1 < argc; i += 2) {
    std::string a = argv[i], v = argv[i + 1];
    if (a == "--spp") spp = std::stoi(v);
    else if (a == "--threads") threads = std::stoi(v);
    else if (a == "--size") std::sscanf(v.c_str(), "%dx%d", &width, &height);
    else if (a == "--runs") runs = std::stoi(v);
    else if (a == "--film") film = v;
    else if (a == "--out") out = v;
    else if (a == "--compare") compare = v;
  }
  FilmImage img;
  if (film.empty() || !LoadFilm(film, img)) {
    SceneDesc desc = LoadScene(argv[1]);
    desc.render.spp = spp;
    if (width > 0 && height > 0) desc.render.width = width, desc.render.height = height;
    RenderOptions o;
    o.threads = threads;
    o.featureBuffers = o.halfFilms = true;
    img = RenderCpu(BuildScene(std::move(desc)), o).image;
    if (!film.empty()) SaveFilm(film, img);
  }
  std::unique_ptr<Denoiser> denoiser = MakeCpuDenoiser(threads);
  double bestWall = 1e30, bestCpu = 1e30;
  for (int r = 0; r < runs; ++r) {
    double cpu0 = CpuSeconds();
    auto t0 = std::chrono::steady_clock::now();
    denoiser->Denoise(img);
    double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double cpu = CpuSeconds() - cpu0;
    bestWall = std::min(bestWall, wall), bestCpu = std::min(bestCpu, cpu);
    std::printf("run %d: %dx%d wall %.3f s, cpu %.3f s (threads %d)\n", r + 1, img.width,
                img.height, wall, cpu, threads);
    std::fflush(stdout);
  }
  if (runs > 0) std::printf("least: wall %.3f s, cpu %.3f s\n", bestWall, bestCpu);
  if (!out.empty()) {
    std::ofstream f(out, std::ios::binary);
    Put(f, img.denoised);
  }
  if (!compare.empty()) Compare(compare, img.denoised);
  return 0;
}
