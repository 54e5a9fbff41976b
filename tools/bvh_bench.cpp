// Ray-traversal and BVH-build benchmark on the CPU: builds a scene's BVH (timed), then traces
// random rays through it on N threads and prints rays/s for closest-hit and any-hit queries.
//
//   bvh_bench SCENE.json [--threads N] [--rays N] [--repeats N] [--bvh binary|wide|all]
//             [--bvh-build sah|sbvh|all] [--rays-kind inside|outside] [--check]
//             [--tri-test watertight|box-clamped]
//
// Rays (fixed seed, the same for every layout): "inside" start uniformly in the scene's bounding
// box with uniform directions (incoherent secondary rays); "outside" start on the bounding
// sphere at 1.5 radii and aim at a uniform point of the box (camera-like, ~half hit).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "src/geometry/bvh.h"
#include "src/geometry/traverse.h"
#include "src/io/scene_loader.h"
#include "src/scene/effects.h"

namespace pt {
namespace {

struct Args {
  std::string scene;
  int threads = 2;
  int rays = 2000000;
  int repeats = 5;
  std::vector<BvhLayout> layouts = {BvhLayout::kBinary, BvhLayout::kWide};
  std::vector<BvhBuilder> builders = {BvhBuilder::kSah};
  bool inside = true;
  bool check = false;  // compare layouts and builders ray by ray instead of timing
  uint32_t triangleTest = kTriTestWatertight;  // as the renderer's --tri-test
};

double Seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::vector<Ray> MakeRays(const Scene& scene, int count, bool inside) {
  Aabb box;
  for (uint32_t i = 0; i < scene.prims.size(); ++i) box.Extend(PrimBounds(HostSceneView(scene), i));
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  auto inBox = [&] { return box.lo + vec3(u(rng), u(rng), u(rng)) * (box.hi - box.lo); };
  auto unit = [&] {
    float z = 1.0f - 2.0f * u(rng), phi = 2.0f * kPi * u(rng), r = std::sqrt(std::max(0.0f, 1 - z * z));
    return vec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  vec3 center = box.Centroid();
  float radius = 0.5f * glm::length(box.hi - box.lo);
  std::vector<Ray> rays(count);
  for (Ray& r : rays) {
    if (inside) {
      r = Ray{inBox(), unit()};
    } else {
      vec3 o = center + 1.5f * radius * unit();
      r = Ray{o, glm::normalize(inBox() - o)};
    }
  }
  return rays;
}

double ProcessCpuSeconds() {  // all threads
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double ThreadCpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// Rays/s of one query over all rays on `threads` threads (rays split in contiguous blocks), by
// wall time; *cpuRate by the busiest thread's CPU time: the rate on dedicated cores, which a
// machine shared with other work (wall time stretched by waiting) still measures.
template <typename Query>
double TraceRate(const std::vector<Ray>& rays, int threads, const Query& query, uint64_t* hits,
                 double* cpuRate) {
  std::vector<uint64_t> counts(threads, 0);
  std::vector<double> cpu(threads, 0.0);
  double t0 = Seconds();
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      size_t begin = rays.size() * t / threads, end = rays.size() * (t + 1) / threads;
      uint64_t n = 0;
      double c0 = ThreadCpuSeconds();
      for (size_t i = begin; i < end; ++i) n += query(rays[i]);
      cpu[t] = ThreadCpuSeconds() - c0;
      counts[t] = n;
    });
  }
  for (std::thread& th : pool) th.join();
  double seconds = Seconds() - t0;
  *hits = 0;
  for (uint64_t c : counts) *hits += c;
  *cpuRate = double(rays.size()) / *std::max_element(cpu.begin(), cpu.end());
  return double(rays.size()) / seconds;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The queries the renderer's stages run for this scene: with no material asking for a hit test
// (alpha, back-face culling), the traversal compiled without that test.
struct Queries {
  const SceneView& view;
  bool hitTests;

  bool Closest(const Ray& ray, HitRecord* hit, TraversalCounters* counters) const {
    return hitTests ? IntersectClosest<true>(view, ray, kInfinity, hit, counters)
                    : IntersectClosest<false>(view, ray, kInfinity, hit, counters);
  }
  bool Any(const Ray& ray) const {
    return hitTests ? IntersectAny<true>(view, ray, kInfinity, nullptr)
                    : IntersectAny<false>(view, ray, kInfinity, nullptr);
  }
};

void RunOne(const Args& args, const SceneDesc& desc, BvhBuilder builder, BvhLayout layout) {
  BvhBuildOptions options;
  options.builder = builder;
  options.layout = layout;
  options.threads = args.threads;
  std::vector<double> buildMs, buildCpuMs;
  Scene scene;
  for (int r = 0; r < std::max(1, args.repeats); ++r) {
    double cpu0 = ProcessCpuSeconds();
    scene = BuildScene(desc, options);
    buildCpuMs.push_back(1e3 * (ProcessCpuSeconds() - cpu0));
    buildMs.push_back(scene.bvhBuildMs);
  }
  SceneView view = HostSceneView(scene);
  view.triangleTest = args.triangleTest;
  std::vector<Ray> rays = MakeRays(scene, args.rays, args.inside);
  std::vector<double> closest, any, closestCpu, anyCpu;
  double cpuRate = 0.0;
  uint64_t hitsClosest = 0, hitsAny = 0;
  TraversalCounters work;
  const Queries q{view, (AnalyzeEffects(scene) & (kEffectAlpha | kEffectBackfaceCulling)) != 0 ||
                            args.triangleTest == kTriTestBoxClamped};
  for (const Ray& r : std::vector<Ray>(rays.begin(), rays.begin() + std::min<size_t>(rays.size(), 100000))) {
    HitRecord hit;
    q.Closest(r, &hit, &work);
  }
  for (int r = 0; r < args.repeats; ++r) {
    closest.push_back(TraceRate(rays, args.threads, [&](const Ray& ray) {
      HitRecord hit;
      return q.Closest(ray, &hit, nullptr) ? 1 : 0;
    }, &hitsClosest, &cpuRate));
    closestCpu.push_back(cpuRate);
    any.push_back(TraceRate(rays, args.threads, [&](const Ray& ray) {
      return q.Any(ray) ? 1 : 0;
    }, &hitsAny, &cpuRate));
    anyCpu.push_back(cpuRate);
  }
  double sampled = double(std::min<size_t>(rays.size(), 100000));
  std::printf("%-6s %-6s %9zu prims  build %8.1f ms  %6.1f node B/prim  SAH %7.2f  nodes/ray %6.2f  "
              "prims/ray %6.2f  closest %7.2f Mrays/s  any %7.2f Mrays/s  hits %.3f\n",
              BvhBuilderName(builder), BvhLayoutName(layout), scene.prims.size(), Median(buildMs),
              double(scene.NodeBytes()) / double(std::max<size_t>(1, scene.prims.size())),
              scene.bvhSahCost, work.nodes / sampled, work.prims / sampled,
              Median(closest) * 1e-6, Median(any) * 1e-6, double(hitsClosest) / rays.size());
  std::printf("       by CPU time (dedicated cores): closest %7.2f Mrays/s  any %7.2f Mrays/s  "
              "scene build (BVH and the rest of BuildScene) %.1f ms CPU over all threads\n",
              Median(closestCpu) * 1e-6, Median(anyCpu) * 1e-6, Median(buildCpuMs));
  if (hitsClosest != hitsAny) std::printf("  ERROR: closest and any-hit disagree on hits\n");
}

// --check: every ray's closest hit (distance, shape, barycentrics) and any-hit answer under
// the binary SAH tree against each other builder/layout; prints the first disagreements.
int CheckLayouts(const Args& args, const SceneDesc& desc) {
  BvhBuildOptions refOptions;
  refOptions.threads = args.threads;
  Scene ref = BuildScene(desc, refOptions);
  SceneView refView = HostSceneView(ref);
  refView.triangleTest = args.triangleTest;
  std::vector<Ray> rays = MakeRays(ref, args.rays, args.inside);
  int bad = 0;
  for (BvhBuilder b : args.builders) {
    for (BvhLayout l : args.layouts) {
      BvhBuildOptions options = refOptions;
      options.builder = b;
      options.layout = l;
      Scene other = BuildScene(desc, options);
      SceneView view = HostSceneView(other);
      view.triangleTest = args.triangleTest;
      size_t mismatches = 0;
      for (size_t i = 0; i < rays.size(); ++i) {
        HitRecord h0, h1;
        bool a = IntersectClosest(refView, rays[i], kInfinity, &h0, nullptr);
        bool c = IntersectClosest(view, rays[i], kInfinity, &h1, nullptr);
        bool same = a == c && (!a || (h0.t == h1.t && h0.uv == h1.uv &&
                                      refView.prims[h0.prim].tagIndex == view.prims[h1.prim].tagIndex));
        float shadowT = a ? 0.999f * h0.t : 10.0f;
        same = same && IntersectAny(refView, rays[i], shadowT, nullptr) ==
                           IntersectAny(view, rays[i], shadowT, nullptr);
        if (same) continue;
        // Brute force over every primitive: which of the two is right.
        float bruteT = kInfinity;
        uint32_t bruteShape = 0, bruteIndex = 0;
        for (uint32_t p = 0; p < refView.primCount; ++p) {
          float t;
          vec2 uv;
          if (IntersectPrim(refView, p, rays[i], bruteT, &t, &uv))
            bruteT = t, bruteShape = refView.prims[p].tagIndex, bruteIndex = p;
        }
        if (++mismatches <= 5)
          {
            Aabb box = PrimBounds(refView, bruteIndex);
            vec3 inv(1.0f / rays[i].d.x, 1.0f / rays[i].d.y, 1.0f / rays[i].d.z);
            float entry = -1.0f;
            bool boxHit = IntersectAabb(box.lo, box.hi, rays[i].o, inv, kInfinity, &entry);
            std::printf("  brute force: t %.9g shape %u; its box: hit %d entry %.9g extent (%g %g %g)\n",
                        bruteT, bruteShape, int(boxHit), entry, box.hi.x - box.lo.x,
                        box.hi.y - box.lo.y, box.hi.z - box.lo.z);
          }
        if (mismatches <= 5)
          std::printf("  %s %s ray %zu: o (%.9g %.9g %.9g) d (%.9g %.9g %.9g): t %.9g vs %.9g, shape %u vs %u\n",
                      BvhBuilderName(b), BvhLayoutName(l), i, rays[i].o.x, rays[i].o.y, rays[i].o.z,
                      rays[i].d.x, rays[i].d.y, rays[i].d.z, h0.t, h1.t,
                      a ? refView.prims[h0.prim].tagIndex : 0u, c ? view.prims[h1.prim].tagIndex : 0u);
      }
      std::printf("%-6s %-6s %zu of %zu rays disagree with binary sah\n", BvhBuilderName(b),
                  BvhLayoutName(l), mismatches, rays.size());
      bad += mismatches != 0;
    }
  }
  return bad ? 1 : 0;
}

}  // namespace
}  // namespace pt

int main(int argc, char** argv) {
  using namespace pt;
  Args args;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) { std::fprintf(stderr, "bvh_bench: %s needs a value\n", a.c_str()); std::exit(1); }
      return argv[++i];
    };
    if (a == "--threads") args.threads = std::stoi(next());
    else if (a == "--rays") args.rays = std::stoi(next());
    else if (a == "--repeats") args.repeats = std::stoi(next());
    else if (a == "--rays-kind") args.inside = next() == "inside";
    else if (a == "--check") args.check = true;
    else if (a == "--tri-test") {
      const std::string v = next();
      if (v != "watertight" && v != "box-clamped") args.layouts.clear();  // usage below
      args.triangleTest = v == "box-clamped" ? kTriTestBoxClamped : kTriTestWatertight;
    }
    else if (a == "--bvh") {
      std::string v = next();
      args.layouts.clear();
      if (v == "binary" || v == "all") args.layouts.push_back(BvhLayout::kBinary);
      if (v == "wide" || v == "all") args.layouts.push_back(BvhLayout::kWide);
    } else if (a == "--bvh-build") {
      std::string v = next();
      args.builders.clear();
      if (v == "sah" || v == "all") args.builders.push_back(BvhBuilder::kSah);
      if (v == "sbvh" || v == "all") args.builders.push_back(BvhBuilder::kSbvh);
      if (v == "gpu" || v == "all") args.builders.push_back(BvhBuilder::kLbvh);  // host threads
    } else if (a[0] != '-') args.scene = a;
    else { std::fprintf(stderr, "bvh_bench: unknown option %s\n", a.c_str()); return 1; }
  }
  if (args.scene.empty() || args.layouts.empty() || args.builders.empty() || args.threads < 1) {
    std::fprintf(stderr, "usage: bvh_bench SCENE.json [--threads N] [--rays N] [--repeats N] "
                         "[--bvh binary|wide|all] [--bvh-build sah|sbvh|all] [--rays-kind inside|outside] "
                         "[--check] [--tri-test watertight|box-clamped]\n");
    return 1;
  }
  SceneDesc desc = LoadScene(args.scene);
  std::printf("%s: %zu triangles, %d threads, %d %s rays, medians of %d\n", args.scene.c_str(),
              desc.triangles.size(), args.threads, args.rays, args.inside ? "inside" : "outside",
              args.repeats);
  if (args.check) return CheckLayouts(args, desc);
  for (BvhBuilder b : args.builders)
    for (BvhLayout l : args.layouts) RunOne(args, desc, b, l);
  return 0;
}
