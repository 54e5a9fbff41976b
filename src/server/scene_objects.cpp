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

}  // namespace

SceneObjects::SceneObjects(const SceneDocument& document, const SceneDesc& desc) {
  ObjectShapes next;
  for (size_t i = 0; i < document.ObjectCount(); ++i) {
    SceneDesc alone = document.LoadObject(i);
    ObjectShapes s;
    s.firstTriangle = next.firstTriangle;
    s.triangleCount = uint32_t(alone.triangles.size());
    s.firstQuad = next.firstQuad;
    s.quadCount = uint32_t(alone.quads.size());
    s.firstSphere = next.firstSphere;
    s.sphereCount = uint32_t(alone.spheres.size());
    shapes_.push_back(s);
    next.firstTriangle += s.triangleCount;
    next.firstQuad += s.quadCount;
    next.firstSphere += s.sphereCount;
  }
  if (next.firstTriangle != desc.triangles.size() || next.firstQuad != desc.quads.size() ||
      next.firstSphere != desc.spheres.size()) {
    throw std::runtime_error("the objects loaded one by one do not add up to the scene");
  }
}

int SceneObjects::ObjectOf(const PrimRef& prim) const {
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
  return moved.triangles.size() == s.triangleCount && moved.quads.size() == s.quadCount &&
         moved.spheres.size() == s.sphereCount;
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
  result.object = objects.ObjectOf(prim);
  result.material = int(prim.material);
  result.distance = hit.t;
  result.point = ray.o + hit.t * ray.d;
  return result;
}

}  // namespace pt
