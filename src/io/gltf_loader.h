// glTF 2.0 (.gltf and .glb) meshes: every triangle primitive of the default scene (or scene 0),
// node transforms composed, vertex normals kept, and the per-vertex data (TEXCOORD_0/1,
// TANGENT, COLOR_0) that the primitive's material reads; materials mapped by gltf_material.h
// (textures decoded only when a used material needs them).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "src/io/gltf_animation.h"
#include "src/io/gltf_scene.h"
#include "src/io/mesh_common.h"

namespace pt {

// Loads the file's triangles into the sink (its materials too, unless the sink overrides them)
// and returns its cameras, lights and ignored parts (src/io/gltf_scene.h), placed by the
// sink's object transform, in the pose `animation` chooses (the static pose by default;
// skins and morph targets applied either way). Throws std::runtime_error for an unreadable or
// malformed file.
GltfSceneContents LoadGltfMesh(const std::string& path, MeshSink& sink,
                               const GltfAnimationChoice& animation = {});

// The cameras, lights and ignored parts alone (no triangles), in the file's own space.
GltfSceneContents ReadGltfSceneParts(const std::string& path,
                                     const GltfAnimationChoice& animation = {});

// While one is alive, each glTF file is parsed once and its parse shared by every load of it
// (a scene placing one file 141 times parses it once), and Prefetch parses files on threads
// of their own ahead of the loader, which then finds them ready (issue 28: big scenes waited
// on the host). The scene loader keeps one for the length of a load; one at a time.
class GltfParseCache {
 public:
  GltfParseCache();
  ~GltfParseCache();
  GltfParseCache(const GltfParseCache&) = delete;
  GltfParseCache& operator=(const GltfParseCache&) = delete;
  void Prefetch(const std::vector<std::string>& paths);  // the .gltf and .glb among them

 private:
  bool owns_ = false;
};

}  // namespace pt
