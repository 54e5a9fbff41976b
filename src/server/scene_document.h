// The scene file as the live preview edits it: its JSON, with the camera, materials, object
// placements and render settings the page changed. Every edit is checked by the scene loader
// itself, on a scene made of the edited part alone, and the renderer is given what the loader
// made of it; so the preview renders what the CLI renders from Text() (bit for bit on the CPU).
#pragma once

#include <string>
#include <vector>

#include "src/io/scene_json.h"
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
  // Merges `fields` into the camera; returns the camera the loader makes of it.
  CameraDesc EditCamera(const Json& fields);
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

  // The edited scene as a JSON file.
  std::string Text() const;

 private:
  // A scene of the document's render, camera and materials and the given objects, loaded.
  SceneDesc LoadWith(const Json& camera, const Json& materials, const Json& objects) const;

  std::string path_, baseDir_;
  Json doc_;
};

// `transform` (absent: identity) moved by delta: the translation of a `matrix` (entries 3, 7
// and 11), else `translate` of the scale-rotate-translate form, which applies last.
Json TranslatedTransform(const Json* transform, vec3 delta);

}  // namespace pt
