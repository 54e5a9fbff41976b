// Instancing on the host: the two levels of a scene whose SceneDesc places meshes by transform
// (one bottom-level BVH per mesh, in its object space, plus one for the world-space primitives;
// a top-level BVH over the instances' world bounds), and moving instances afterwards.
//
// To move instances in a live render (what the preview server calls):
//   UpdateInstanceTransform(scene, i, toWorld);   // any number of times
//   RebuildTopLevel(scene);                       // top level only: bottom levels untouched
//   session->TopLevelChanged();                   // re-uploads the top-level arrays only
#pragma once

#include <cstddef>

#include "src/geometry/aabb.h"
#include "src/scene/scene.h"

namespace pt {

// What BuildScene does when SceneDesc::meshes is not empty: bottom levels, instance table, top
// level, light table (each instance's emissive triangles are area lights of their own, in world
// space). Throws std::runtime_error for inconsistent meshes or instances.
void BuildInstancedScene(Scene& scene);

// The exact world bounds of every placement (the world's own primitives included).
Aabb InstancedWorldBounds(const Scene& scene);

// Whether a matrix can place an instance: finite, affine (last row 0 0 0 1), invertible. On
// false, *why says what is wrong.
bool ValidInstanceTransform(const glm::dmat4& toWorld, std::string* why);

// Moves instance `index` (of SceneDesc::instances) to toWorld: the instance table only; call
// RebuildTopLevel before rendering again (once, after any number of moves). Throws
// std::invalid_argument for an index out of range or a transform ValidInstanceTransform refuses.
void UpdateInstanceTransform(Scene& scene, size_t index, const glm::dmat4& toWorld);

// The top level again over the instances' current world bounds, with the bounding sphere and
// the light probabilities (scaling an instance changes its lights' power). Costs O(n log n) in
// the instances; no mesh is touched. Records the time in Scene::tlasBuildMs.
void RebuildTopLevel(Scene& scene);

// World-space area of an instanced triangle light (Light::instance >= 0): of the triangle its
// sampling uses (TriangleToWorld), by the formula its pdf uses, so the two agree.
double InstanceLightArea(const Scene& scene, const Light& light);

// Appends the area lights of every instance, sets Instance::lightBase and the mesh primitives'
// PrimRef::light (rank among the mesh's emitters). Called by BuildLightTable first, so the
// world's area lights follow (the world's instance has lightBase 0: its PrimRef::light values
// are light indices), as in the scene FlattenInstances makes.
void AppendInstanceLights(Scene& scene);

// The same scene without instancing: every instance's triangles placed in world space by its
// (float) transform as a mesh object would be (normals by the inverse transpose, vertices 1 and
// 2 swapped under mirroring), instance after instance, then the world's own triangles; meshes
// and instances emptied. Light order, closest-hit ties and the bounding sphere then match the
// instanced scene's, so identity placements render bit for bit alike. For tests and studies.
SceneDesc FlattenInstances(SceneDesc desc);

}  // namespace pt
