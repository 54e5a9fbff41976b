#include "src/io/scene_loader.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

#include "src/geometry/box.h"
#include "src/io/environment_loader.h"
#include "src/io/gltf_loader.h"
#include "src/io/gltf_variants.h"
#include "src/io/image_io.h"
#include "src/io/media_json.h"
#include "src/io/model_scene.h"
#include "src/io/scene_json.h"
#include "src/scene/instances.h"
#include "src/scene/transform.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

constexpr int64_t kFormatVersion = 1;
constexpr int64_t kMaxPixels = int64_t(1) << 26;  // 8192 x 8192
constexpr int64_t kMaxSpp = int64_t(1) << 24;
constexpr int64_t kMaxSeed = 0xffffffffll;

// An entry of the "meshes" table: its JSON, and its SceneDesc::meshes index once loaded.
struct MeshEntry {
  JsonObject json;
  int64_t mesh = -1;
};

// Everything a parse step needs besides the JSON: the scene being filled and name lookups.
struct LoadState {
  const std::string& file;
  std::string baseDir;
  SceneDesc& scene;
  std::unordered_map<std::string, uint32_t> materials;
  std::string skippedByFile;  // "a.glb (2), b.obj (1)" for the one degenerate-triangle warning
  std::map<std::string, MeshEntry> meshTable;
  const LoadOptions* options = nullptr;  // the command line's choices
  std::string variant;  // --variant (LoadOptions::variant)
  // "mesh" objects still to load, by their "file" string: a file placed again and again (a
  // scene of copies) reserves room for all of them after its first load.
  std::unordered_map<std::string, size_t> placementsLeft;
};

AdaptiveSettings ParseAdaptive(const JsonObject& a, int64_t spp) {
  a.AllowOnly({"tolerance", "min_spp", "batch"}, "render.adaptive");
  AdaptiveSettings s;
  s.enabled = true;
  s.tolerance = a.Number("tolerance", Range{0.0, 1.0, true, false});
  int64_t minSpp = a.Integer("min_spp", 1, kMaxSpp);
  if (minSpp > spp) {
    a.Fail("min_spp", std::to_string(minSpp) + " exceeds render.spp (" + std::to_string(spp) +
                          "), the per-pixel maximum");
  }
  s.minSpp = int(minSpp);
  s.batch = int(a.Integer("batch", 1, kMaxSpp));
  return s;
}

RenderSettings ParseRender(const JsonObject& r) {
  r.AllowOnly({"width", "height", "spp", "max_depth", "seed", "russian_roulette_depth", "adaptive",
               "sampler"},
              "render");
  RenderSettings s;
  int64_t width = r.Integer("width", 1, kMaxPixels);
  int64_t height = r.Integer("height", 1, kMaxPixels);
  if (width * height > kMaxPixels) {
    r.Fail("width", std::to_string(width) + " x " + std::to_string(height) +
                        " pixels is too large (at most " + std::to_string(kMaxPixels) + " pixels)");
  }
  s.width = int(width);
  s.height = int(height);
  s.spp = int(r.Integer("spp", 1, kMaxSpp));
  s.maxDepth = int(r.Integer("max_depth", 0, kMaxBounces));
  s.seed = uint32_t(r.IntegerOr("seed", 0, 0, kMaxSeed));
  s.russianRouletteDepth = int(r.IntegerOr("russian_roulette_depth", 3, 0, kMaxBounces));
  if (r.Has("adaptive")) s.adaptive = ParseAdaptive(r.Object("adaptive"), s.spp);
  if (r.Has("sampler")) {
    std::string sampler = r.String("sampler");
    if (sampler != "independent" && sampler != "sobol")
      r.Fail("sampler", "'" + sampler + "' is not a sampler (independent or sobol)");
    s.sampler = sampler == "sobol" ? SamplerKind::kSobol : SamplerKind::kIndependent;
  }
  return s;
}

std::string FormatVec3(vec3 v) {
  std::string s = "[";  // appended piecewise: "[" + ... trips a GCC 12 -Wrestrict false positive
  return s.append(FormatNumber(v.x)).append(", ").append(FormatNumber(v.y)).append(", ")
      .append(FormatNumber(v.z)).append("]");
}

CameraDesc ParseCamera(const JsonObject& c) {
  c.AllowOnly({"position", "look_at", "up", "fov_y", "aperture_radius", "focus_distance"},
              "the camera");
  CameraDesc cam;
  cam.position = c.Vec3("position");
  cam.lookAt = c.Vec3("look_at");
  cam.up = c.Vec3Or("up", vec3(0.0f, 1.0f, 0.0f));
  cam.fovY = c.Number("fov_y", Range{0.0, 180.0, true, true});
  cam.apertureRadius = c.NumberOr("aperture_radius", 0.0f, Range::NonNegative());
  glm::dvec3 forward = glm::dvec3(cam.lookAt) - glm::dvec3(cam.position);
  if (!(glm::length(forward) > 0.0)) c.Fail("look_at", "equals camera.position: no view direction");
  if (!(glm::length(glm::dvec3(cam.up)) > 0.0)) c.Fail("up", "must not be the zero vector");
  double sine = glm::length(glm::cross(glm::normalize(forward), glm::normalize(glm::dvec3(cam.up))));
  if (!(sine > 1e-6)) {
    c.Fail("up", FormatVec3(cam.up) + " is parallel to the view direction (look_at - position)");
  }
  cam.focusDistance = c.NumberOr("focus_distance", float(glm::length(forward)), Range::Positive());
  return cam;
}

// ---- Materials ------------------------------------------------------------------------------

Material ParseMaterial(const JsonObject& m) {
  std::string type = m.String("type");
  Material mat;
  if (type == "diffuse") {
    m.AllowOnly({"type", "albedo"}, "a diffuse material");
    mat.type = MaterialType::kDiffuse;
    mat.albedo = m.Vec3("albedo", Range::Unit());
  } else if (type == "emissive") {
    m.AllowOnly({"type", "radiance", "two_sided"}, "an emissive material");
    mat.type = MaterialType::kEmissive;
    mat.radiance = m.Vec3("radiance", Range::NonNegative());
    mat.twoSided = m.BoolOr("two_sided", false) ? 1u : 0u;
  } else if (type == "conductor") {
    m.AllowOnly({"type", "albedo", "roughness"}, "a conductor material");
    mat.type = MaterialType::kConductor;
    mat.albedo = m.Vec3("albedo", Range::Unit());
    mat.roughness = m.NumberOr("roughness", 0.0f, Range::Unit());
  } else if (type == "dielectric") {
    m.AllowOnly({"type", "ior", "roughness", "absorption"}, "a dielectric material");
    mat.type = MaterialType::kDielectric;
    mat.ior = m.Number("ior", Range::Positive());
    mat.roughness = m.NumberOr("roughness", 0.0f, Range::Unit());
    mat.absorption = m.Vec3Or("absorption", vec3(0.0f), Range::NonNegative());
  } else if (type == "plastic") {
    m.AllowOnly({"type", "albedo", "ior", "roughness"}, "a plastic material");
    mat.type = MaterialType::kPlastic;
    mat.albedo = m.Vec3("albedo", Range::Unit());
    mat.ior = m.Number("ior", Range::Positive());
    mat.roughness = m.NumberOr("roughness", 0.0f, Range::Unit());
  } else {
    m.Fail("type", "unknown material type \"" + type +
                       "\" (expected diffuse, emissive, conductor, dielectric or plastic)");
  }
  return mat;
}

void ParseMaterials(const JsonObject& root, LoadState& state) {
  JsonValue all = root.Field("materials");
  JsonObject materials(all);
  if (all.Raw().size() > kMaxMaterials)
    materials.FailHere(std::to_string(all.Raw().size()) + " materials; at most " +
                       std::to_string(kMaxMaterials) + " are supported");
  for (const auto& item : all.Raw().items()) {
    JsonObject m(JsonValue(item.value(), materials.FieldPath(item.key()), state.file));
    if (item.key() == kInterfaceMaterialName)
      materials.Fail(item.key(), "\"interface\" is reserved: the invisible surface of a "
                                 "medium's bounds (docs/scene-format.md)");
    state.materials[item.key()] = uint32_t(state.scene.materials.size());
    state.scene.materials.push_back(ParseMaterial(m));
    state.scene.materialNames.push_back(item.key());
  }
}

uint32_t MaterialRef(const JsonObject& o, LoadState& state) {
  std::string name = o.String("material");
  if (name == kInterfaceMaterialName) return InterfaceMaterial(state.scene);
  auto it = state.materials.find(name);
  if (it == state.materials.end()) {
    std::string defined;
    for (const std::string& n : state.scene.materialNames) defined += (defined.empty() ? "" : ", ") + n;
    o.Fail("material", "undefined material \"" + name + "\" (defined: " +
                           (defined.empty() ? "none" : defined) + ")");
  }
  return it->second;
}

// ---- Objects --------------------------------------------------------------------------------

// The object's medium interface ("interior", "exterior"; the "interface" material).
uint32_t ObjectInterior(const JsonObject& o, LoadState& state) {
  bool invisible = o.Has("material") && o.String("material") == kInterfaceMaterialName;
  return ParseObjectInterior(o, state.scene, invisible);
}

// Objects that cannot bound a medium must not take the invisible "interface" material.
void RefuseInterface(const JsonObject& o, const char* why) {
  if (o.Has("material") && o.String("material") == kInterfaceMaterialName)
    o.Fail("material", std::string("\"interface\" surfaces bound media, and ") + why);
}

glm::mat4 ObjectTransform(const JsonObject& o) {
  return o.Has("transform") ? ParseTransform(o.Object("transform")) : glm::mat4(1.0f);
}

void ParseSphere(const JsonObject& o, LoadState& state) {
  o.AllowOnly({"type", "center", "radius", "material", "transform", "interior", "exterior"},
              "a sphere");
  vec3 center = o.Vec3("center");
  float radius = o.Number("radius", Range::Positive());
  uint32_t material = MaterialRef(o, state);
  glm::mat4 m = ObjectTransform(o);
  float scale = 1.0f;
  if (!UniformScaleOf(m, &scale)) {
    JsonObject t = o.Object("transform");
    t.Fail(t.Has("scale") ? "scale" : "matrix",
           "a sphere accepts only a uniform scale (the same factor on every axis)");
  }
  Sphere s{vec3(m * vec4(center, 1.0f)), radius * scale};
  vec3 reach = Abs(s.center) + vec3(s.radius);  // intersection squares |o - c| and r
  if (!IsFinite(s.center) || !(s.radius > 0.0f) || !std::isfinite(s.radius) ||
      !std::isfinite(glm::dot(reach, reach))) {
    o.Fail("radius", "the transformed sphere is degenerate or not finite");
  }
  state.scene.spheres.push_back(s);
  state.scene.sphereMaterials.push_back(material);
  SetShapeInterfaces(o, ShapeType::kSphere, state.scene.spheres.size() - 1,
                     state.scene.spheres.size(), ObjectInterior(o, state), state.scene);
}

void ParseQuad(const JsonObject& o, LoadState& state) {
  if (o.Has("interior"))
    o.Fail("interior", "a quad encloses no volume: bound a medium with a box, a sphere or a "
                       "closed mesh");
  o.AllowOnly({"type", "origin", "u", "v", "material", "transform"}, "a quad");
  RefuseInterface(o, "a quad encloses no volume");
  vec3 origin = o.Vec3("origin"), u = o.Vec3("u"), v = o.Vec3("v");
  uint32_t material = MaterialRef(o, state);
  glm::mat4 m = ObjectTransform(o);
  Quad q{vec3(m * vec4(origin, 1.0f)), vec3(m * vec4(u, 0.0f)), vec3(m * vec4(v, 0.0f))};
  vec3 n = glm::cross(q.u, q.v);
  if (!IsFinite(q.origin) || !(glm::dot(n, n) > 0.0f) || !std::isfinite(glm::dot(n, n))) {
    o.Fail("v", "u and v are parallel, zero or not finite: the quad has no area");
  }
  state.scene.quads.push_back(q);
  state.scene.quadMaterials.push_back(material);
}

void ParseBox(const JsonObject& o, LoadState& state) {
  o.AllowOnly({"type", "min", "max", "material", "transform", "interior", "exterior"}, "a box");
  vec3 lo = o.Vec3("min"), hi = o.Vec3("max");
  if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) {
    o.Fail("max", FormatVec3(hi) + " must exceed min " + FormatVec3(lo) + " on every axis");
  }
  uint32_t material = MaterialRef(o, state);
  size_t before = state.scene.quads.size();
  AppendBoxQuads(lo, hi, ObjectTransform(o), state.scene.quads);
  state.scene.quadMaterials.resize(state.scene.quads.size(), material);
  if (state.scene.quads.size() - before != 6) o.FailHere("the transformed box is degenerate");
  SetShapeInterfaces(o, ShapeType::kQuad, before, state.scene.quads.size(),
                     ObjectInterior(o, state), state.scene);
}

// The mesh file o's "file" names, resolved against the scene's folder: a supported format and
// an existing file, or an error naming that field.
fs::path ResolveMeshFile(const JsonObject& o, const LoadState& state) {
  std::string file = o.String("file");
  if (!IsModelFile(file)) {
    o.Fail("file", "unsupported mesh format \"" + LowerExtension(file) + "\" in \"" + file +
                       "\" (expected .gltf, .glb or .obj)");
  }
  fs::path resolved = fs::path(file).is_absolute() ? fs::path(file) : fs::path(state.baseDir) / file;
  std::error_code ec;
  if (!fs::is_regular_file(resolved, ec)) {
    o.Fail("file", "cannot open \"" + resolved.string() + "\": no such file");
  }
  return resolved;
}

// Loads that file into the sink, with the file's own lights when lightsFromFile; errors name the
// field.
void LoadMeshFile(const JsonObject& o, LoadState& state, MeshSink& sink, bool lightsFromFile) {
  fs::path resolved = ResolveMeshFile(o, state);
  std::string file = o.String("file");
  SceneDesc& scene = state.scene;
  size_t trianglesBefore = scene.triangles.size();
  int skippedBefore = scene.skippedDegenerateTriangles;
  GltfSceneContents contents;
  bool own = o.Has("variant");
  sink.SetVariant(own ? o.String("variant") : state.variant);
  try {
    contents = LoadModelFile(resolved.string(), sink, AnimationChoice(*state.options, &o));
  } catch (const GltfVariantError& e) {
    std::string what = "\"" + resolved.string() + "\": " + e.what();
    if (own) o.Fail("variant", what);
    throw SceneError(state.file, "--variant", what);
  } catch (const std::runtime_error& e) {
    o.Fail("file", "\"" + resolved.string() + "\": " + e.what());
  }
  if (lightsFromFile) AddGltfLights(contents, scene);
  std::string summary = GltfSceneSummary(file, contents);
  if (!summary.empty()) scene.warnings.push_back(summary);
  int skipped = scene.skippedDegenerateTriangles - skippedBefore;
  if (skipped > 0) {
    state.skippedByFile += (state.skippedByFile.empty() ? "" : ", ") + file + " (" +
                           std::to_string(skipped) + ")";
  }
  if (scene.triangles.size() == trianglesBefore) sink.Warn("the mesh has no triangles");
}

// After a load of `file` that added `added` triangles: room for as many again per placement of
// the file still to come (the same file gives the same triangles; a guess otherwise, which
// only sizes the arrays' capacity).
void ReserveForPlacements(const std::string& file, size_t added, LoadState& state) {
  auto it = state.placementsLeft.find(file);
  if (it == state.placementsLeft.end() || it->second == 0) return;
  size_t left = --it->second;
  if (left > 0 && added > 0)
    ReserveTriangles(state.scene, state.scene.triangles.size() + left * added);
}

// The count of "mesh" objects per "file" string (ill-formed entries skipped: the loader's own
// checks report them in order).
std::unordered_map<std::string, size_t> CountPlacements(const Json& json) {
  std::unordered_map<std::string, size_t> count;
  const auto objects = json.find("objects");
  if (objects == json.end() || !objects->is_array()) return count;
  for (const Json& o : *objects) {
    if (!o.is_object() || !o.contains("type") || !o.contains("file")) continue;
    if (o["type"] == "mesh" && o["file"].is_string()) ++count[o["file"].get<std::string>()];
  }
  return count;
}

void ParseMesh(const JsonObject& o, LoadState& state) {
  o.AllowOnly({"type", "file", "material", "transform", "lights_from_file", "animation", "time",
               "variant", "interior", "exterior"},
              "a mesh");
  int64_t material = o.Has("material") ? int64_t(MaterialRef(o, state)) : -1;
  bool lightsFromFile = o.BoolOr("lights_from_file", true);
  uint32_t iface = ObjectInterior(o, state);
  MeshSink sink(state.scene, glm::dmat4(ObjectTransform(o)), material, o.String("file"));
  if (iface) sink.DisallowInstances();  // the interface is kept per world-space triangle
  size_t first = state.scene.triangles.size();
  LoadMeshFile(o, state, sink, lightsFromFile);
  ReserveForPlacements(o.String("file"), state.scene.triangles.size() - first, state);
  SetShapeInterfaces(o, ShapeType::kTriangle, first, state.scene.triangles.size(), iface,
                     state.scene);
}

// ---- Instancing: the "meshes" table and "instance" objects ---------------------------------

// Checks every entry of "meshes" (fields, file, material, transform) without loading it yet: a
// mesh is loaded when first placed, and one never placed is not loaded at all.
void ParseMeshTable(const JsonObject& root, LoadState& state) {
  if (!root.Has("meshes")) return;
  JsonValue all = root.Field("meshes");
  JsonObject meshes(all);
  for (const auto& item : all.Raw().items()) {
    JsonObject m(JsonValue(item.value(), meshes.FieldPath(item.key()), state.file));
    m.AllowOnly({"file", "material", "transform", "animation", "time", "variant"},
                "a mesh of the mesh table");
    RefuseInterface(m, "instanced meshes cannot bound media (use a \"mesh\" object)");
    if (m.Has("material")) MaterialRef(m, state);
    if (m.Has("transform")) ParseTransform(m.Object("transform"));
    ResolveMeshFile(m, state);
    state.meshTable.emplace(item.key(), MeshEntry{m, -1});
  }
}

// The scene mesh of a table entry, loaded into its own space on first use.
uint32_t TableMesh(const JsonObject& o, LoadState& state) {
  std::string name = o.String("mesh");
  auto it = state.meshTable.find(name);
  if (it == state.meshTable.end()) {
    std::string defined;
    for (const auto& [key, entry] : state.meshTable) defined += (defined.empty() ? "" : ", ") + key;
    o.Fail("mesh", "undefined mesh \"" + name + "\" (the top-level \"meshes\" defines: " +
                       (defined.empty() ? "none" : defined) + ")");
  }
  MeshEntry& entry = it->second;
  if (entry.mesh >= 0) return uint32_t(entry.mesh);
  const JsonObject& m = entry.json;
  SceneDesc& scene = state.scene;
  int64_t material = m.Has("material") ? int64_t(MaterialRef(m, state)) : -1;
  MeshSink sink(scene, glm::dmat4(ObjectTransform(m)), material, m.String("file"));
  sink.DisallowInstances();  // two levels: a file's own reuse is flattened into the mesh
  uint32_t first = uint32_t(scene.triangles.size());
  LoadMeshFile(m, state, sink, /*lightsFromFile=*/false);  // one placement could not carry them
  uint32_t count = uint32_t(scene.triangles.size()) - first;
  if (count == 0) m.Fail("file", "\"" + m.String("file") + "\" has no triangles to place");
  entry.mesh = int64_t(scene.meshes.size());
  scene.meshes.push_back(MeshDesc{name, first, count});
  return uint32_t(entry.mesh);
}

void ParseInstance(const JsonObject& o, LoadState& state) {
  o.AllowOnly({"type", "mesh", "material", "transform"}, "an instance");
  RefuseInterface(o, "instances cannot bound media (use a \"mesh\" object)");
  InstanceDesc instance;
  instance.mesh = TableMesh(o, state);
  instance.material = o.Has("material") ? int32_t(MaterialRef(o, state)) : -1;
  instance.toWorld = glm::dmat4(ObjectTransform(o));
  std::string why;
  if (!ValidInstanceTransform(instance.toWorld, &why)) o.Fail("transform", why);
  state.scene.instances.push_back(instance);
}

void WarnUnplacedMeshes(const LoadState& state) {
  for (const auto& [name, entry] : state.meshTable) {
    if (entry.mesh < 0)
      state.scene.warnings.push_back(state.file + ": meshes." + name + " is never placed (not loaded)");
  }
}

void ParseObjects(const JsonObject& root, LoadState& state) {
  JsonValue objects = root.Field("objects");
  size_t count = objects.ArraySize();
  for (size_t i = 0; i < count; ++i) {
    JsonObject o(objects.Element(i));
    std::string type = o.String("type");
    if (type == "sphere") {
      ParseSphere(o, state);
    } else if (type == "quad") {
      ParseQuad(o, state);
    } else if (type == "box") {
      ParseBox(o, state);
    } else if (type == "mesh") {
      ParseMesh(o, state);
    } else if (type == "instance") {
      ParseInstance(o, state);
    } else if (type == "volume") {
      ParseVolumeObject(o, state.scene);
    } else {
      o.Fail("type", "unknown object type \"" + type +
                         "\" (expected sphere, quad, box, mesh, instance or volume)");
    }
  }
}

// Angles in degrees, as everywhere in the format; stored in radians.
SpotLightDesc ParseSpotLight(const JsonObject& l) {
  l.AllowOnly({"type", "position", "direction", "intensity", "inner_angle", "outer_angle"},
              "a spot light");
  SpotLightDesc s;
  s.position = l.Vec3("position");
  vec3 direction = l.Vec3("direction");
  if (!(glm::length(glm::dvec3(direction)) > 0.0)) l.Fail("direction", "must not be the zero vector");
  s.direction = glm::normalize(direction);
  s.intensity = l.Vec3("intensity", Range::NonNegative());
  float inner = l.NumberOr("inner_angle", 0.0f, Range{0.0, 90.0, false, true});
  float outer = l.NumberOr("outer_angle", 45.0f, Range{0.0, 90.0, true, false});
  if (!(inner < outer)) {
    l.Fail("inner_angle", FormatNumber(inner) + " must be less than outer_angle (" +
                              FormatNumber(outer) + ")");
  }
  s.innerAngle = float(double(inner) * M_PI / 180.0);
  s.outerAngle = float(double(outer) * M_PI / 180.0);
  return s;
}

void ParseLights(const JsonObject& root, LoadState& state) {
  if (!root.Has("lights")) return;
  JsonValue lights = root.Field("lights");
  size_t count = lights.ArraySize();
  for (size_t i = 0; i < count; ++i) {
    JsonObject l(lights.Element(i));
    std::string type = l.String("type");
    if (type == "directional") {
      state.scene.directionalLights.push_back(ParseDirectionalLight(l));
      continue;
    }
    if (type == "spot") {
      state.scene.spotLights.push_back(ParseSpotLight(l));
      continue;
    }
    if (type != "point") {
      l.Fail("type", "unknown light type \"" + type + "\" (expected point, spot or directional)");
    }
    l.AllowOnly({"type", "position", "intensity"}, "a point light");
    state.scene.pointLights.push_back(
        PointLightDesc{l.Vec3("position"), l.Vec3("intensity", Range::NonNegative())});
  }
}

void CheckFormat(const JsonObject& root) {
  int64_t format = root.IntegerOr("format", kFormatVersion, INT32_MIN, INT32_MAX);
  if (format > kFormatVersion) {
    root.Fail("format", "format " + std::to_string(format) +
                            " is newer than this renderer reads (format 1): update the renderer");
  }
  if (format < 1) root.Fail("format", std::to_string(format) + " is not a format version (use 1)");
}

}  // namespace

SceneDesc LoadSceneFromString(const std::string& text, const std::string& pathForMessages,
                              const std::string& baseDir, const LoadOptions& options) {
  Json json = ParseSceneJson(text, pathForMessages);
  JsonObject root(JsonValue(json, "", pathForMessages));
  CheckFormat(root);  // first: a later format may have fields this one does not know
  root.AllowOnly({"format", "render", "camera", "background", "environment", "materials",
                  "meshes", "objects", "lights", "media", "medium"},
                 "the scene");
  SceneDesc scene;
  scene.path = pathForMessages;
  LoadState state{pathForMessages, baseDir.empty() ? std::string(".") : baseDir, scene, {}, {},
                  {}, &options, options.variant, CountPlacements(json)};
  scene.render = ParseRender(root.Object("render"));
  JsonObject camera = root.Object("camera");
  if (camera.Has("from_file")) {
    scene.camera = ParseCameraFromFile(camera, state.baseDir, options);
  } else if (!options.camera.empty()) {
    camera.FailHere("--camera picks a camera of a glTF file, and this camera is given in the "
                    "scene (take one from a file with \"camera\": {\"from_file\": ...})");
  } else {
    scene.camera = ParseCamera(camera);
  }
  scene.background = root.Vec3Or("background", vec3(0.0f), Range::NonNegative());
  if (root.Has("environment")) {
    if (root.Has("background")) {
      root.Fail("environment", "give either background (a constant) or environment, not both");
    }
    ParseEnvironment(root.Object("environment"), state.baseDir, scene);
  }
  ParseMaterials(root, state);
  ParseSceneMedia(root, state.baseDir, scene);
  ParseMeshTable(root, state);
  ParseObjects(root, state);
  WarnUnplacedMeshes(state);
  ParseLights(root, state);
  if (scene.skippedDegenerateTriangles > 0) {
    scene.warnings.push_back("skipped " + std::to_string(scene.skippedDegenerateTriangles) +
                             " degenerate triangles (zero area or non-finite vertices) in " +
                             state.skippedByFile);
  }
  return scene;
}

// The files of the scene's "objects" and "meshes" entries, to parse ahead (none when the text
// is not a scene the loader would read: its own errors name the field). Through the loader's
// depth-limited parser: a deeply nested document must not overflow a recursive walk.
static std::vector<std::string> TopLevelMeshFiles(const std::string& text,
                                                  const std::string& path,
                                                  const std::string& baseDir) {
  std::vector<std::string> files;
  try {
    const Json json = ParseSceneJson(text, path);
    for (const char* table : {"objects", "meshes"}) {
      const auto it = json.find(table);
      if (it == json.end()) continue;
      for (const Json& entry : *it) {
        if (!entry.is_object() || !entry.contains("file") || !entry["file"].is_string()) continue;
        const fs::path file(entry["file"].get<std::string>());
        files.push_back(file.is_absolute() ? file.string() : (fs::path(baseDir) / file).string());
      }
    }
  } catch (const std::exception&) {
    files.clear();
  }
  return files;
}

SceneDesc LoadScene(const std::string& path, const LoadOptions& options) {
  if (IsModelFile(path)) return LoadModelScene(path, options);
  std::error_code ec;
  if (!fs::exists(path, ec)) throw SceneError(path, "", "cannot open the scene file: no such file");
  if (fs::is_directory(path, ec)) throw SceneError(path, "", "is a folder, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path, "", std::string("cannot open the scene file: ") + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw SceneError(path, "", "cannot read the scene file");
  std::string baseDir = fs::path(path).parent_path().string();
  // The scene's glTF files parse on threads of their own while the loader reads the scene;
  // each file once, however often it is placed.
  GltfParseCache parses;
  parses.Prefetch(TopLevelMeshFiles(text.str(), path, baseDir));
  return LoadSceneFromString(text.str(), path, baseDir, options);
}

}  // namespace pt
