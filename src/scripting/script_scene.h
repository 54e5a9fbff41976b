// A scene as a script holds it (the Python module's pathtracer.Scene): loaded once, built once
// (BVH, light table) and kept between renders; a render's options rebuild only what they
// change (the BVH for --bvh/--bvh-build, the environment for --env), and edits of the camera,
// a material or an instance's transform update the built scene in place, as the live preview
// does (src/server/live_render.cpp): a material re-reads the light table, an instance re-builds
// the top level only. Every edit is checked by the scene loader itself, so an edited scene
// renders what a fresh load of the edited file renders, and a bad value is a SceneError naming
// the scene and the field (the scene is then unchanged).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "src/app/cli.h"
#include "src/app/stats_json.h"
#include "src/io/scene_json.h"
#include "src/scene/scene.h"

namespace pt {

class SceneDocument;
class SceneObjects;

class ScriptScene {
 public:
  // A JSON scene or a model file (.gltf, .glb, .obj); `camera` is --camera's choice of a
  // glTF camera (empty: the scene's own). Throws SceneError (a bad file), std::runtime_error.
  static std::unique_ptr<ScriptScene> Load(const std::string& path, const std::string& camera);
  // JSON scene text (a Python dict): `name` names it in messages, relative files resolve
  // against baseDir.
  static std::unique_ptr<ScriptScene> FromText(const std::string& text, const std::string& name,
                                               const std::string& baseDir,
                                               const std::string& camera);
  ~ScriptScene();

  const std::string& Name() const { return name_; }
  // The loader's warnings not yet handed out (each once).
  std::vector<std::string> TakeWarnings();

  // ---- Reading ----
  // The camera as the scene format's fields (position, look_at, up, fov_y, aperture_radius and,
  // with an aperture, focus_distance); an automatic camera as framed for the last render.
  Json CameraJson() const;
  const std::vector<std::string>& MaterialNames() const { return Desc().materialNames; }
  // The material's fields as the scene file gives them; empty for a model file's material.
  Json MaterialJson(const std::string& name);
  size_t InstanceCount() const { return Desc().instances.size(); }
  const glm::dmat4& InstanceTransform(size_t index) const;
  const RenderSettings& SceneSettings() const { return base_.render; }
  // The edited scene as a JSON file (a JSON scene only; empty for a model file). Its render
  // section is the scene's, without adaptive sampling.
  std::string Text();
  // Grows with every edit, rebuild and Prepare: a progressive render started before stops
  // then (its session reads the built scene).
  uint64_t Version() const { return version_; }

  // ---- Edits ----
  // Merges the scene format's camera fields into the camera.
  void EditCamera(const Json& fields);
  // Merges fields into the named material (a different "type" replaces it whole). A JSON
  // scene's materials only: a model file's material is refused.
  void EditMaterial(const std::string& name, const Json& fields);
  // Instance `index` (of InstanceCount()) placed by `transform`, in either form of the scene
  // format ({"matrix": [16 numbers, row-major]} or scale / rotate / translate).
  void SetInstanceTransform(size_t index, const Json& transform);

  // ---- Rendering ----
  // The scene built for a render with these options (kept until options or edits change it).
  // Times are set for what ran now (0 when nothing was loaded or built). Throws CliError for
  // overrides that do not fit (image size, crop), SceneError for a bad --env.
  const Scene& Prepare(const CliOptions& cli, AppTimes* times);

 private:
  // What the options change beyond the render settings: a rebuild when it differs.
  struct BuildKey {
    std::string envPath;
    std::optional<float> envStrength;
    BvhBuildOptions bvh;
    float autoFrameAspect = 0.0f;  // the aspect an automatic camera was framed for
    bool operator==(const BuildKey& o) const;
  };
  // The loaded scene's parts the options override, restored before each rebuild.
  struct BaseParts {
    RenderSettings render;
    CameraDesc camera;
    vec3 background;
    EnvironmentDesc environment;
    std::vector<DirectionalLightDesc> directionalLights;
  };

  ScriptScene(std::string name, std::string baseDir, SceneDesc desc);
  const SceneDesc& Desc() const { return built_.desc; }
  BuildKey KeyFor(const CliOptions& cli, const RenderSettings& render) const;
  void Rebuild(const CliOptions& cli, const RenderSettings& render, const BuildKey& key);
  SceneDocument& Document();  // JSON scenes: made on the first edit
  const SceneObjects& Objects();
  CameraDesc CameraFromFields(const Json& fields) const;
  glm::dmat4 CheckedTransform(size_t index, const Json& transform) const;

  std::string name_, baseDir_;
  std::optional<std::string> text_;  // a JSON scene's text (none for a model file)
  BaseParts base_;
  Scene built_;
  BuildKey key_;
  bool topLevelDirty_ = false, materialsDirty_ = false;
  std::unique_ptr<SceneDocument> document_;
  std::unique_ptr<SceneObjects> objects_;
  std::vector<std::string> warnings_;
  uint64_t version_ = 0;
};

}  // namespace pt
