#include "src/server/scene_document.h"

#include <charconv>
#include <cstdlib>
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
  // A bare file name's folder is empty: the working directory.
  std::string base = baseDir.empty() ? "." : baseDir;
  LoadSceneFromString(text, path_, base);  // the full check
  doc_ = ParseSceneJson(text, path_);
  baseDir_ = fs::absolute(fs::path(base)).lexically_normal().string();
  doc_["render"] = RenderSection(render);  // overrides applied, adaptive dropped
  if (!doc_.contains("materials")) doc_["materials"] = Json::object();
  MakePathsAbsolute();
  sceneLighting_ = Json::object();
  for (const char* key : {"background", "environment"}) {
    if (doc_.contains(key)) sceneLighting_[key] = doc_[key];
  }
}

// Relative paths (meshes, maps, a camera's file) made absolute, so Text() renders from any
// folder.
void SceneDocument::MakePathsAbsolute() {
  auto absolute = [&](Json& entry, const char* key) {
    if (!entry.is_object() || !entry.contains(key) || !entry[key].is_string()) return;
    fs::path file = entry[key].get<std::string>();
    if (file.is_relative()) entry[key] = (fs::path(baseDir_) / file).lexically_normal().string();
  };
  for (Json& object : doc_["objects"]) {
    if (object.value("type", "") == "mesh") absolute(object, "file");
  }
  if (doc_.contains("meshes")) {
    for (Json& mesh : doc_["meshes"]) absolute(mesh, "file");
  }
  if (doc_.contains("environment")) absolute(doc_["environment"], "file");
  if (doc_.contains("camera")) absolute(doc_["camera"], "from_file");
}

SceneDocument SceneDocument::ForModel(const std::string& path, const SceneDesc& loaded,
                                      const LoadOptions& options) {
  SceneDocument d;
  d.path_ = path;
  fs::path file = fs::absolute(fs::path(path)).lexically_normal();
  d.baseDir_ = file.parent_path().string();
  Json mesh = {{"type", "mesh"}, {"file", file.string()}};
  if (!options.animation.empty()) mesh["animation"] = options.animation;
  if (options.time) mesh["time"] = *options.time;
  if (!options.variant.empty()) mesh["variant"] = options.variant;
  d.doc_ = Json::object();
  d.doc_["format"] = 1;
  d.doc_["render"] = RenderSection(loaded.render);
  d.doc_["camera"] = CameraDescJson(loaded.camera);
  d.doc_["materials"] = Json::object();
  d.doc_["objects"] = Json::array({mesh});
  d.sceneLighting_ = Json::object();
  d.AdoptLighting(loaded);  // the loader's default environment, or --env's map
  return d;
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

CameraDesc SceneDocument::EditCamera(const Json& fields, bool replace) {
  if (!fields.is_object()) throw SceneError(path_, "camera", "expected an object");
  Json camera = replace ? Json::object() : CameraJson();
  for (const auto& [key, value] : fields.items()) camera[key] = value;
  CameraDesc loaded = LoadWith(camera, doc_["materials"], Json::array()).camera;
  doc_["camera"] = camera;
  return loaded;
}

void SceneDocument::ResolveCamera(const CameraDesc& resolved) {
  const Json& camera = CameraJson();
  if (camera.is_object() && camera.contains("position") && camera.contains("look_at")) return;
  doc_["camera"] = CameraDescJson(resolved);
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

double DocumentFloat(float v) {
  char text[32];
  auto end = std::to_chars(text, text + sizeof(text), v).ptr;
  return std::strtod(std::string(text, end).c_str(), nullptr);
}

Json DocumentVec3(vec3 v) {
  return Json::array({DocumentFloat(v.x), DocumentFloat(v.y), DocumentFloat(v.z)});
}

Json CameraDescJson(const CameraDesc& c) {
  Json camera = {{"position", DocumentVec3(c.position)}, {"look_at", DocumentVec3(c.lookAt)},
                 {"up", DocumentVec3(c.up)}, {"fov_y", DocumentFloat(c.fovY)}};
  if (c.apertureRadius > 0.0f) {
    camera["aperture_radius"] = DocumentFloat(c.apertureRadius);
    camera["focus_distance"] = DocumentFloat(c.focusDistance);
  }
  return camera;
}

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
