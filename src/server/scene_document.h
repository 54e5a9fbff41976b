// The scene file as the live preview edits it: its JSON, with the camera, materials, object
// placements and render settings the page changed. Every edit is checked by the scene loader
// itself, on a scene made of the edited part alone, and the renderer is given what the loader
// made of it; so the preview renders what the CLI renders from Text() (bit for bit on the CPU).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "src/io/scene_json.h"
#include "src/io/scene_loader.h"
#include "src/scene/scene.h"

namespace pt {

class SceneDocument {
 public:
  // Reads the scene file (throws SceneError as LoadScene does). `render` holds the settings
  // after command-line overrides; they replace the file's, and `adaptive` is dropped (the
  // preview samples every pixel alike). Relative mesh paths become absolute, so Text() renders
  // from any folder.
  SceneDocument(const std::string& path, const RenderSettings& render);
  // The same from the scene's text (a scene made in memory: the Python module's dicts);
  // pathForMessages names it in errors, baseDir is where its relative paths start.
  SceneDocument(const std::string& text, const std::string& pathForMessages,
                const std::string& baseDir, const RenderSettings& render);
  // A model file (.gltf, .glb, .obj) as the JSON scene that includes it: one `mesh` object of
  // the file (absolute path; with the pose and variant the load used), the camera and the
  // lighting the loader gave `loaded` (its default environment, or --env's map), `loaded`'s
  // render settings. Not loaded again here: `loaded` is what LoadScene made of the file.
  static SceneDocument ForModel(const std::string& path, const SceneDesc& loaded,
                                const LoadOptions& options);

  const std::string& Path() const { return path_; }
  size_t ObjectCount() const { return doc_["objects"].size(); }
  const Json& ObjectJson(size_t index) const { return doc_["objects"].at(index); }
  // Materials the file defines, in its order (their indices in SceneDesc::materials); a mesh
  // file's own materials come after them and are not in the document.
  size_t MaterialCount() const { return doc_["materials"].size(); }
  std::string MaterialName(size_t index) const;
  const Json& MaterialJson(size_t index) const;
  const Json& CameraJson() const { return doc_["camera"]; }
  const Json& RenderJson() const { return doc_["render"]; }

  // The object alone, loaded as the scene file loads it: its shapes in world space.
  SceneDesc LoadObject(size_t index) const;

  // Edits: each is checked by the loader and applied only when valid; otherwise it throws
  // SceneError naming the field, and the document is unchanged.
  // Merges `fields` into the camera (replace: `fields` is the whole camera); returns the
  // camera the loader makes of it.
  CameraDesc EditCamera(const Json& fields, bool replace = false);
  // A camera the file does not state as position and look_at (from a glTF file, or framed
  // automatically) becomes those of `resolved` (the camera as built), so edits merge into it.
  void ResolveCamera(const CameraDesc& resolved);
  // Merges `fields` into a material (a different "type" replaces it whole); returns it loaded.
  Material EditMaterial(size_t index, const Json& fields);
  // An object moved by `delta` (composed into its transform) and what the loader makes of it;
  // SetObject applies it.
  struct MovedObject {
    Json object;
    SceneDesc loaded;
  };
  MovedObject TranslatedObject(size_t index, vec3 delta) const;
  // An "instance" object moved by `delta` the same way, and the placement the loader makes of
  // it (checked as the loader checks it); its mesh is not loaded.
  struct MovedInstance {
    Json object;
    glm::dmat4 toWorld;
  };
  MovedInstance TranslatedInstance(size_t index, vec3 delta) const;
  // An "instance" object given a new `transform` (either form of the file's), checked as the
  // loader checks it.
  MovedInstance PlacedInstance(size_t index, Json transform) const;
  void SetObject(size_t index, Json object) { doc_["objects"][index] = std::move(object); }
  // render.max_depth or render.spp, within the loader's limits.
  void SetRenderSetting(const std::string& key, int64_t value);

  // The lighting at infinity (src/server/scene_document_env.cpp): the scene's own
  // (`background` or `environment`, as the file had it), none, or an equirectangular map
  // file; scaled by `strength` and turned by `rotation` degrees about +Y. Checked by the
  // loader (the map is read); returns what it made of it (environment, background and the
  // sky's sun among the directional lights).
  struct Lighting {
    enum class Kind { kScene, kNone, kMap } kind = Kind::kScene;
    std::string mapPath;  // kMap: an absolute path
    float strength = 1.0f;
    float rotation = 0.0f;
  };
  SceneDesc EditLighting(const Lighting& lighting);
  const Lighting& CurrentLighting() const { return lighting_; }
  // The lighting at infinity of `loaded` (the scene as the render loaded it, after --env,
  // --env none and --env-strength) becomes the document's, and "the scene's own" lighting.
  void AdoptLighting(const SceneDesc& loaded);

  // The edited scene as a JSON file.
  std::string Text() const;

  // The folder relative paths of the scene start from (absolute).
  const std::string& BaseDir() const { return baseDir_; }

 private:
  SceneDocument() = default;
  void MakePathsAbsolute();
  Json LightingJson(const Lighting& lighting) const;
  // A scene of the document's render, camera and materials and the given objects, loaded.
  SceneDesc LoadWith(const Json& camera, const Json& materials, const Json& objects) const;

  std::string path_, baseDir_;
  Json doc_;
  Json sceneLighting_;  // the file's "background" and "environment" entries, as read
  Lighting lighting_;
};

// A float as the double of its shortest decimal (3.9f as 3.9, not 3.9000000953674316): the
// loader reads it back as the same float.
double DocumentFloat(float v);
Json DocumentVec3(vec3 v);
// A camera as the scene format states it (position, look_at, up, fov_y, the lens when it has
// one): the loader makes the same camera of it.
Json CameraDescJson(const CameraDesc& camera);

// `transform` (absent: identity) moved by delta: the translation of a `matrix` (entries 3, 7
// and 11), else `translate` of the scale-rotate-translate form, which applies last.
Json TranslatedTransform(const Json* transform, vec3 delta);

}  // namespace pt
