#include "src/server/scene_objects.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "src/geometry/traverse.h"
#include "src/integrator/stages/generate.h"
#include "src/server/scene_document.h"

namespace pt {
namespace {

// The index of the range [first, first + count) that holds i, or -1.
template <typename First, typename Count>
int FindRange(const std::vector<ObjectShapes>& shapes, uint32_t i, First first, Count count) {
  auto it = std::upper_bound(shapes.begin(), shapes.end(), i,
                             [&](uint32_t v, const ObjectShapes& s) { return v < first(s); });
  while (it != shapes.begin()) {
    --it;
    if (count(*it) > 0) return i < first(*it) + count(*it) ? int(it - shapes.begin()) : -1;
  }
  return -1;
}

template <typename T>
void Replace(std::vector<T>& all, uint32_t first, const std::vector<T>& with) {
  std::copy(with.begin(), with.end(), all.begin() + first);
}

// An instance object's part: one instance, and its table mesh when it places that mesh first
// (the loader loads a table mesh on first use, appending its triangles there).
ObjectShapes InstanceShapes(const SceneDesc& desc, const ObjectShapes& next) {
  if (next.firstInstance >= desc.instances.size()) {
    throw std::runtime_error("the scene has fewer instances than the file's instance objects");
  }
  ObjectShapes s = next;
  s.isInstance = true;
  s.instanceCount = 1;
  s.triangleCount = s.quadCount = s.sphereCount = s.meshCount = 0;
  uint32_t mesh = desc.instances[next.firstInstance].mesh;
  if (mesh == next.firstMesh && mesh < desc.meshes.size()) {
    if (desc.meshes[mesh].firstTriangle != next.firstTriangle) {
      throw std::runtime_error("an instanced mesh's triangles are not where its object is");
    }
    s.meshCount = 1;
    s.triangleCount = desc.meshes[mesh].triangleCount;
  } else if (mesh > next.firstMesh) {
    throw std::runtime_error("an instance places a mesh the objects before it did not load");
  }
  return s;
}

}  // namespace

SceneObjects::SceneObjects(const SceneDocument& document, const SceneDesc& desc) {
  // One object that is no instance made every shape (a model file's document): not loaded
  // again to learn what the scene already says.
  if (document.ObjectCount() == 1 && document.ObjectJson(0).value("type", "") != "instance") {
    ObjectShapes s;
    s.triangleCount = uint32_t(desc.triangles.size());
    s.quadCount = uint32_t(desc.quads.size());
    s.sphereCount = uint32_t(desc.spheres.size());
    s.meshCount = uint32_t(desc.meshes.size());
    s.instanceCount = uint32_t(desc.instances.size());
    shapes_.push_back(s);
    instanceOwner_.assign(s.instanceCount, 0);
    return;
  }
  ObjectShapes next;
  for (size_t i = 0; i < document.ObjectCount(); ++i) {
    ObjectShapes s;
    if (document.ObjectJson(i).value("type", "") == "instance") {
      s = InstanceShapes(desc, next);
    } else {
      SceneDesc alone = document.LoadObject(i);
      s = next;
      s.triangleCount = uint32_t(alone.triangles.size());
      s.quadCount = uint32_t(alone.quads.size());
      s.sphereCount = uint32_t(alone.spheres.size());
      s.meshCount = uint32_t(alone.meshes.size());
      s.instanceCount = uint32_t(alone.instances.size());
    }
    shapes_.push_back(s);
    instanceOwner_.insert(instanceOwner_.end(), s.instanceCount, int(i));
    next.firstTriangle += s.triangleCount;
    next.firstQuad += s.quadCount;
    next.firstSphere += s.sphereCount;
    next.firstMesh += s.meshCount;
    next.firstInstance += s.instanceCount;
  }
  if (next.firstTriangle != desc.triangles.size() || next.firstQuad != desc.quads.size() ||
      next.firstSphere != desc.spheres.size() || next.firstMesh != desc.meshes.size() ||
      next.firstInstance != desc.instances.size()) {
    throw std::runtime_error("the objects loaded one by one do not add up to the scene");
  }
}

int SceneObjects::ObjectOf(const PrimRef& prim, uint32_t instance) const {
  if (instance < instanceOwner_.size()) return instanceOwner_[instance];
  return ObjectOfPrim(prim);
}

int SceneObjects::InstanceOf(size_t index) const {
  const ObjectShapes& s = shapes_.at(index);
  return s.isInstance ? int(s.firstInstance) : -1;
}

int SceneObjects::ObjectOfPrim(const PrimRef& prim) const {
  uint32_t i = prim.Index();
  switch (prim.Type()) {
    case ShapeType::kTriangle:
      return FindRange(shapes_, i, [](const ObjectShapes& s) { return s.firstTriangle; },
                       [](const ObjectShapes& s) { return s.triangleCount; });
    case ShapeType::kQuad:
      return FindRange(shapes_, i, [](const ObjectShapes& s) { return s.firstQuad; },
                       [](const ObjectShapes& s) { return s.quadCount; });
    case ShapeType::kSphere:
      return FindRange(shapes_, i, [](const ObjectShapes& s) { return s.firstSphere; },
                       [](const ObjectShapes& s) { return s.sphereCount; });
  }
  return -1;
}

bool SceneObjects::Fits(size_t index, const SceneDesc& moved) const {
  const ObjectShapes& s = shapes_.at(index);
  return !s.isInstance && moved.triangles.size() == s.triangleCount &&
         moved.quads.size() == s.quadCount && moved.spheres.size() == s.sphereCount &&
         moved.meshes.size() == s.meshCount && moved.instances.size() == s.instanceCount;
}

void SceneObjects::Place(size_t index, const SceneDesc& moved, SceneDesc& desc) const {
  const ObjectShapes& s = shapes_.at(index);
  if (!Fits(index, moved)) {
    throw std::runtime_error("the moved object has other shapes than before (degenerate "
                             "after the move?)");
  }
  Replace(desc.triangles, s.firstTriangle, moved.triangles);
  Replace(desc.quads, s.firstQuad, moved.quads);
  Replace(desc.spheres, s.firstSphere, moved.spheres);
  for (uint32_t i = 0; i < s.instanceCount; ++i) {  // a mesh file's own reuse, placed anew
    InstanceDesc placed = moved.instances[i];
    placed.mesh += s.firstMesh;
    desc.instances[s.firstInstance + i] = placed;
  }
}

Aabb ObjectBounds(const SceneDesc& desc, const ObjectShapes& s) {
  Aabb box;
  auto grow = [&](vec3 p) {
    box.lo = glm::min(box.lo, p);
    box.hi = glm::max(box.hi, p);
  };
  if (s.isInstance || s.instanceCount > 0) {  // placed meshes: their corners moved
    for (uint32_t i = s.firstInstance; i < s.firstInstance + s.instanceCount; ++i) {
      const InstanceDesc& inst = desc.instances.at(i);
      const MeshDesc& mesh = desc.meshes.at(inst.mesh);
      for (uint32_t t = mesh.firstTriangle; t < mesh.firstTriangle + mesh.triangleCount; ++t) {
        for (vec3 p : {desc.triangles[t].p0, desc.triangles[t].p1, desc.triangles[t].p2}) {
          grow(vec3(inst.toWorld * glm::dvec4(glm::dvec3(p), 1.0)));
        }
      }
    }
    if (s.isInstance) return box;
  }
  // A flat object's own triangles (those of its meshes are in object space: placed above).
  auto inMesh = [&](uint32_t t) {
    for (uint32_t m = s.firstMesh; m < s.firstMesh + s.meshCount; ++m) {
      const MeshDesc& mesh = desc.meshes.at(m);
      if (t >= mesh.firstTriangle && t < mesh.firstTriangle + mesh.triangleCount) return true;
    }
    return false;
  };
  for (uint32_t t = s.firstTriangle; t < s.firstTriangle + s.triangleCount; ++t) {
    if (inMesh(t)) continue;
    for (vec3 p : {desc.triangles[t].p0, desc.triangles[t].p1, desc.triangles[t].p2}) grow(p);
  }
  for (uint32_t q = s.firstQuad; q < s.firstQuad + s.quadCount; ++q) {
    const Quad& quad = desc.quads[q];
    for (vec3 p : {quad.origin, quad.origin + quad.u, quad.origin + quad.v,
                   quad.origin + quad.u + quad.v}) {
      grow(p);
    }
  }
  for (uint32_t i = s.firstSphere; i < s.firstSphere + s.sphereCount; ++i) {
    grow(desc.spheres[i].center - vec3(desc.spheres[i].radius));
    grow(desc.spheres[i].center + vec3(desc.spheres[i].radius));
  }
  return box;
}

PickResult PickPixel(const Scene& scene, const Camera& camera, int width, int height, float x,
                     float y, const SceneObjects& objects) {
  Camera pinhole = camera;
  pinhole.apertureRadius = 0.0f;
  Ray ray = CameraRay(pinhole, x, y, float(width), float(height), vec2(0.5f));
  HitRecord hit;
  PickResult result;
  SceneView view = HostSceneView(scene);
  if (!IntersectClosest(view, ray, std::numeric_limits<float>::infinity(), &hit, nullptr)) {
    return result;
  }
  const PrimRef& prim = scene.prims[hit.prim];
  result.object = objects.ObjectOf(prim, hit.instance);
  result.material = int(prim.material);
  if (hit.instance < scene.instances.size() && scene.instances[hit.instance].material >= 0) {
    result.material = scene.instances[hit.instance].material;  // the instance's override
  }
  result.distance = hit.t;
  result.point = ray.o + hit.t * ray.d;
  return result;
}

}  // namespace pt
