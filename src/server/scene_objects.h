// The scene file's objects as the renderer's primitives: which shapes each object made, so that
// a pixel's primitive names its object, and an object moved in place of its old shapes. An
// "instance" object makes no shapes of its own: it is one SceneDesc::instances entry, moved
// through the top level (src/scene/instances.h).
#pragma once

#include <cstdint>
#include <vector>

#include "src/geometry/aabb.h"
#include "src/scene/scene.h"

namespace pt {

class SceneDocument;

// The ranges of SceneDesc's arrays one object of the file made. An instance object's triangles
// are those of the table mesh it placed first (none when an earlier instance placed it).
struct ObjectShapes {
  uint32_t firstTriangle = 0, triangleCount = 0;
  uint32_t firstQuad = 0, quadCount = 0;
  uint32_t firstSphere = 0, sphereCount = 0;
  uint32_t firstMesh = 0, meshCount = 0;          // SceneDesc::meshes
  uint32_t firstInstance = 0, instanceCount = 0;  // SceneDesc::instances
  bool isInstance = false;                        // an "instance" object
};

class SceneObjects {
 public:
  // Loads each object alone to learn its shapes (the loader appends objects in file order);
  // an instance object is not loaded (its mesh may be large): it appends one instance, and its
  // mesh's triangles when it places that mesh first. Throws std::runtime_error when the objects
  // do not add up to the scene's.
  SceneObjects(const SceneDocument& document, const SceneDesc& desc);

  size_t Count() const { return shapes_.size(); }
  const ObjectShapes& Shapes(size_t index) const { return shapes_[index]; }
  // The object a hit belongs to, or -1: the instance object (or mesh object of a file with
  // reused meshes) that placed HitRecord::instance, else the object that made the primitive
  // (a flat scene's hits, and the world's own primitives: the trailing Scene::instances entry).
  int ObjectOf(const PrimRef& prim, uint32_t instance) const;
  // The SceneDesc::instances index of an instance object, or -1 for other objects.
  int InstanceOf(size_t index) const;
  // Whether `moved` has the object's shape counts (a move can make a shape degenerate).
  bool Fits(size_t index, const SceneDesc& moved) const;
  // Replaces the object's world-space shapes with those of `moved` (SceneDocument::LoadObject
  // of its new placement), and the placements of a mesh file's reused meshes; materials,
  // normals and UVs stay, as a move keeps them. Not for instance objects. Throws
  // std::runtime_error when the moved object has other shape counts.
  void Place(size_t index, const SceneDesc& moved, SceneDesc& desc) const;

 private:
  int ObjectOfPrim(const PrimRef& prim) const;

  std::vector<ObjectShapes> shapes_;
  std::vector<int> instanceOwner_;  // the object of each SceneDesc::instances entry
};

// World-space bounds of one object's shapes (an instance's: its mesh placed); empty (lo > hi)
// when it has none.
Aabb ObjectBounds(const SceneDesc& desc, const ObjectShapes& shapes);

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
