// The document's lighting at infinity as the preview's environment picker edits it: the file's
// own background or environment, none, or a map file, with a strength and a turn about +Y.
#include <cmath>
#include <filesystem>

#include "src/io/environment_loader.h"
#include "src/server/scene_document.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

// The file's own lighting scaled and turned: a constant background becomes the equivalent
// constant environment (which has a strength); an environment object keeps its other fields.
Json ScaledSceneLighting(const Json& scene, float strength, float rotation) {
  Json env;
  if (scene.contains("environment")) {
    env = scene["environment"];
  } else if (scene.contains("background")) {
    env = Json{{"radiance", scene["background"]}};
  } else {
    return Json();  // the file has none: nothing to scale
  }
  if (!env.is_object()) return env;  // the loader refuses it with its own message
  if (strength != 1.0f || env.contains("strength")) {
    double base = env.value("strength", 1.0);
    env["strength"] = base * double(strength);
  }
  if (rotation != 0.0f) {
    Json rotate = env.value("rotate", Json::array({0.0, 0.0, 0.0}));
    if (rotate.is_array() && rotate.size() == 3 && rotate[1].is_number()) {
      rotate[1] = rotate[1].get<double>() + double(rotation);
    }
    env["rotate"] = rotate;
  }
  return env;
}

}  // namespace

Json SceneDocument::LightingJson(const Lighting& lighting) const {
  switch (lighting.kind) {
    case Lighting::Kind::kNone: return Json();
    case Lighting::Kind::kScene:
      if (lighting.strength == 1.0f && lighting.rotation == 0.0f) return sceneLighting_;
      return Json{{"environment", ScaledSceneLighting(sceneLighting_, lighting.strength,
                                                       lighting.rotation)}};
    case Lighting::Kind::kMap:
      return Json{{"environment",
                   {{"file", lighting.mapPath},
                    {"strength", lighting.strength},
                    {"rotate", Json::array({0.0, double(lighting.rotation), 0.0})}}}};
  }
  return Json();
}

SceneDesc SceneDocument::EditLighting(const Lighting& lighting) {
  if (!(lighting.strength >= 0.0f) || !std::isfinite(lighting.strength)) {
    throw SceneError(path_, "environment.strength", "must be a finite number >= 0");
  }
  if (!std::isfinite(lighting.rotation)) {
    throw SceneError(path_, "environment.rotate", "must be a finite number of degrees");
  }
  Json entries = LightingJson(lighting);
  Json mini = Json::object();
  mini["render"] = Json{{"width", 1}, {"height", 1}, {"spp", 1}, {"max_depth", 0}};
  mini["camera"] = CameraJson();
  mini["materials"] = Json::object();
  mini["objects"] = Json::array();
  if (entries.is_object()) {
    for (const auto& [key, value] : entries.items()) mini[key] = value;
  }
  SceneDesc loaded = LoadSceneFromString(mini.dump(), path_, baseDir_);
  doc_.erase("background");
  doc_.erase("environment");
  if (entries.is_object()) {
    for (const auto& [key, value] : entries.items()) doc_[key] = value;
  }
  lighting_ = lighting;
  return loaded;
}

void SceneDocument::AdoptLighting(const SceneDesc& loaded) {
  doc_.erase("background");
  doc_.erase("environment");
  const EnvironmentDesc& env = loaded.environment;
  if (env.isSky && sceneLighting_.contains("environment")) {  // the file's sky, rescaled
    Json sky = sceneLighting_["environment"];
    sky["strength"] = DocumentFloat(env.strength);
    doc_["environment"] = sky;
  } else if (env.HasMap()) {
    Json map = {{"file", fs::absolute(fs::path(env.file)).lexically_normal().string()},
                {"strength", DocumentFloat(env.strength)},
                {"rotate", DocumentVec3(env.rotateDegrees)}};
    if (!env.visibleToCamera) {
      map["visible_to_camera"] = false;
      map["camera_color"] = DocumentVec3(env.cameraColor);
    }
    doc_["environment"] = map;
  } else if (loaded.background != vec3(0.0f)) {
    doc_["background"] = DocumentVec3(loaded.background);
  }
  sceneLighting_ = Json::object();
  for (const char* key : {"background", "environment"}) {
    if (doc_.contains(key)) sceneLighting_[key] = doc_[key];
  }
  lighting_ = Lighting{};
}

}  // namespace pt
