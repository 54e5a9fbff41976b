#include "src/scripting/script_scene.h"

#include <charconv>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "src/app/run_steps.h"
#include "src/io/environment_loader.h"
#include "src/io/model_scene.h"
#include "src/io/scene_loader.h"
#include "src/lights/light_table.h"
#include "src/scene/instances.h"
#include "src/scene/transform.h"
#include "src/server/scene_document.h"
#include "src/server/scene_objects.h"

namespace pt {
namespace {

namespace fs = std::filesystem;
using ScriptClock = std::chrono::steady_clock;

double ScriptMsSince(ScriptClock::time_point start) {
  return std::chrono::duration<double, std::milli>(ScriptClock::now() - start).count();
}

std::string ReadSceneText(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw SceneError(path, "", "cannot open the scene file: no such file");
  if (fs::is_directory(path, ec)) throw SceneError(path, "", "is a folder, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path, "", "cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw SceneError(path, "", "cannot read the scene file");
  return text.str();
}

// A float as the double of its shortest decimal (3.9f as 3.9, not 3.9000000953674316): the
// loader reads it back as the same float.
double ShortFloat(float v) {
  char text[32];
  auto end = std::to_chars(text, text + sizeof(text), v).ptr;
  return std::strtod(std::string(text, end).c_str(), nullptr);
}

Json Vec3Json(vec3 v) { return Json::array({ShortFloat(v.x), ShortFloat(v.y), ShortFloat(v.z)}); }

}  // namespace

bool ScriptScene::BuildKey::operator==(const BuildKey& o) const {
  return envPath == o.envPath && envStrength == o.envStrength && bvh.layout == o.bvh.layout &&
         bvh.builder == o.bvh.builder && autoFrameAspect == o.autoFrameAspect;
}

std::unique_ptr<ScriptScene> ScriptScene::Load(const std::string& path,
                                               const std::string& camera) {
  LoadOptions load;
  load.camera = camera;
  if (IsModelFile(path)) {
    return std::unique_ptr<ScriptScene>(new ScriptScene(path, "", LoadScene(path, load)));
  }
  std::string text = ReadSceneText(path);
  std::string baseDir = fs::path(path).parent_path().string();
  auto scene = std::unique_ptr<ScriptScene>(
      new ScriptScene(path, baseDir, LoadSceneFromString(text, path, baseDir, load)));
  scene->text_ = std::move(text);
  return scene;
}

std::unique_ptr<ScriptScene> ScriptScene::FromText(const std::string& text,
                                                   const std::string& name,
                                                   const std::string& baseDir,
                                                   const std::string& camera) {
  LoadOptions load;
  load.camera = camera;
  auto scene = std::unique_ptr<ScriptScene>(
      new ScriptScene(name, baseDir, LoadSceneFromString(text, name, baseDir, load)));
  scene->text_ = text;
  return scene;
}

// Built at once with the default options: what most renders use, and a scene the renderer
// cannot take fails here, at load.
ScriptScene::ScriptScene(std::string name, std::string baseDir, SceneDesc desc)
    : name_(std::move(name)), baseDir_(baseDir.empty() ? "." : std::move(baseDir)) {
  warnings_ = desc.warnings;
  base_ = BaseParts{desc.render, desc.camera, desc.background, desc.environment,
                    desc.directionalLights};
  CliOptions defaults;
  key_ = KeyFor(defaults, desc.render);
  built_ = BuildScene(std::move(desc), key_.bvh);
}

ScriptScene::~ScriptScene() = default;

std::vector<std::string> ScriptScene::TakeWarnings() { return std::exchange(warnings_, {}); }

Json ScriptScene::CameraJson() const {
  const CameraDesc& c = Desc().camera;  // an automatic camera as framed
  Json camera = {{"position", Vec3Json(c.position)}, {"look_at", Vec3Json(c.lookAt)},
                 {"up", Vec3Json(c.up)}, {"fov_y", ShortFloat(c.fovY)},
                 {"aperture_radius", ShortFloat(c.apertureRadius)}};
  // Without an aperture the focus distance plays no part; left out, a changed position or
  // look_at does not keep the old one.
  if (c.apertureRadius > 0.0f) camera["focus_distance"] = ShortFloat(c.focusDistance);
  return camera;
}

Json ScriptScene::MaterialJson(const std::string& name) {
  const auto& names = MaterialNames();
  size_t index = size_t(std::find(names.begin(), names.end(), name) - names.begin());
  if (!text_ || index >= Document().MaterialCount()) return Json();
  return Document().MaterialJson(index);
}

const glm::dmat4& ScriptScene::InstanceTransform(size_t index) const {
  if (index >= InstanceCount()) {
    throw SceneError(name_, "instances", "no instance " + std::to_string(index) +
                                             " (the scene has " +
                                             std::to_string(InstanceCount()) + ")");
  }
  return Desc().instances[index].toWorld;
}

std::string ScriptScene::Text() { return text_ ? Document().Text() : std::string(); }

SceneDocument& ScriptScene::Document() {
  if (!document_) {
    document_ = std::make_unique<SceneDocument>(*text_, name_, baseDir_, base_.render);
  }
  return *document_;
}

const SceneObjects& ScriptScene::Objects() {
  if (!objects_) objects_ = std::make_unique<SceneObjects>(Document(), Desc());
  return *objects_;
}

// ---- Edits ----------------------------------------------------------------------------------

CameraDesc ScriptScene::CameraFromFields(const Json& fields) const {
  Json camera = CameraJson();
  for (const auto& [key, value] : fields.items()) camera[key] = value;
  Json mini = {{"render", {{"width", 1}, {"height", 1}, {"spp", 1}, {"max_depth", 0}}},
               {"camera", camera}, {"materials", Json::object()}, {"objects", Json::array()}};
  return LoadSceneFromString(mini.dump(), name_, baseDir_).camera;
}

void ScriptScene::EditCamera(const Json& fields) {
  if (!fields.is_object()) throw SceneError(name_, "camera", "expected an object");
  CameraDesc camera = text_ ? Document().EditCamera(fields) : CameraFromFields(fields);
  base_.camera = camera;
  built_.desc.camera = camera;
  built_.camera = MakeCamera(camera, Desc().render.width, Desc().render.height);
  key_.autoFrameAspect = 0.0f;  // framed no more
  ++version_;
}

void ScriptScene::EditMaterial(const std::string& name, const Json& fields) {
  const auto& names = MaterialNames();
  size_t index = size_t(std::find(names.begin(), names.end(), name) - names.begin());
  if (index == names.size()) {
    std::string all;
    for (const std::string& n : names) all += (all.empty() ? "" : ", ") + n;
    throw SceneError(name_, "materials", "no material \"" + name + "\" (the scene has: " + all +
                                             ")");
  }
  if (!text_ || index >= Document().MaterialCount()) {
    throw SceneError(name_, "materials." + name,
                     "is a model file's material: only the materials of a JSON scene's "
                     "\"materials\" can be edited");
  }
  built_.desc.materials[index] = Document().EditMaterial(index, fields);
  materialsDirty_ = true;
  ++version_;
}

glm::dmat4 ScriptScene::CheckedTransform(size_t index, const Json& transform) const {
  std::string field = "instances[" + std::to_string(index) + "].transform";
  glm::dmat4 toWorld(ParseTransform(JsonObject(JsonValue(transform, field, name_))));
  std::string why;
  if (!ValidInstanceTransform(toWorld, &why)) throw SceneError(name_, field, why);
  return toWorld;
}

void ScriptScene::SetInstanceTransform(size_t index, const Json& transform) {
  InstanceTransform(index);  // throws for an index out of range
  int object = -1;
  if (text_) {
    for (size_t o = 0; o < Objects().Count() && object < 0; ++o) {
      if (Objects().InstanceOf(o) == int(index)) object = int(o);
    }
  }
  glm::dmat4 toWorld;
  if (object >= 0) {  // an "instance" object of the file: its JSON follows
    SceneDocument::MovedInstance placed = Document().PlacedInstance(size_t(object), transform);
    Document().SetObject(size_t(object), std::move(placed.object));
    toWorld = placed.toWorld;
  } else {  // a model file's own reuse of a mesh
    toWorld = CheckedTransform(index, transform);
  }
  UpdateInstanceTransform(built_, index, toWorld);
  topLevelDirty_ = true;
  ++version_;
}

// ---- Building -------------------------------------------------------------------------------

ScriptScene::BuildKey ScriptScene::KeyFor(const CliOptions& cli,
                                          const RenderSettings& render) const {
  BuildKey key;
  key.envPath = cli.envPath;
  key.envStrength = cli.envStrength;
  key.bvh = ChooseBvh(cli, AppBackends{});  // the host builds (no device LBVH here)
  if (base_.camera.autoFrame) {  // until a camera edit replaces it
    key.autoFrameAspect = float(render.width) / float(std::max(1, render.height));
  }
  return key;
}

void ScriptScene::Rebuild(const CliOptions& cli, const RenderSettings& render,
                          const BuildKey& key) {
  // The environment first, alone: a bad --env leaves the built scene as it was.
  SceneDesc env;
  env.background = base_.background;
  env.environment = base_.environment;
  env.directionalLights = base_.directionalLights;
  if (!key.envPath.empty()) ReplaceEnvironmentMap(key.envPath, &env);
  if (key.envStrength) env.environment.strength = *key.envStrength;
  std::string dark = DarkEnvironmentWarning(env);
  if (!dark.empty()) warnings_.push_back(dark);
  SceneDesc desc = std::move(built_.desc);
  desc.render = render;
  desc.camera = base_.camera;
  desc.background = env.background;
  desc.environment = std::move(env.environment);
  desc.directionalLights = std::move(env.directionalLights);
  built_ = BuildScene(std::move(desc), key.bvh);
  key_ = key;
  topLevelDirty_ = materialsDirty_ = false;
  ++version_;
}

const Scene& ScriptScene::Prepare(const CliOptions& cli, AppTimes* times) {
  *times = AppTimes{};
  times->bvhBuilder = BuilderThatRan(cli, false);  // the module builds on the host
  RenderSettings render = base_.render;
  ApplyCliOverrides(cli, &render);
  BuildKey key = KeyFor(cli, render);
  if (!(key == key_)) {
    ScriptClock::time_point start = ScriptClock::now();
    Rebuild(cli, render, key);
    times->bvhBuildMs = built_.bvhBuildMs > 0.0 ? built_.bvhBuildMs : ScriptMsSince(start);
  }
  built_.desc.render = render;
  built_.camera = MakeCamera(built_.desc.camera, render.width, render.height);
  // As the live preview applies edits: the top level first, then the light table (which
  // follows the top level's bounds).
  if (topLevelDirty_) RebuildTopLevel(built_);
  if (materialsDirty_) BuildLightTable(built_);
  topLevelDirty_ = materialsDirty_ = false;
  ++version_;
  return built_;
}

}  // namespace pt
