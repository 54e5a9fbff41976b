// From loaded shapes to a renderable scene: BVH over every primitive, primitives in leaf
// order, the light table, and the camera basis.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>

#include "src/core/parallel_ranges.h"
#include "src/core/prefault.h"
#include "src/geometry/aabb.h"
#include "src/geometry/bvh.h"
#include "src/geometry/bvh_wide.h"
#include "src/geometry/lbvh_build.h"
#include "src/geometry/shapes.h"
#include "src/lights/light_table.h"
#include "src/materials/surface_attributes.h"
#include "src/scene/auto_camera.h"
#include "src/scene/instances.h"
#include "src/scene/scene.h"
#include "src/scene/scene_bvh.h"

namespace pt {

bool NeedsHitTest(const Material& m) {
  return (m.flags & (kMaterialAlphaMask | kMaterialAlphaBlend | kMaterialCullBack)) != 0;
}

namespace {

// Items per thread below which the per-primitive loops stay on one thread.
constexpr size_t kMinPrimsPerThread = 1 << 16;

PrimRef MakePrimRef(const SceneDesc& d, ShapeType type, uint32_t index, uint32_t material) {
  bool test = material < d.materials.size() && NeedsHitTest(d.materials[material]);
  return PrimRef{PrimRef::Pack(type, index, test), material, -1};
}

}  // namespace

void CollectPrimitives(const SceneDesc& d, std::vector<PrimRef>& prims, std::vector<Aabb>& bounds,
                       const std::vector<bool>& skipTriangle, int threads) {
  auto add = [&](ShapeType type, uint32_t index, uint32_t material, const Aabb& box) {
    prims.push_back(MakePrimRef(d, type, index, material));
    bounds.push_back(box);
  };
  size_t shapes = d.triangles.size() + d.quads.size() + d.spheres.size();
  ReserveOnThreads(prims, prims.size() + shapes, threads);
  ReserveOnThreads(bounds, bounds.size() + shapes, threads);
  if (skipTriangle.empty()) {  // every triangle: filled in place, a big mesh on every core
    size_t n = d.triangles.size(), base = prims.size();
    prims.resize(base + n);
    bounds.resize(base + n);
    ForRangesOnThreads(n, threads, kMinPrimsPerThread, [&](size_t lo, size_t hi) {
      for (size_t i = lo; i < hi; ++i) {
        prims[base + i] = MakePrimRef(d, ShapeType::kTriangle, uint32_t(i), d.triangleMaterials[i]);
        bounds[base + i] = TriangleBounds(d.triangles[i]);
      }
    });
  } else {
    for (uint32_t i = 0; i < d.triangles.size(); ++i) {
      if (i < skipTriangle.size() && skipTriangle[i]) continue;
      add(ShapeType::kTriangle, i, d.triangleMaterials[i], TriangleBounds(d.triangles[i]));
    }
  }
  for (uint32_t i = 0; i < d.quads.size(); ++i)
    add(ShapeType::kQuad, i, d.quadMaterials[i], QuadBounds(d.quads[i]));
  for (uint32_t i = 0; i < d.spheres.size(); ++i)
    add(ShapeType::kSphere, i, d.sphereMaterials[i], SphereBounds(d.spheres[i]));
}

Camera MakeCamera(const CameraDesc& desc, int width, int height) {
  return MakeCamera(desc, width, height, 1);
}

Camera MakeCamera(const CameraDesc& desc, int width, int height, int spp) {
  Camera c;
  c.position = desc.position;
  c.forward = glm::normalize(desc.lookAt - desc.position);
  c.right = glm::normalize(glm::cross(c.forward, desc.up));
  c.up = glm::cross(c.right, c.forward);
  c.tanHalfFovY = std::tan(glm::radians(desc.fovY) * 0.5f);
  c.aspect = float(width) / float(height);
  c.pixelSpread = 2.0f * c.tanHalfFovY / float(height);
  c.textureFootprint = TextureFootprintScale(spp);
  c.apertureRadius = desc.apertureRadius;
  c.focusDistance = desc.focusDistance > 0.0f ? desc.focusDistance
                                              : glm::length(desc.lookAt - desc.position);
  return c;
}

namespace {

// Bounds of the part of a convex polygon inside `box` (Sutherland-Hodgman in double, rounded
// outwards to float and clamped to the box): what spatial splits need.
Aabb ClipPolygon(const glm::dvec3* in, int n, const Aabb& box) {
  glm::dvec3 a[16], b[16];
  for (int i = 0; i < n; ++i) a[i] = in[i];
  for (int plane = 0; plane < 6 && n > 0; ++plane) {
    int axis = plane % 3;
    bool upper = plane >= 3;
    double bound = upper ? box.hi[axis] : box.lo[axis];
    auto inside = [&](const glm::dvec3& p) { return upper ? p[axis] <= bound : p[axis] >= bound; };
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const glm::dvec3& p = a[i];
      const glm::dvec3& q = a[(i + 1) % n];
      if (inside(p)) b[m++] = p;
      if (inside(p) != inside(q) && m < 15) {
        double t = (bound - p[axis]) / (q[axis] - p[axis]);
        glm::dvec3 x = p + t * (q - p);
        x[axis] = bound;
        b[m++] = x;
      }
    }
    n = m;
    for (int i = 0; i < n; ++i) a[i] = b[i];
  }
  Aabb out;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      float lo = std::nextafter(float(a[i][k]), -kInfinity), hi = std::nextafter(float(a[i][k]), kInfinity);
      out.lo[k] = std::min(out.lo[k], lo);
      out.hi[k] = std::max(out.hi[k], hi);
    }
  }
  if (out.IsEmpty()) return out;
  return Aabb{glm::max(out.lo, box.lo), glm::min(out.hi, box.hi)};
}

PrimClipper MakeClipper(const SceneDesc& d, const std::vector<PrimRef>& prims,
                        const std::vector<Aabb>& bounds) {
  return [&d, &prims, &bounds](uint32_t i, const Aabb& box) {
    const PrimRef& ref = prims[i];
    if (ref.Type() == ShapeType::kTriangle) {
      const Triangle& t = d.triangles[ref.Index()];
      glm::dvec3 v[3] = {glm::dvec3(t.p0), glm::dvec3(t.p1), glm::dvec3(t.p2)};
      return ClipPolygon(v, 3, box);
    }
    // Quads and spheres: their padded bounds cut by the box (valid, if weaker).
    const Aabb& b = bounds[i];
    Aabb out{glm::max(b.lo, box.lo), glm::min(b.hi, box.hi)};
    return out.IsEmpty() ? Aabb() : out;
  };
}

}  // namespace

const char* BvhBuilderName(BvhBuilder b) {
  switch (b) {
    case BvhBuilder::kSbvh: return "sbvh";
    case BvhBuilder::kLbvh: return "gpu";
    case BvhBuilder::kAuto: return "auto";
    default: return "sah";
  }
}
const char* BvhLayoutName(BvhLayout l) { return l == BvhLayout::kWide ? "wide" : "binary"; }

// The binary tree the layout is made from: the linear BVH (on the options' device; else, asked
// for explicitly, on the host's threads, the same bodies) or the SAH builder's. auto takes the
// linear BVH only for a mesh of kLbvhAutoPrims+ primitives that a device built.
static BvhBuildResult BuildBinaryTree(const std::vector<Aabb>& bounds,
                                      const BvhBuildOptions& options, const PrimClipper& clip) {
  BvhBuildResult bvh;
  const bool lbvh = options.builder == BvhBuilder::kLbvh ||
                    (options.builder == BvhBuilder::kAuto && bounds.size() >= kLbvhAutoPrims);
  if (lbvh && options.deviceLbvh && options.deviceLbvh(bounds, &bvh)) return bvh;
  if (options.builder == BvhBuilder::kLbvh) return BuildLbvhHost(bounds, options.threads);
  return BuildBvh(bounds, options, kBvhMaxDepth, clip);
}

LayoutBvh BuildLayoutBvh(const SceneDesc& d, const std::vector<PrimRef>& unordered,
                         const std::vector<Aabb>& bounds, const BvhBuildOptions& options) {
  PrimClipper clip;
  if (options.builder == BvhBuilder::kSbvh) clip = MakeClipper(d, unordered, bounds);
  LayoutBvh out;
  if (options.layout == BvhLayout::kWide) {
    // The linear BVH collapsed where it was built (the GPU), when it can be.
    WideBvhResult wide;
    const bool lbvh = options.builder == BvhBuilder::kLbvh ||
                      (options.builder == BvhBuilder::kAuto && bounds.size() >= kLbvhAutoPrims);
    if (!(lbvh && options.maxLeafSize >= 3 && options.deviceWideLbvh &&
          options.deviceWideLbvh(bounds, &wide))) {
      // A full binary tree: the collapse chooses the leaves (of at most 3 primitives) itself.
      BvhBuildOptions binary = options;
      binary.maxLeafSize = 1;
      BvhBuildResult bvh = BuildBinaryTree(bounds, binary, clip);
      wide = CollapseToWide(bvh, bounds, options.threads, options.maxLeafSize);
    }
    out.wideNodes = std::move(wide.nodes);
    out.sahCost = wide.sahCost;
    out.depth = wide.maxDepth;
    out.order = std::move(wide.primOrder);
    return out;
  }
  BvhBuildResult bvh = BuildBinaryTree(bounds, options, clip);
  out.nodes = std::move(bvh.nodes);
  out.sahCost = BinarySahCost(out.nodes);
  out.depth = bvh.maxDepth;
  out.order = std::move(bvh.primOrder);
  return out;
}

void PackTriangles(Scene& scene, int threads) {
  const SceneDesc& d = scene.desc;
  ReserveOnThreads(scene.packedTriangles, scene.prims.size(), threads);
  scene.packedTriangles.resize(scene.prims.size());
  ForRangesOnThreads(scene.prims.size(), threads, kMinPrimsPerThread, [&](size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i) {
      const PrimRef& ref = scene.prims[i];
      PackedTriangle& p = scene.packedTriangles[i];
      p = PackedTriangle{};
      p.tag = ref.tagIndex;
      p.material = ref.material;
      if (ref.Type() != ShapeType::kTriangle) continue;
      const Triangle& t = d.triangles[ref.Index()];
      p.p0 = t.p0;
      p.p1 = t.p1;
      p.p2 = t.p2;
    }
  });
}

namespace {

// The union of many boxes, a range per thread (min and max: the same in any order).
Aabb UnionOnThreads(const std::vector<Aabb>& boxes, int threads) {
  Aabb world;
  std::mutex mutex;
  ForRangesOnThreads(boxes.size(), threads, kMinPrimsPerThread, [&](size_t lo, size_t hi) {
    Aabb part;
    for (size_t i = lo; i < hi; ++i) part = Union(part, boxes[i]);
    std::lock_guard<std::mutex> lock(mutex);
    world = Union(world, part);
  });
  return world;
}

// The flat scene (no instances): one BVH over every primitive. Returns the world's bounds.
Aabb BuildFlatScene(Scene& scene, const BvhBuildOptions& options) {
  const SceneDesc& d = scene.desc;
  std::vector<PrimRef> unordered;
  std::vector<Aabb> bounds;
  CollectPrimitives(d, unordered, bounds, {}, options.threads);
  Aabb world = UnionOnThreads(bounds, options.threads);

  auto t0 = std::chrono::steady_clock::now();
  LayoutBvh bvh = BuildLayoutBvh(d, unordered, bounds, options);
  scene.bvhBuildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  scene.nodes = std::move(bvh.nodes);
  scene.wideNodes = std::move(bvh.wideNodes);
  scene.bvhSahCost = bvh.sahCost;
  scene.bvhDepth = bvh.depth;
  ReserveOnThreads(scene.prims, bvh.order.size(), options.threads);
  scene.prims.resize(bvh.order.size());
  ForRangesOnThreads(bvh.order.size(), options.threads, kMinPrimsPerThread,
                     [&](size_t lo, size_t hi) {
                       for (size_t i = lo; i < hi; ++i) scene.prims[i] = unordered[bvh.order[i]];
                     });
  scene.worldPrimCount = uint32_t(scene.prims.size());
  PackTriangles(scene, options.threads);

  if (!bounds.empty()) {
    scene.sceneCenter = 0.5f * (world.lo + world.hi);
    scene.sceneRadius = std::max(1e-6f, 0.5f * glm::length(world.hi - world.lo));
  }
  BuildLightTable(scene);
  return world;
}

}  // namespace

Scene BuildScene(SceneDesc desc, const BvhBuildOptions& options) {
  // The loaders check their own files; this covers scenes put together from several (includes).
  if (desc.materials.size() > kMaxMaterials)
    throw std::runtime_error("the scene has " + std::to_string(desc.materials.size()) +
                             " materials; at most " + std::to_string(kMaxMaterials) +
                             " are supported");
  Scene scene;
  scene.desc = std::move(desc);
  const SceneDesc& d = scene.desc;
  if (d.triangleNormals.size() != d.triangles.size())
    throw std::runtime_error("internal: triangle normals do not match triangles");
  scene.bvhLayout = options.layout;
  scene.bvhOptions = options;
  Aabb world;
  if (!d.meshes.empty()) {  // instances: two levels (src/scene/instances.cpp)
    BuildInstancedScene(scene);
    world = InstancedWorldBounds(scene);
  } else {
    world = BuildFlatScene(scene, options);
  }
  if (d.camera.autoFrame) {  // the image's size is final here (after command-line overrides)
    float aspect = float(d.render.width) / float(std::max(1, d.render.height));
    scene.desc.camera = FrameBounds(world.lo, world.hi, aspect, d.camera.fovY);
  }
  scene.camera = MakeCamera(d.camera, d.render.width, d.render.height, d.render.spp);
  return scene;
}

SceneView HostSceneView(const Scene& scene) {
  const Scene& s = scene;
  const SceneDesc& d = scene.desc;
  SceneView v;
#define PT_SCENE_ARRAY_HOST(Type, name, host) v.name = (host).empty() ? nullptr : (host).data();
  PT_SCENE_ARRAYS(PT_SCENE_ARRAY_HOST)
#undef PT_SCENE_ARRAY_HOST
  v.nodeCount = scene.NodeCount();
  v.instanceCount = uint32_t(scene.instances.size());
  v.tlasNodeCount = scene.TlasNodeCount();
  v.bvhLayout = scene.bvhLayout;
  v.primCount = uint32_t(scene.prims.size());
  v.materialCount = uint32_t(d.materials.size());
  v.lightCount = uint32_t(scene.lights.size());
  v.backgroundLight = scene.backgroundLight;
  v.distantLightCount = uint32_t(scene.distantLights.size());
  v.env = scene.env;
  v.lightTree = scene.lightTree;
  v.background = d.background * d.environment.strength;
  v.sceneCenter = scene.sceneCenter;
  v.sceneRadius = scene.sceneRadius;
  v.camera = scene.camera;
  return v;
}

}  // namespace pt
