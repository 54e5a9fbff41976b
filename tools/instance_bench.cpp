// Instancing benchmark on the CPU: builds a scene with instances (timed), reports what its two
// levels hold in memory, then moves instances and rebuilds the top level only - what an
// interactive preview does per frame - and prints the median cost.
//
//   instance_bench SCENE.json [--bvh binary|wide] [--moves N] [--repeats N] [--threads N]
//
// Each repeat moves N instances (chosen with a fixed seed; all of them when N exceeds the count)
// by a small translation and rotation (UpdateInstanceTransform), then calls RebuildTopLevel.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "src/io/scene_loader.h"
#include "src/scene/instances.h"

namespace pt {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

struct Args {
  std::string scene;
  BvhLayout layout = BvhLayout::kBinary;
  int moves = 1;
  int repeats = 20;
  int threads = 0;
};

bool ParseArgs(int argc, char** argv, Args* args) {
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    bool hasValue = i + 1 < argc;
    if (a == "--bvh" && hasValue) {
      std::string v = argv[++i];
      if (v != "binary" && v != "wide") return false;
      args->layout = v == "wide" ? BvhLayout::kWide : BvhLayout::kBinary;
    } else if (a == "--moves" && hasValue) {
      args->moves = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--repeats" && hasValue) {
      args->repeats = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--threads" && hasValue) {
      args->threads = std::max(0, std::atoi(argv[++i]));
    } else if (!a.empty() && a[0] != '-' && args->scene.empty()) {
      args->scene = a;
    } else {
      return false;
    }
  }
  return !args->scene.empty();
}

template <typename T>
double MiB(const std::vector<T>& v) {
  return double(v.size() * sizeof(T)) / (1 << 20);
}

void PrintMemory(const Scene& s) {
  const SceneDesc& d = s.desc;
  double mesh = MiB(d.triangles) + MiB(d.triangleNormals) + MiB(d.triangleUvs) +
                MiB(d.triangleMaterials) + MiB(s.packedTriangles) + MiB(s.prims) +
                MiB(s.nodes) + MiB(s.wideNodes);
  double table = MiB(s.instances) + MiB(s.instanceOrder) + MiB(s.tlasNodes) +
                 MiB(s.tlasWideNodes);
  std::printf("triangles stored %zu, placed %llu, instances %zu, lights %zu\n",
              d.triangles.size(), (unsigned long long)s.PlacedTriangleCount(), s.instances.size(),
              s.lights.size());
  std::printf("memory: meshes + bottom levels %.2f MiB, instance table + top level %.2f MiB "
              "(%u top-level nodes)\n",
              mesh, table, s.TlasNodeCount());
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int Run(const Args& args) {
  Clock::time_point start = Clock::now();
  SceneDesc desc = LoadScene(args.scene);
  double loadMs = MsSince(start);
  BvhBuildOptions options;
  options.layout = args.layout;
  options.threads = args.threads;
  start = Clock::now();
  Scene scene = BuildScene(std::move(desc), options);
  double buildMs = MsSince(start);
  std::printf("%s, %s layout: load %.1f ms, build %.1f ms (top level %.3f ms)\n",
              args.scene.c_str(), BvhLayoutName(args.layout), loadMs, buildMs, scene.tlasBuildMs);
  PrintMemory(scene);
  size_t count = scene.desc.instances.size();
  if (count == 0) {
    std::fprintf(stderr, "instance_bench: %s has no instances\n", args.scene.c_str());
    return 2;
  }
  std::mt19937 rng(1);
  std::uniform_int_distribution<size_t> pick(0, count - 1);
  std::uniform_real_distribution<double> jitter(-0.01, 0.01);
  size_t moves = std::min(size_t(args.moves), count);
  std::vector<double> updateMs, rebuildMs;
  for (int r = 0; r < args.repeats; ++r) {
    start = Clock::now();
    for (size_t m = 0; m < moves; ++m) {
      size_t i = moves == count ? m : pick(rng);
      glm::dmat4 to = glm::translate(glm::dmat4(1.0), glm::dvec3(jitter(rng), 0.0, jitter(rng))) *
                      scene.desc.instances[i].toWorld;
      to = glm::rotate(to, jitter(rng), glm::dvec3(0.0, 1.0, 0.0));
      UpdateInstanceTransform(scene, i, to);
    }
    updateMs.push_back(MsSince(start));
    start = Clock::now();
    RebuildTopLevel(scene);
    rebuildMs.push_back(MsSince(start));
  }
  std::printf("move %zu of %zu instances: update %.3f ms, RebuildTopLevel %.3f ms "
              "(medians of %d)\n",
              moves, count, Median(updateMs), Median(rebuildMs), args.repeats);
  return 0;
}

}  // namespace
}  // namespace pt

int main(int argc, char** argv) {
  pt::Args args;
  if (!pt::ParseArgs(argc, argv, &args)) {
    std::fprintf(stderr,
                 "usage: instance_bench SCENE.json [--bvh binary|wide] [--moves N] "
                 "[--repeats N] [--threads N]\n");
    return 1;
  }
  try {
    return pt::Run(args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "instance_bench: %s\n", e.what());
    return 2;
  }
}
