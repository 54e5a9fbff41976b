#include "src/scene/instances.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "src/geometry/aabb.h"
#include "src/geometry/shapes.h"
#include "src/lights/light_sample.h"
#include "src/materials/emission.h"
#include "src/lights/light_table.h"
#include "src/scene/scene_bvh.h"

namespace pt {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

Affine3 ToAffine(const glm::dmat4& m) {  // glm is column-major: m[column][row]
  Affine3 a;
  a.r0 = vec4(float(m[0][0]), float(m[1][0]), float(m[2][0]), float(m[3][0]));
  a.r1 = vec4(float(m[0][1]), float(m[1][1]), float(m[2][1]), float(m[3][1]));
  a.r2 = vec4(float(m[0][2]), float(m[1][2]), float(m[2][2]), float(m[3][2]));
  return a;
}

glm::dmat4 FromAffine(const Affine3& a) {
  glm::dmat4 m(1.0);
  const vec4 rows[3] = {a.r0, a.r1, a.r2};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) m[c][r] = double(rows[r][c]);
  }
  return m;
}

// The placement's device record. toWorld is rounded to float first and toObject is the exact
// inverse of that float matrix (then rounded): the world surface is the float toWorld's image of
// the mesh, and ObjectRay's error bound covers toObject's rounding (src/geometry/instance.h).
Instance MakeInstance(const Scene& scene, uint32_t mesh, const glm::dmat4& toWorld,
                      int32_t material) {
  Instance inst{};
  inst.toWorld = ToAffine(toWorld);
  glm::dmat4 rounded = FromAffine(inst.toWorld);
  inst.toObject = ToAffine(glm::inverse(rounded));
  const Scene::MeshBvh& b = scene.meshBvhs[mesh];
  inst.nodeOffset = b.nodeOffset;
  inst.primOffset = b.primOffset;
  inst.mesh = mesh;
  inst.material = material;
  inst.lightBase = -1;
  inst.firstTriangle = mesh < scene.desc.meshes.size() ? scene.desc.meshes[mesh].firstTriangle : 0;
  inst.flags = 0;
  if (rounded == glm::dmat4(1.0)) inst.flags |= kInstanceIdentity;
  if (glm::determinant(glm::dmat3(rounded)) < 0.0) inst.flags |= kInstanceMirrored;
  return inst;
}

// World bounds of an instance: the mesh's object box through the float toWorld, in double
// (exact corners, rounded outwards); an identity placement's is the object box itself.
Aabb InstanceWorldBounds(const Scene& scene, const Instance& inst) {
  const Scene::MeshBvh& b = scene.meshBvhs[inst.mesh];
  if (inst.flags & kInstanceIdentity) {
    Aabb box;
    box.lo = b.lo;
    box.hi = b.hi;
    return box;
  }
  glm::dmat4 m = FromAffine(inst.toWorld);
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (int corner = 0; corner < 8; ++corner) {
    glm::dvec3 p((corner & 1) ? b.hi.x : b.lo.x, (corner & 2) ? b.hi.y : b.lo.y,
                 (corner & 4) ? b.hi.z : b.lo.z);
    glm::dvec3 w = glm::dvec3(m * glm::dvec4(p, 1.0));
    lo = glm::min(lo, w);
    hi = glm::max(hi, w);
  }
  Aabb box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = std::nextafter(float(lo[a]), -INFINITY);
    box.hi[a] = std::nextafter(float(hi[a]), INFINITY);
  }
  return box;
}

// The object-space ray of ObjectRay is the world ray's preimage only up to rounding, so a ray
// that grazes an instance's box in object space could miss its world box by as much: each top-
// level box is grown by a relative margin far above that rounding (~1e-6 of its size and place).
Aabb Padded(const Aabb& box) {
  Aabb out = box;
  for (int a = 0; a < 3; ++a) {
    float reach = std::max(std::fabs(box.lo[a]), std::fabs(box.hi[a])) + (box.hi[a] - box.lo[a]);
    float pad = Gamma(16) * reach;
    out.lo[a] = box.lo[a] - pad;
    out.hi[a] = box.hi[a] + pad;
  }
  return out;
}

// One bottom level over `prims` appended to the scene's nodes and prims.
Scene::MeshBvh AppendBottomLevel(Scene& scene, const std::vector<PrimRef>& prims,
                                 const std::vector<Aabb>& bounds) {
  LayoutBvh bvh = BuildLayoutBvh(scene.desc, prims, bounds, scene.bvhOptions);
  Scene::MeshBvh m;
  m.nodeOffset = scene.NodeCount();
  m.primOffset = uint32_t(scene.prims.size());
  m.nodeCount = uint32_t(bvh.nodes.size() + bvh.wideNodes.size());
  scene.nodes.insert(scene.nodes.end(), bvh.nodes.begin(), bvh.nodes.end());
  scene.wideNodes.insert(scene.wideNodes.end(), bvh.wideNodes.begin(), bvh.wideNodes.end());
  for (uint32_t i : bvh.order) scene.prims.push_back(prims[i]);
  m.primCount = uint32_t(bvh.order.size());
  Aabb box;
  for (const Aabb& b : bounds) box.Extend(b);
  m.lo = box.lo;
  m.hi = box.hi;
  scene.bvhDepth = std::max(scene.bvhDepth, bvh.depth);
  return m;
}

// Mesh ranges inside the triangles and disjoint, instances naming meshes and materials that
// exist, transforms usable: what the loaders guarantee, checked once more for other callers.
std::vector<bool> CheckMeshes(const SceneDesc& d) {
  std::vector<bool> inMesh(d.triangles.size(), false);
  for (const MeshDesc& m : d.meshes) {
    if (m.triangleCount == 0 || uint64_t(m.firstTriangle) + m.triangleCount > d.triangles.size())
      throw std::runtime_error("internal: mesh \"" + m.name + "\" has no triangles or is out of range");
    for (uint32_t i = m.firstTriangle; i < m.firstTriangle + m.triangleCount; ++i) {
      if (inMesh[i]) throw std::runtime_error("internal: meshes share triangle " + std::to_string(i));
      inMesh[i] = true;
    }
  }
  std::string why;
  for (const InstanceDesc& inst : d.instances) {
    if (inst.mesh >= d.meshes.size()) throw std::runtime_error("internal: instance of no mesh");
    if (inst.material >= int64_t(d.materials.size()))
      throw std::runtime_error("internal: instance material out of range");
    if (!ValidInstanceTransform(inst.toWorld, &why))
      throw std::runtime_error("an instance of \"" + d.meshes[inst.mesh].name + "\": " + why);
  }
  return inMesh;
}

// Top level over every instance; the bounding sphere from the exact (unpadded) boxes, so an
// identity-only scene has the flat scene's sphere.
void BuildTopLevel(Scene& scene) {
  auto t0 = Clock::now();
  std::vector<Aabb> boxes(scene.instances.size());
  Aabb world;
  for (size_t i = 0; i < boxes.size(); ++i) {
    Aabb exact = InstanceWorldBounds(scene, scene.instances[i]);
    world.Extend(exact);
    boxes[i] = Padded(exact);
  }
  BvhBuildOptions options = scene.bvhOptions;
  options.builder = BvhBuilder::kSah;  // spatial splits would visit an instance twice
  options.maxLeafSize = options.topLevelLeafSize;
  LayoutBvh bvh = BuildLayoutBvh(scene.desc, {}, boxes, options);
  scene.tlasNodes = std::move(bvh.nodes);
  scene.tlasWideNodes = std::move(bvh.wideNodes);
  scene.instanceOrder = std::move(bvh.order);
  scene.bvhSahCost = bvh.sahCost;
  if (!world.IsEmpty()) {
    scene.sceneCenter = 0.5f * (world.lo + world.hi);
    scene.sceneRadius = std::max(1e-6f, 0.5f * glm::length(world.hi - world.lo));
  }
  scene.tlasBuildMs = MsSince(t0);
}

}  // namespace

bool ValidInstanceTransform(const glm::dmat4& m, std::string* why) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (std::isfinite(m[c][r])) continue;
      *why = "the transform is not finite";
      return false;
    }
  }
  if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) {
    *why = "the transform's last row is not 0 0 0 1";
    return false;
  }
  // The float matrix is what renders: it must be finite and invertible too.
  glm::dmat4 rounded = FromAffine(ToAffine(m));
  for (int c = 0; c < 4; ++c) {
    if (std::isfinite(rounded[c][0] + rounded[c][1] + rounded[c][2])) continue;
    *why = "the transform does not fit in single precision";
    return false;
  }
  double det = glm::determinant(glm::dmat3(rounded));
  glm::dmat4 inverse = glm::inverse(rounded);
  bool invertible = std::fabs(det) > 0.0 && std::isfinite(det);
  for (int c = 0; c < 4 && invertible; ++c)
    invertible = std::isfinite(float(inverse[c][0])) && std::isfinite(float(inverse[c][1])) &&
                 std::isfinite(float(inverse[c][2]));
  if (!invertible) {
    *why = "the transform is singular or nearly so (determinant " + std::to_string(det) + ")";
    return false;
  }
  return true;
}

void BuildInstancedScene(Scene& scene) {
  auto t0 = Clock::now();
  const SceneDesc& d = scene.desc;
  std::vector<bool> inMesh = CheckMeshes(d);
  scene.bvhDepth = 0;

  // The world's primitives first, so that prims [0, worldPrimCount) are they.
  std::vector<PrimRef> prims;
  std::vector<Aabb> bounds;
  CollectPrimitives(d, prims, bounds, inMesh);
  Scene::MeshBvh world;
  if (!prims.empty()) world = AppendBottomLevel(scene, prims, bounds);
  scene.worldPrimCount = world.primCount;

  for (const MeshDesc& m : d.meshes) {
    prims.clear();
    bounds.clear();
    for (uint32_t i = m.firstTriangle; i < m.firstTriangle + m.triangleCount; ++i) {
      uint32_t material = d.triangleMaterials[i];
      bool test = material < d.materials.size() && NeedsHitTest(d.materials[material]);
      prims.push_back(PrimRef{PrimRef::Pack(ShapeType::kTriangle, i, test), material, -1});
      bounds.push_back(TriangleBounds(d.triangles[i]));
    }
    scene.meshBvhs.push_back(AppendBottomLevel(scene, prims, bounds));
  }
  if (world.primCount > 0) scene.meshBvhs.push_back(world);
  PackTriangles(scene);

  for (const InstanceDesc& i : d.instances)
    scene.instances.push_back(MakeInstance(scene, i.mesh, i.toWorld, i.material));
  if (world.primCount > 0) {
    scene.instances.push_back(
        MakeInstance(scene, uint32_t(scene.meshBvhs.size() - 1), glm::dmat4(1.0), -1));
  }
  BuildTopLevel(scene);
  scene.bvhBuildMs = MsSince(t0);
  BuildLightTable(scene);
}

Aabb InstancedWorldBounds(const Scene& scene) {
  Aabb world;
  for (const Instance& inst : scene.instances) world.Extend(InstanceWorldBounds(scene, inst));
  return world;
}

void UpdateInstanceTransform(Scene& scene, size_t index, const glm::dmat4& toWorld) {
  if (index >= scene.desc.instances.size()) {
    throw std::invalid_argument("instance " + std::to_string(index) + " does not exist (" +
                                std::to_string(scene.desc.instances.size()) + " instances)");
  }
  std::string why;
  if (!ValidInstanceTransform(toWorld, &why)) throw std::invalid_argument(why);
  InstanceDesc& desc = scene.desc.instances[index];
  desc.toWorld = toWorld;
  int32_t lightBase = scene.instances[index].lightBase;
  scene.instances[index] = MakeInstance(scene, desc.mesh, toWorld, desc.material);
  scene.instances[index].lightBase = lightBase;
  if (lightBase < 0) return;
  // Its lights' power follows its scale: recomputed here, so that RebuildTopLevel need not
  // recompute every instance's (millions of lights where emissive meshes are placed often).
  size_t end = size_t(lightBase);
  while (end < scene.lights.size() && scene.lights[end].instance == int32_t(index)) ++end;
  UpdateLightPowers(scene, size_t(lightBase), end);
}

void RebuildTopLevel(Scene& scene) {
  if (!scene.HasInstances()) return;
  BuildTopLevel(scene);
  UpdateLightDistribution(scene);
}

double InstanceLightArea(const Scene& scene, const Light& light) {
  const Instance& inst = scene.instances[size_t(light.instance)];
  const Triangle& t = scene.desc.triangles[scene.prims[light.prim].Index()];
  return TriangleArea(TriangleToWorld(inst, t));
}

namespace {

// Lights past this many would take gigabytes (a light per placed emitting triangle).
constexpr size_t kMaxLights = size_t(1) << 26;

Light InstanceAreaLight(uint32_t prim, const Material& m, uint32_t instance) {
  Light light;
  light.type = LightType::kArea;
  light.prim = prim;
  light.radiance = m.radiance;
  light.twoSided = m.twoSided;
  light.instance = int32_t(instance);
  return light;
}

// A mesh's primitives (global prim indices) in triangle order: spatial splits may put a
// triangle in several leaves, so copies sit next to each other.
std::vector<uint32_t> PrimsInTriangleOrder(const Scene& scene, const Scene::MeshBvh& b) {
  std::vector<uint32_t> order(b.primCount);
  for (uint32_t k = 0; k < b.primCount; ++k) order[k] = b.primOffset + k;
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t c) {
    return scene.prims[a].tagIndex < scene.prims[c].tagIndex;
  });
  return order;
}

// Ranks each mesh's own emitters (PrimRef::light, copies of a triangle sharing one) and returns
// the prim of each rank.
std::vector<uint32_t> RankEmitters(Scene& scene, const std::vector<uint32_t>& inOrder) {
  std::vector<uint32_t> emitters;
  for (size_t k = 0; k < inOrder.size(); ++k) {
    PrimRef& ref = scene.prims[inOrder[k]];
    ref.light = -1;
    if (!MaterialEmits(scene.desc.materials[ref.material])) continue;
    if (!emitters.empty() && scene.prims[emitters.back()].tagIndex == ref.tagIndex) {
      ref.light = scene.prims[emitters.back()].light;
      continue;
    }
    ref.light = int32_t(emitters.size());
    emitters.push_back(inOrder[k]);
  }
  return emitters;
}

}  // namespace

void AppendInstanceLights(Scene& scene) {
  const SceneDesc& d = scene.desc;
  std::vector<std::vector<uint32_t>> inOrder(d.meshes.size()), emitters(d.meshes.size());
  for (size_t m = 0; m < d.meshes.size(); ++m) {
    inOrder[m] = PrimsInTriangleOrder(scene, scene.meshBvhs[m]);
    emitters[m] = RankEmitters(scene, inOrder[m]);
  }
  for (size_t i = 0; i < d.instances.size(); ++i) {
    const InstanceDesc& desc = d.instances[i];
    size_t before = scene.lights.size();
    if (desc.material >= 0 && MaterialEmits(d.materials[desc.material])) {
      // Every triangle emits, in triangle order (the first copy of each).
      const std::vector<uint32_t>& prims = inOrder[desc.mesh];
      for (size_t k = 0; k < prims.size(); ++k) {
        if (k > 0 && scene.prims[prims[k]].tagIndex == scene.prims[prims[k - 1]].tagIndex) continue;
        scene.lights.push_back(
            InstanceAreaLight(prims[k], d.materials[desc.material], uint32_t(i)));
      }
    } else if (desc.material < 0) {
      for (uint32_t prim : emitters[desc.mesh])
        scene.lights.push_back(
            InstanceAreaLight(prim, d.materials[scene.prims[prim].material], uint32_t(i)));
    }
    scene.instances[i].lightBase = scene.lights.size() > before ? int32_t(before) : -1;
    if (scene.lights.size() > kMaxLights) {
      throw std::runtime_error(
          "instanced emitters make more than " + std::to_string(kMaxLights) +
          " area lights (one per placed emitting triangle): place fewer emissive instances");
    }
  }
  if (scene.instances.size() > d.instances.size()) scene.instances.back().lightBase = 0;
}

uint64_t Scene::PlacedTriangleCount() const {
  if (!HasInstances()) return desc.triangles.size();
  uint64_t placed = desc.triangles.size();
  for (const MeshDesc& m : desc.meshes) placed -= m.triangleCount;
  for (const InstanceDesc& i : desc.instances) placed += desc.meshes[i.mesh].triangleCount;
  return placed;
}

}  // namespace pt

namespace pt {

SceneDesc FlattenInstances(SceneDesc d) {
  if (d.meshes.empty()) return d;
  std::vector<bool> inMesh = CheckMeshes(d);
  SceneDesc out = d;
  out.meshes.clear();
  out.instances.clear();
  out.triangles.clear();
  out.triangleNormals.clear();
  out.triangleUvs.clear();
  out.triangleMaterials.clear();
  bool uvs = !d.triangleUvs.empty();
  auto copy = [&](uint32_t i, const glm::dmat4& m, bool mirrored, int32_t material) {
    // As MeshSink places a mesh: vertices 1 and 2 trade places under a mirroring transform.
    const int k[3] = {0, mirrored ? 2 : 1, mirrored ? 1 : 2};
    const vec3 p[3] = {d.triangles[i].p0, d.triangles[i].p1, d.triangles[i].p2};
    const vec3 n[3] = {d.triangleNormals[i].n0, d.triangleNormals[i].n1, d.triangleNormals[i].n2};
    glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(m)));
    vec3 w[3], wn[3];
    for (int j = 0; j < 3; ++j) {
      w[j] = vec3(m * glm::dvec4(glm::dvec3(p[k[j]]), 1.0));
      glm::dvec3 dn = normalMatrix * glm::dvec3(n[k[j]]);
      double len = glm::length(dn);
      wn[j] = len > 0.0 ? vec3(dn / len) : vec3(0.0f);  // no normals stay no normals
    }
    out.triangles.push_back(Triangle{w[0], w[1], w[2]});
    out.triangleNormals.push_back(TriangleNormals{wn[0], wn[1], wn[2]});
    out.triangleMaterials.push_back(material >= 0 ? uint32_t(material) : d.triangleMaterials[i]);
    if (!uvs) return;
    const vec2 uv[3] = {d.triangleUvs[i].uv0, d.triangleUvs[i].uv1, d.triangleUvs[i].uv2};
    out.triangleUvs.push_back(TriangleUvs{uv[k[0]], uv[k[1]], uv[k[2]]});
  };
  // The float matrix an instance renders with (Instance::toWorld), applied in double.
  for (const InstanceDesc& inst : d.instances) {
    glm::dmat4 m = FromAffine(ToAffine(inst.toWorld));
    bool mirrored = glm::determinant(glm::dmat3(m)) < 0.0;
    const MeshDesc& mesh = d.meshes[inst.mesh];
    for (uint32_t i = mesh.firstTriangle; i < mesh.firstTriangle + mesh.triangleCount; ++i)
      copy(i, m, mirrored, inst.material);
  }
  for (uint32_t i = 0; i < d.triangles.size(); ++i) {
    if (!inMesh[i]) copy(i, glm::dmat4(1.0), false, -1);
  }
  return out;
}

}  // namespace pt
