// The scene file's objects as the renderer's primitives: which shapes each object made, so that
// a pixel's primitive names its object, and an object moved in place of its old shapes.
#pragma once

#include <cstdint>
#include <vector>

#include "src/scene/scene.h"

namespace pt {

class SceneDocument;

// The ranges of SceneDesc's shape arrays one object of the file made.
struct ObjectShapes {
  uint32_t firstTriangle = 0, triangleCount = 0;
  uint32_t firstQuad = 0, quadCount = 0;
  uint32_t firstSphere = 0, sphereCount = 0;
};

class SceneObjects {
 public:
  // Loads each object alone to learn its shapes (the loader appends objects in file order).
  // Throws std::runtime_error when they do not add up to the scene's.
  SceneObjects(const SceneDocument& document, const SceneDesc& desc);

  size_t Count() const { return shapes_.size(); }
  const ObjectShapes& Shapes(size_t index) const { return shapes_[index]; }
  // The object that made a primitive, or -1.
  int ObjectOf(const PrimRef& prim) const;
  // Whether `moved` has the object's shape counts (a move can make a shape degenerate).
  bool Fits(size_t index, const SceneDesc& moved) const;
  // Replaces the object's world-space shapes with those of `moved` (SceneDocument::LoadObject
  // of its new placement); materials, normals and UVs stay, as a move keeps them. Throws
  // std::runtime_error when the moved object has other shape counts.
  void Place(size_t index, const SceneDesc& moved, SceneDesc& desc) const;

 private:
  std::vector<ObjectShapes> shapes_;
};

// What the centre of pixel (x, y) sees: a ray cast on the host through the scene's BVH with
// the renderer's own traversal (a pinhole camera: the lens centre).
struct PickResult {
  int object = -1;    // -1: nothing (the background)
  int material = -1;  // the hit primitive's material
  vec3 point = vec3(0.0f);
  float distance = 0.0f;
};
PickResult PickPixel(const Scene& scene, const Camera& camera, int width, int height, float x,
                     float y, const SceneObjects& objects);

}  // namespace pt
