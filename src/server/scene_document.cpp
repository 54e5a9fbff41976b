#include "src/server/scene_document.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "src/io/scene_loader.h"
#include "src/scene/instances.h"
#include "src/scene/transform.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

std::string ReadText(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw SceneError(path, "", "cannot open the scene file");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in.good() && !in.eof()) throw SceneError(path, "", "cannot read the scene file");
  return text.str();
}

Json RenderSection(const RenderSettings& r) {
  Json render = Json::object();
  render["width"] = r.width;
  render["height"] = r.height;
  render["spp"] = r.spp;
  render["max_depth"] = r.maxDepth;
  render["seed"] = r.seed;
  render["russian_roulette_depth"] = r.russianRouletteDepth;
  return render;
}

// The smallest render section the loader accepts: a mini scene needs no pixels.
Json TinyRender() { return Json{{"width", 1}, {"height", 1}, {"spp", 1}, {"max_depth", 0}}; }

}  // namespace

SceneDocument::SceneDocument(const std::string& path, const RenderSettings& render)
    : SceneDocument(ReadText(path), path, fs::path(path).parent_path().string(), render) {}

SceneDocument::SceneDocument(const std::string& text, const std::string& pathForMessages,
                             const std::string& baseDir, const RenderSettings& render)
    : path_(pathForMessages) {
  LoadSceneFromString(text, path_, baseDir);  // the full check
  doc_ = ParseSceneJson(text, path_);
  baseDir_ = fs::absolute(fs::path(baseDir)).lexically_normal().string();
  Json renderJson = RenderSection(render);
  doc_["render"] = renderJson;  // overrides applied, adaptive dropped
  if (!doc_.contains("materials")) doc_["materials"] = Json::object();
  auto absolute = [&](Json& entry) {
    if (!entry.is_object() || !entry.contains("file")) return;
    fs::path file = entry["file"].get<std::string>();
    if (file.is_relative()) entry["file"] = (fs::path(baseDir_) / file).lexically_normal().string();
  };
  for (Json& object : doc_["objects"]) {
    if (object.value("type", "") == "mesh") absolute(object);
  }
  if (doc_.contains("meshes")) {
    for (Json& mesh : doc_["meshes"]) absolute(mesh);
  }
}

std::string SceneDocument::MaterialName(size_t index) const {
  auto it = doc_["materials"].begin();
  std::advance(it, std::ptrdiff_t(index));
  return it.key();
}

const Json& SceneDocument::MaterialJson(size_t index) const {
  return doc_["materials"].at(MaterialName(index));
}

SceneDesc SceneDocument::LoadWith(const Json& camera, const Json& materials,
                                  const Json& objects) const {
  Json mini = Json::object();
  mini["render"] = TinyRender();
  mini["camera"] = camera;
  mini["materials"] = materials;
  mini["objects"] = objects;
  return LoadSceneFromString(mini.dump(), path_, baseDir_);
}

SceneDesc SceneDocument::LoadObject(size_t index) const {
  return LoadWith(CameraJson(), doc_["materials"], Json::array({ObjectJson(index)}));
}

CameraDesc SceneDocument::EditCamera(const Json& fields) {
  if (!fields.is_object()) throw SceneError(path_, "camera", "expected an object");
  Json camera = CameraJson();
  for (const auto& [key, value] : fields.items()) camera[key] = value;
  CameraDesc loaded = LoadWith(camera, doc_["materials"], Json::array()).camera;
  doc_["camera"] = camera;
  return loaded;
}

Material SceneDocument::EditMaterial(size_t index, const Json& fields) {
  if (!fields.is_object()) throw SceneError(path_, "materials", "expected an object");
  if (index >= MaterialCount()) throw SceneError(path_, "materials", "no such material");
  std::string name = MaterialName(index);
  Json materials = doc_["materials"];
  Json& material = materials[name];
  bool newType = fields.contains("type") && fields["type"] != material.value("type", Json());
  if (newType) material = Json::object();
  for (const auto& [key, value] : fields.items()) material[key] = value;
  Material loaded = LoadWith(CameraJson(), materials, Json::array()).materials.at(index);
  doc_["materials"] = std::move(materials);
  return loaded;
}

SceneDocument::MovedObject SceneDocument::TranslatedObject(size_t index, vec3 delta) const {
  if (index >= ObjectCount()) throw SceneError(path_, "objects", "no such object");
  Json object = ObjectJson(index);
  const Json* transform = object.contains("transform") ? &object["transform"] : nullptr;
  object["transform"] = TranslatedTransform(transform, delta);
  SceneDesc loaded;
  try {
    loaded = LoadWith(CameraJson(), doc_["materials"], Json::array({object}));
  } catch (const SceneError& e) {  // name the object by its place in the file
    std::string message = e.what();
    size_t at = message.find("objects[0]");
    if (at != std::string::npos) message.replace(at, 10, "objects[" + std::to_string(index) + "]");
    throw SceneError(message);
  }
  return MovedObject{std::move(object), std::move(loaded)};
}

SceneDocument::MovedInstance SceneDocument::TranslatedInstance(size_t index, vec3 delta) const {
  if (index >= ObjectCount()) throw SceneError(path_, "objects", "no such object");
  const Json& object = ObjectJson(index);
  const Json* transform = object.contains("transform") ? &object["transform"] : nullptr;
  return PlacedInstance(index, TranslatedTransform(transform, delta));
}

SceneDocument::MovedInstance SceneDocument::PlacedInstance(size_t index, Json transform) const {
  if (index >= ObjectCount()) throw SceneError(path_, "objects", "no such object");
  Json object = ObjectJson(index);
  object["transform"] = std::move(transform);
  // As the loader's ParseInstance reads it: a float matrix, then checked in double.
  std::string field = "objects[" + std::to_string(index) + "].transform";
  glm::dmat4 toWorld(ParseTransform(JsonObject(JsonValue(object["transform"], field, path_))));
  std::string why;
  if (!ValidInstanceTransform(toWorld, &why)) throw SceneError(path_, field, why);
  return MovedInstance{std::move(object), toWorld};
}

void SceneDocument::SetRenderSetting(const std::string& key, int64_t value) {
  if (key != "max_depth" && key != "spp") throw SceneError(path_, "render", "cannot set " + key);
  Json render = doc_["render"];
  render[key] = value;
  Json mini = Json::object();
  mini["render"] = render;
  mini["camera"] = CameraJson();
  mini["materials"] = Json::object();
  mini["objects"] = Json::array();
  LoadSceneFromString(mini.dump(), path_, baseDir_);  // the loader's limits
  doc_["render"] = std::move(render);
}

std::string SceneDocument::Text() const { return doc_.dump(2) + "\n"; }

Json TranslatedTransform(const Json* transform, vec3 delta) {
  Json t = transform ? *transform : Json::object();
  if (!t.is_object()) return t;  // the loader refuses it with its own message
  if (t.contains("matrix") && t["matrix"].is_array() && t["matrix"].size() == 16) {
    for (int row = 0; row < 3; ++row) {
      Json& entry = t["matrix"][size_t(row * 4 + 3)];
      if (entry.is_number()) entry = entry.get<double>() + double(delta[row]);
    }
    return t;
  }
  Json translate = t.contains("translate") ? t["translate"] : Json::array({0.0, 0.0, 0.0});
  if (translate.is_array() && translate.size() == 3) {
    for (int axis = 0; axis < 3; ++axis) {
      Json& entry = translate[size_t(axis)];
      if (entry.is_number()) entry = entry.get<double>() + double(delta[axis]);
    }
  }
  t["translate"] = translate;
  return t;
}

}  // namespace pt
