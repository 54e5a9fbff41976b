// How well a light sampler's choice matches what each light delivers, at the camera's first hits
// (and one diffuse bounce further) of a scene: for each point, every finite light's unshadowed
// contribution f_i (its LightBoundsOf intensity x emission cosine x receiver cosine / d^2, from
// its centre) and visibility V_i (a shadow ray to that centre), and each sampler's probability
// p_i. Next-event estimation choosing one light has relative variance
//   sum_i (f_i V_i)^2 / p_i / F^2 - 1,  F = sum_i f_i V_i,
// (light choice only: no sampling within a light), averaged over points; "ideal" is p ~ f
// (unshadowed), whose variance comes from shadows alone. Also the shadowed share of the
// choice and the time per choice. "exact<D": the tree with its choices above depth D made by
// the children's summed f, which shows at which depths the importance loses.
//
//   light_tree_bench SCENE.json [--points N] [--bounce]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "src/geometry/traverse.h"
#include "src/integrator/stages/generate.h"
#include "src/io/scene_loader.h"
#include "src/lights/light_bvh_build.h"
#include "src/lights/light_sample.h"

using namespace pt;

namespace {

struct Point {
  vec3 p, n;
};

std::vector<Point> HitPoints(const SceneView& v, int count, bool bounce, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  std::vector<Point> out;
  const float w = 960.0f, h = 540.0f;
  for (int tries = 0; int(out.size()) < count && tries < 20 * count; ++tries) {
    Ray ray = CameraRay(v.camera, w * u01(rng), h * u01(rng), w, h, vec2(0.5f));
    HitRecord hit;
    if (!IntersectClosest(v, ray, kInfinity, &hit, nullptr)) continue;
    SurfaceInteraction si = MakeInteraction(v, ray, hit);
    if (si.light >= 0) continue;
    vec3 n = glm::dot(si.ng, ray.d) > 0.0f ? -si.ng : si.ng;
    if (bounce) {
      Frame f = Frame::FromZ(n);
      vec3 d = f.FromLocal(SampleCosineHemisphere(vec2(u01(rng), u01(rng))));
      Ray r2{OffsetRayOrigin(si.p, si.pError, n, d), d};
      if (!IntersectClosest(v, r2, kInfinity, &hit, nullptr)) continue;
      si = MakeInteraction(v, r2, hit);
      if (si.light >= 0) continue;
      n = glm::dot(si.ng, r2.d) > 0.0f ? -si.ng : si.ng;
    }
    out.push_back({si.p + 1e-3f * n, n});
  }
  return out;
}

// Probability of every light at r by one walk down the tree (0 for lights outside it). Nodes
// above depth `exactDepth` choose between their children by the children's summed f (the
// ideal), the rest by importance: where the tree's choice loses against the ideal.
void TreePmfs(const SceneView& v, const LightRef& r, const std::vector<double>& nodeF,
              int exactDepth, std::vector<float>* pmf) {
  std::fill(pmf->begin(), pmf->end(), 0.0f);
  struct Item { uint32_t node; float p; int depth; };
  std::vector<Item> stack{{0, 1.0f, 0}};
  while (!stack.empty()) {
    Item it = stack.back();
    stack.pop_back();
    const LightBvhNode& n = v.lightNodes[it.node];
    if (n.IsLeaf()) {
      (*pmf)[n.Light()] = it.node == 0 ? (NodeImportance(v, 0, r) > 0.0f ? 1.0f : 0.0f) : it.p;
      continue;
    }
    float c0 = NodeImportance(v, n.child, r), c1 = NodeImportance(v, n.child + 1, r);
    if (it.depth < exactDepth && nodeF[n.child] + nodeF[n.child + 1] > 0.0) {
      c0 = float(nodeF[n.child]);
      c1 = float(nodeF[n.child + 1]);
    }
    float sum = c0 + c1;
    if (!(sum > 0.0f)) continue;
    if (c0 > 0.0f) stack.push_back({n.child, it.p * c0 / sum, it.depth + 1});
    if (c1 > 0.0f) stack.push_back({n.child + 1, it.p * c1 / sum, it.depth + 1});
  }
}

// Summed f below every node (children follow their parent in the array, so a reverse pass).
void NodeSums(const SceneView& v, const std::vector<double>& f, std::vector<double>* nodeF) {
  nodeF->assign(v.lightTree.nodeCount, 0.0);
  for (uint32_t k = v.lightTree.nodeCount; k-- > 0;) {
    const LightBvhNode& n = v.lightNodes[k];
    (*nodeF)[k] = n.IsLeaf() ? f[n.Light()]
                             : (k == 1 ? 0.0 : (*nodeF)[n.child] + (*nodeF)[n.child + 1]);
  }
}

struct Tally {
  double relVar = 0.0, shadowed = 0.0;
  std::vector<double> each;
  int points = 0;
  void Add(const std::vector<double>& f, const std::vector<char>& vis,
           const std::vector<float>& p) {
    double F = 0.0, second = 0.0, total = 0.0, blocked = 0.0;
    for (size_t i = 0; i < f.size(); ++i) {
      if (p[i] > 0.0f && f[i] > 0.0 && !vis[i]) blocked += p[i];
      total += p[i];
      if (!(f[i] > 0.0) || !vis[i]) continue;
      F += f[i];
      second += p[i] > 0.0f ? f[i] * f[i] / p[i] : 1e30;  // missed light: unbounded
    }
    if (!(F > 0.0)) return;  // no light arrives: nothing to estimate
    relVar += second / (F * F) - 1.0;
    each.push_back(second / (F * F) - 1.0);
    shadowed += total > 0.0 ? blocked / total : 0.0;
    ++points;
  }
  void Print(const char* name) {
    std::sort(each.begin(), each.end());
    auto q = [&](double f) { return each[size_t(f * double(each.size() - 1))]; };
    std::printf("  %-8s relVar %9.3f  shadowed choices %5.1f%%  (%d points) median %.3f "
                "p90 %.3f max %.1f\n", name, relVar / points, 100.0 * shadowed / points, points,
                q(0.5), q(0.9), q(1.0));
  }
};

// Each finite light's unshadowed contribution at r (its bounds shrunk to their centre, so
// LightImportance gives phi x emission cosine x receiver cosine / d^2) and whether a shadow ray
// to that centre passes (stopping short of the light's own surface).
void Contributions(const SceneView& v, const std::vector<std::optional<LightBounds>>& bounds,
                   const LightRef& r, std::vector<double>* f, std::vector<char>* vis) {
  for (size_t i = 0; i < bounds.size(); ++i) {
    (*f)[i] = 0.0;
    (*vis)[i] = 0;
    if (!bounds[i]) continue;
    LightBounds b = *bounds[i];
    float size = glm::length(0.5f * (b.hi - b.lo));
    b.lo = b.hi = 0.5f * (b.lo + b.hi);
    (*f)[i] = LightImportance(b, r);
    if (!((*f)[i] > 0.0)) continue;
    vec3 d = b.lo - r.p;
    float dist = glm::length(d);
    (*vis)[i] = !IntersectAny(v, Ray{r.p, d / dist}, dist - 1.01f * size, nullptr);
  }
}

constexpr int kExactDepths[] = {2, 4, 6, 8, 12};
constexpr int kHybrids = int(sizeof(kExactDepths) / sizeof(kExactDepths[0]));

void Study(const Scene& scene, const SceneView& v, const std::vector<Point>& pts) {
  uint32_t n = v.lightTree.boundedCount;
  std::vector<std::optional<LightBounds>> bounds(n);
  double powerSum = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    bounds[i] = LightBoundsOf(scene, i);
    powerSum += v.lightPmf[i];
  }
  Tally ideal, power, bvh, hybrid[kHybrids];
  std::vector<double> f(n), nodeF;
  std::vector<char> vis(n);
  std::vector<float> pIdeal(n), pPower(n), pBvh(n);
  for (const Point& pt : pts) {
    LightRef r{pt.p, pt.n, false};
    Contributions(v, bounds, r, &f, &vis);
    double fSum = 0.0;
    for (uint32_t i = 0; i < n; ++i) fSum += f[i];
    for (uint32_t i = 0; i < n; ++i) {
      pIdeal[i] = fSum > 0.0 ? float(f[i] / fSum) : 0.0f;
      pPower[i] = float(v.lightPmf[i] / powerSum);
    }
    NodeSums(v, f, &nodeF);
    for (int k = 0; k < kHybrids; ++k) {
      TreePmfs(v, r, nodeF, kExactDepths[k], &pBvh);
      hybrid[k].Add(f, vis, pBvh);
    }
    TreePmfs(v, r, nodeF, 0, &pBvh);
    ideal.Add(f, vis, pIdeal);
    power.Add(f, vis, pPower);
    bvh.Add(f, vis, pBvh);
  }
  ideal.Print("ideal");
  power.Print("power");
  bvh.Print("bvh");
  for (int k = 0; k < kHybrids; ++k)
    hybrid[k].Print(("exact<" + std::to_string(kExactDepths[k])).c_str());
}

// Nanoseconds per choice of the power table and the tree, over the points in turn.
void TimeChoices(const SceneView& v, const std::vector<Point>& pts) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const int kChoices = 2000000;
  double sink = 0.0;
  for (int method = 0; method < 2; ++method) {
    auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < kChoices; ++k) {
      const Point& pt = pts[size_t(k) % pts.size()];
      LightRef r{pt.p, pt.n, false};
      int light = 0;
      float pmf = 0.0f;
      if (method == 0) light = SampleLightIndex(v, u01(rng));
      else SampleLightTree(v, r, u01(rng), u01(rng), &light, &pmf);
      sink += light + pmf;
    }
    double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0)
                    .count() / kChoices;
    std::printf("  %s choice: %.1f ns%s\n", method == 0 ? "power" : "bvh", ns,
                sink < 0.0 ? " " : "");  // sink keeps the loop
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: light_tree_bench SCENE.json [--points N] [--bounce]\n");
    return 2;
  }
  int count = 400;
  bool bounce = false;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--points") && i + 1 < argc) count = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--bounce")) bounce = true;
  }
  Scene scene = BuildScene(LoadScene(argv[1]));
  SceneView v = HostSceneView(scene);
  v.lightTree.sampler = uint32_t(LightSampler::kBvh);
  std::vector<Point> pts = HitPoints(v, count, bounce, 7);
  if (pts.empty() || v.lightTree.nodeCount == 0) {
    std::fprintf(stderr, "light_tree_bench: no hit points or no light tree\n");
    return 1;
  }
  std::printf("%s: %u finite lights, %u tree nodes, %zu %s points\n", argv[1],
              v.lightTree.boundedCount, v.lightTree.nodeCount, pts.size(),
              bounce ? "second-hit" : "first-hit");
  double depthSum = 0.0;
  int leaves = 0, deepest = 0;
  for (uint32_t i = 0; i < v.lightTree.boundedCount; ++i) {
    if (v.lightTrails[i] == 0) continue;
    int depth = 63 - __builtin_clzll(v.lightTrails[i]);  // the trail's end marker
    depthSum += depth;
    deepest = std::max(deepest, depth);
    ++leaves;
  }
  std::printf("  leaf depth: mean %.1f, deepest %d\n", depthSum / leaves, deepest);
  Study(scene, v, pts);
  TimeChoices(v, pts);
  return 0;
}
