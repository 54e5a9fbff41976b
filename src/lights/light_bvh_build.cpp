#include "src/lights/light_bvh_build.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "src/geometry/instance.h"
#include "src/lights/light_sample.h"

namespace pt {

namespace {

using glm::dvec3;

// A cone of directions: unit axis w, half-angle theta (as its cosine; -1: every direction).
struct EmissionCone {
  dvec3 w{0.0, 0.0, 1.0};
  double cosTheta = 1.0;
};

// Whether cone a holds cone b, whose axes are theta_d apart: theta_d + theta_b <= theta_a,
// by cosines (no inverse trigonometry: the builder asks this for every light at every level).
bool ConeHolds(const EmissionCone& a, const EmissionCone& b, double cosD, double sinD) {
  if (a.cosTheta <= -1.0) return true;
  double cosB = b.cosTheta, sinB = std::sqrt(std::max(0.0, 1.0 - cosB * cosB));
  if (cosD < -cosB) return false;  // theta_d + theta_b > pi
  return cosD * cosB - sinD * sinB >= a.cosTheta;
}

// The smallest cone this construction finds around both (pbrt-v4's DirectionCone::Union).
EmissionCone UnionCone(const EmissionCone& a, const EmissionCone& b) {
  if (a.w == b.w) return EmissionCone{a.w, std::min(a.cosTheta, b.cosTheta)};  // coplanar
  double cosD = std::clamp(glm::dot(a.w, b.w), -1.0, 1.0);
  double sinD = std::sqrt(std::max(0.0, 1.0 - cosD * cosD));
  if (ConeHolds(a, b, cosD, sinD)) return a;
  if (ConeHolds(b, a, cosD, sinD)) return b;
  double thetaA = std::acos(std::clamp(a.cosTheta, -1.0, 1.0));
  double thetaB = std::acos(std::clamp(b.cosTheta, -1.0, 1.0));
  double thetaD = std::acos(cosD);
  double thetaO = 0.5 * (thetaA + thetaD + thetaB);
  if (thetaO >= M_PI) return EmissionCone{a.w, -1.0};
  dvec3 axis = glm::cross(a.w, b.w);
  double len = glm::length(axis);
  if (!(len > 1e-12)) return EmissionCone{a.w, -1.0};
  axis /= len;
  // Rodrigues: a.w turned by thetaO - thetaA towards b.w.
  double r = thetaO - thetaA, c = std::cos(r), s = std::sin(r);
  dvec3 w = a.w * c + glm::cross(axis, a.w) * s + axis * glm::dot(axis, a.w) * (1.0 - c);
  return EmissionCone{glm::normalize(w), std::cos(thetaO)};
}

// Bounds in double while building.
struct LightBuildBounds {
  dvec3 lo{INFINITY}, hi{-INFINITY};
  EmissionCone cone;
  double phi = 0.0;
  double cosTheta_e = 1.0;
  bool twoSided = false;
  bool flat = false;  // one-sided flat emitters of normal exactly cone.w
  bool empty = true;

  void Add(const LightBuildBounds& o) {
    if (o.empty) return;
    flat = (empty || (flat && cone.w == o.cone.w)) && o.flat;
    lo = glm::min(lo, o.lo);
    hi = glm::max(hi, o.hi);
    cone = empty ? o.cone : UnionCone(cone, o.cone);
    phi += o.phi;
    cosTheta_e = empty ? o.cosTheta_e : std::min(cosTheta_e, o.cosTheta_e);
    twoSided = twoSided || o.twoSided;
    empty = false;
  }
};

LightBuildBounds ToBuild(const LightBounds& b) {
  LightBuildBounds o;
  o.lo = dvec3(b.lo);
  o.hi = dvec3(b.hi);
  o.cone = EmissionCone{glm::normalize(dvec3(b.w)), double(b.cosTheta_o)};
  o.phi = double(b.phi);
  o.cosTheta_e = double(b.cosTheta_e);
  o.twoSided = b.twoSided;
  o.flat = b.flat;
  o.empty = false;
  return o;
}

// The surface area orientation heuristic of a candidate child (Conty Estevez and Kulla 2018,
// eq. 1-2): phi times the solid-angle measure of its emission cone times its box's area, with
// pbrt-v4's regulariser against long thin boxes split across their short axis.
double SaohCost(const LightBuildBounds& b, double kr) {
  if (b.empty) return 0.0;
  double thetaO = std::acos(std::clamp(b.cone.cosTheta, -1.0, 1.0));
  double thetaE = std::acos(std::clamp(b.cosTheta_e, -1.0, 1.0));
  double thetaW = std::min(thetaO + thetaE, M_PI);
  double sinO = std::sin(thetaO), cosO = std::cos(thetaO);
  double mOmega = 2.0 * M_PI * (1.0 - cosO) +
                  0.5 * M_PI * (2.0 * thetaW * sinO - std::cos(thetaO - 2.0 * thetaW) -
                                2.0 * thetaO * sinO + cosO);
  dvec3 e = b.hi - b.lo;
  double area = 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
  return b.phi * mOmega * kr * area;
}

struct LightItem {
  LightBuildBounds b;
  dvec3 centroid;
  uint32_t light;
};

struct LightTreeBuilder {
  std::vector<LightItem>& items;
  std::vector<LightBuildBounds> bounds;  // per node, quantised at the end
  std::vector<uint32_t> child;      // per node: first child, or kLeafBit | light
  std::vector<uint64_t>& trails;    // per light

  static constexpr int kBuckets = 12;

  static int CeilLog2(size_t n) {
    int d = 0;
    while ((size_t(1) << d) < n) ++d;
    return d;
  }

  // Index in [begin, end) where the items are split (partitioned in place), and the bounds
  // of the two sides.
  size_t Split(size_t begin, size_t end, const LightBuildBounds& node, int depth,
               LightBuildBounds* left, LightBuildBounds* right) {
    dvec3 clo(INFINITY), chi(-INFINITY);
    for (size_t i = begin; i < end; ++i) {
      clo = glm::min(clo, items[i].centroid);
      chi = glm::max(chi, items[i].centroid);
    }
    dvec3 extent = chi - clo;
    int bestDim = -1, bestBucket = -1;
    double bestCost = INFINITY;
    // Deep trees fall back to halving by count, so no light's trail outgrows 64 bits.
    bool balanced = depth + CeilLog2(end - begin) >= kLightBvhMaxDepth;
    dvec3 nodeExtent = node.hi - node.lo;
    double maxExtent = std::max({nodeExtent.x, nodeExtent.y, nodeExtent.z});
    for (int dim = 0; dim < 3 && !balanced; ++dim) {
      if (!(extent[dim] > 0.0)) continue;
      LightBuildBounds bucket[kBuckets];
      for (size_t i = begin; i < end; ++i)
        bucket[BucketOf(items[i], clo, extent, dim)].Add(items[i].b);
      double kr = nodeExtent[dim] > 0.0 ? maxExtent / nodeExtent[dim] : 1.0;
      LightBuildBounds above[kBuckets];  // above[s]: buckets s to the last
      above[kBuckets - 1] = bucket[kBuckets - 1];
      for (int s = kBuckets - 2; s >= 0; --s) {
        above[s] = above[s + 1];
        above[s].Add(bucket[s]);
      }
      LightBuildBounds below;
      for (int s = 0; s + 1 < kBuckets; ++s) {
        below.Add(bucket[s]);
        if (below.empty || above[s + 1].empty) continue;
        double cost = SaohCost(below, kr) + SaohCost(above[s + 1], kr);
        if (cost < bestCost) {
          bestCost = cost;
          bestDim = dim;
          bestBucket = s;
          *left = below;
          *right = above[s + 1];
        }
      }
    }
    if (bestDim >= 0) {
      auto below = [&](const LightItem& it) {
        return BucketOf(it, clo, extent, bestDim) <= bestBucket;
      };
      auto mid = std::partition(items.begin() + begin, items.begin() + end, below);
      size_t m = size_t(mid - items.begin());
      if (m > begin && m < end) return m;
    }
    // Coincident centroids (or the depth limit): halve by count along the widest axis.
    int dim = MaxDimension(vec3(extent));
    size_t m = begin + (end - begin) / 2;
    std::nth_element(items.begin() + begin, items.begin() + m, items.begin() + end,
                     [dim](const LightItem& a, const LightItem& b) {
                       return a.centroid[dim] < b.centroid[dim] ||
                              (a.centroid[dim] == b.centroid[dim] && a.light < b.light);
                     });
    *left = *right = LightBuildBounds{};
    for (size_t i = begin; i < end; ++i) (i < m ? left : right)->Add(items[i].b);
    return m;
  }

  static int BucketOf(const LightItem& it, dvec3 clo, dvec3 extent, int dim) {
    int b = int(double(kBuckets) * (it.centroid[dim] - clo[dim]) / extent[dim]);
    return std::clamp(b, 0, kBuckets - 1);
  }

  // Fills node `node` with items [begin, end) at `depth`; `trail` is its path from the root
  // with the end marker at bit `depth`.
  void Build(uint32_t node, size_t begin, size_t end, int depth, uint64_t trail,
             const LightBuildBounds& b) {
    bounds[node] = b;
    if (end - begin == 1) {
      child[node] = LightBvhNode::kLeafBit | items[begin].light;
      trails[items[begin].light] = trail;
      return;
    }
    LightBuildBounds left, right;
    size_t mid = Split(begin, end, b, depth, &left, &right);
    uint32_t first = uint32_t(bounds.size());
    bounds.resize(first + 2);
    child.resize(first + 2);
    child[node] = first;
    uint64_t marker = uint64_t(1) << depth;
    uint64_t path = trail & ~marker;  // the choices so far
    Build(first, begin, mid, depth + 1, path | (marker << 1), left);
    Build(first + 1, mid, end, depth + 1, path | marker | (marker << 1), right);
  }
};

uint16_t QuantiseLo(double v, double lo, double scale) {
  if (!(scale > 0.0)) return 0;
  return uint16_t(std::clamp(std::floor((v - lo) / scale), 0.0, 65535.0));
}
uint16_t QuantiseHi(double v, double lo, double scale) {
  if (!(scale > 0.0)) return 0;
  return uint16_t(std::clamp(std::ceil((v - lo) / scale), 0.0, 65535.0));
}

// A node as the device reads it. The cone is widened by the axis' octahedral rounding
// (< 1e-4 rad) before its cosine is rounded down, so the decoded cone still holds the lights.
LightBvhNode PackNode(const LightBuildBounds& b, uint32_t child, const LightTreeView& t) {
  LightBvhNode n{};
  n.phi = float(b.phi);
  n.child = child;
  n.axis = EncodeOctahedral(vec3(b.cone.w));
  double thetaO = std::acos(std::clamp(b.cone.cosTheta, -1.0, 1.0));
  double cosO = b.cone.cosTheta <= -1.0 ? -1.0 : std::cos(std::min(M_PI, thetaO + 1e-4));
  n.cosines = QuantiseCosDown(float(cosO)) | (QuantiseCosDown(float(b.cosTheta_e)) << 15) |
              (b.twoSided ? 1u << 30 : 0u) | (b.flat ? 1u << 31 : 0u);
  for (int a = 0; a < 3; ++a) {
    n.qlo[a] = QuantiseLo(b.lo[a], double(t.lo[a]), double(t.scale[a]));
    n.qhi[a] = QuantiseHi(b.hi[a], double(t.lo[a]), double(t.scale[a]));
  }
  return n;
}

}  // namespace

std::optional<LightBounds> LightBoundsOf(const Scene& scene, size_t index) {
  const Light& light = scene.lights[index];
  double power = index < scene.lightPower.size() ? scene.lightPower[index] : 0.0;
  if (!(power > 0.0) || !std::isfinite(power)) return std::nullopt;
  LightBounds b;
  b.cosTheta_e = 0.0f;  // area lights: the hemisphere over each normal
  auto extend = [&b](vec3 p) {
    b.lo = glm::min(b.lo, p);
    b.hi = glm::max(b.hi, p);
  };
  switch (light.type) {
    case LightType::kArea: {
      const SceneDesc& d = scene.desc;
      const PrimRef& prim = scene.prims[light.prim];
      double sides = light.twoSided ? 2.0 : 1.0;
      b.twoSided = light.twoSided != 0;
      b.phi = float(power / (double(kPi) * sides));  // radiance x area, per side
      if (prim.Type() == ShapeType::kSphere) {
        const Sphere& s = d.spheres[prim.Index()];
        extend(s.center - vec3(s.radius));
        extend(s.center + vec3(s.radius));
        b.phi = float(power / (4.0 * sides));  // radiance x pi r^2
        b.cosTheta_o = -1.0f;
        return b;
      }
      vec3 n;
      if (prim.Type() == ShapeType::kQuad) {
        const Quad& q = d.quads[prim.Index()];
        for (vec3 p : {q.origin, q.origin + q.u, q.origin + q.v, q.origin + q.u + q.v}) extend(p);
        n = glm::cross(q.u, q.v);
      } else {
        Triangle t = d.triangles[prim.Index()];
        if (light.instance >= 0) t = TriangleToWorld(scene.instances[size_t(light.instance)], t);
        for (vec3 p : {t.p0, t.p1, t.p2}) extend(p);
        n = glm::cross(t.p1 - t.p0, t.p2 - t.p0);
      }
      if (!(glm::length(n) > 0.0f)) return std::nullopt;
      b.w = glm::normalize(n);
      b.cosTheta_o = 1.0f;
      b.flat = !b.twoSided;
      return b;
    }
    case LightType::kPoint:
    case LightType::kSpot: {
      extend(light.position);
      b.phi = Luminance(light.intensity);
      b.cosTheta_o = -1.0f;
      if (light.type == LightType::kSpot) {
        // Full intensity within the inner cone, none past the outer (Light::SpotFalloff).
        double s = light.spotScale, o = light.spotOffset;
        double cosOuter = std::clamp(-o / s, -1.0, 1.0);
        double cosInner = std::clamp((1.0 - o) / s, -1.0, 1.0);
        b.w = light.direction;
        b.cosTheta_o = float(cosInner);
        b.cosTheta_e = float(std::cos(std::max(0.0, std::acos(cosOuter) - std::acos(cosInner))));
      }
      if (!(b.phi > 0.0f)) return std::nullopt;
      return b;
    }
    default: return std::nullopt;  // at infinity: chosen beside the tree
  }
}

void BuildLightBvh(Scene& scene) {
  auto t0 = std::chrono::steady_clock::now();
  scene.lightNodes.clear();
  scene.lightTrails.clear();
  scene.lightTree = LightTreeView{};
  size_t bounded = 0;
  while (bounded < scene.lights.size() && scene.lights[bounded].type != LightType::kDirectional &&
         scene.lights[bounded].type != LightType::kBackground &&
         scene.lights[bounded].type != LightType::kEnvironmentMap)
    ++bounded;
  scene.lightTree.boundedCount = uint32_t(bounded);
  std::vector<LightItem> items;
  for (size_t i = 0; i < bounded; ++i) {
    std::optional<LightBounds> b = LightBoundsOf(scene, i);
    if (!b) continue;
    LightBuildBounds bb = ToBuild(*b);
    items.push_back(LightItem{bb, 0.5 * (bb.lo + bb.hi), uint32_t(i)});
  }
  if (items.empty()) return;
  scene.lightTrails.assign(bounded, 0);
  LightTreeBuilder builder{items, {}, {}, scene.lightTrails};
  // Node 1 is padding (never reached), so every pair of siblings starts at an even index: one
  // 64-byte line where the array is 64-byte aligned (device allocations are).
  builder.bounds.resize(2);
  builder.child.resize(2);
  LightBuildBounds all;
  for (const LightItem& it : items) all.Add(it.b);
  builder.Build(0, 0, items.size(), 0, 1, all);
  builder.bounds[1] = builder.bounds[0];
  builder.child[1] = builder.child[0];
  // The grid: the root's box, in 65535 steps per axis.
  const LightBuildBounds& root = builder.bounds[0];
  LightTreeView& t = scene.lightTree;
  t.lo = vec3(root.lo);
  t.scale = vec3((root.hi - root.lo) / 65535.0);
  // Float rounding of lo + 65535 * scale may fall short of hi: one ulp more per axis.
  for (int a = 0; a < 3; ++a) {
    if (t.scale[a] > 0.0f && double(t.lo[a]) + 65535.0 * double(t.scale[a]) < root.hi[a])
      t.scale[a] = std::nextafter(t.scale[a], INFINITY);
    if (double(t.lo[a]) > root.lo[a]) t.lo[a] = std::nextafter(t.lo[a], -INFINITY);
  }
  t.nodeCount = uint32_t(builder.bounds.size());
  scene.lightNodes.resize(builder.bounds.size());
  for (size_t i = 0; i < builder.bounds.size(); ++i)
    scene.lightNodes[i] = PackNode(builder.bounds[i], builder.child[i], t);
  scene.lightBvhBuildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

LightSampler ChooseLightSampler(LightSampler requested, const Scene& scene) {
  if (requested != LightSampler::kAuto) return requested;
  size_t inTree = scene.lightTree.nodeCount / 2;  // one light per leaf, one padding node
  return inTree >= kAutoBvhMinLights ? LightSampler::kBvh : LightSampler::kPower;
}

const char* LightSamplerName(LightSampler s) {
  switch (s) {
    case LightSampler::kUniform: return "uniform";
    case LightSampler::kPower: return "power";
    case LightSampler::kBvh: return "bvh";
    case LightSampler::kAuto: return "auto";
  }
  return "?";
}

}  // namespace pt
