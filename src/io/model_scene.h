// A model file (.gltf, .glb or .obj) as a whole scene, and the parts of a model that a JSON
// scene takes from it (its triangles as a `mesh` object, its lights, a camera). The render
// defaults, the automatic camera and the default environment of such a scene are documented in
// docs/scene-format.md ("A glTF or OBJ file as the scene").
#pragma once

#include <string>
#include <vector>

#include "src/io/gltf_animation.h"
#include "src/io/gltf_scene.h"
#include "src/io/mesh_common.h"
#include "src/io/scene_loader.h"

namespace pt {

class JsonObject;

// Render settings of a model scene (the command line overrides each).
constexpr int kModelSceneHeight = 720;        // width = height x the camera's aspectRatio
constexpr float kModelSceneAspect = 16.0f / 9.0f;  // when the camera gives none: 1280 x 720
constexpr int kModelSceneSpp = 64;
constexpr int kModelSceneMaxDepth = 12;
// Radiance of the uniform environment that lights a model with no light of its own.
constexpr float kDefaultEnvironmentRadiance = 1.0f;

// True for the extensions LoadScene reads as a model rather than as a JSON scene.
bool IsModelFile(const std::string& path);

// Loads a model file's triangles (and materials, unless the sink overrides them) through the
// sink; returns the glTF file's cameras, lights and ignored parts (empty for OBJ). Throws
// std::runtime_error for an unreadable or malformed file.
GltfSceneContents LoadModelFile(const std::string& path, MeshSink& sink,
                                const GltfAnimationChoice& animation = {});

// The pose options gives, else the JSON object's "animation" (an index or a name) and "time"
// fields (o may be null: none).
GltfAnimationChoice AnimationChoice(const LoadOptions& options, const JsonObject* o);

// Appends the file's point, spot and directional lights to the scene's.
void AddGltfLights(const GltfSceneContents& contents, SceneDesc& scene);

// The one summary line of a glTF file's scene parts ("FILE: NOTE; NOTE; ignored: 2 animations
// ..."), empty when there is nothing to say.
std::string GltfSceneSummary(const std::string& label, const GltfSceneContents& contents,
                             const std::vector<std::string>& notes = {});

// A model file as the whole scene: its default scene's triangles, materials and lights, the
// camera options.camera selects (the first perspective camera by default, the automatic
// camera without one) and the render defaults above; unlit (and options.environmentGiven
// false), the default environment. Errors name the file and the part.
SceneDesc LoadModelScene(const std::string& path, const LoadOptions& options);

// A JSON scene's camera taken from a model file: {"from_file": F, "name": N | "index": I,
// "transform": T, "fov_y", "aperture_radius", "focus_distance"}. `selector` (the command
// line's --camera) replaces name and index when not empty; "animation" and "time" pose it
// (replaced by the command line's).
CameraDesc ParseCameraFromFile(const JsonObject& camera, const std::string& baseDir,
                               const LoadOptions& options);

}  // namespace pt
