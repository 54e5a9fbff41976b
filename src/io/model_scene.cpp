#include "src/io/model_scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "src/io/gltf_loader.h"
#include "src/io/gltf_variants.h"
#include "src/io/image_io.h"
#include "src/io/obj_loader.h"
#include "src/materials/emission.h"
#include "src/io/scene_json.h"
#include "src/scene/auto_camera.h"
#include "src/scene/transform.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxModelSceneSide = 8192;

void CheckRegularFile(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw SceneError(path, "", "cannot open the file: no such file");
  if (!fs::is_regular_file(path, ec)) throw SceneError(path, "", "is not a regular file");
}

// Whether any material a triangle uses emits light (then the model is not unlit).
bool AnyEmitter(const SceneDesc& scene) {
  std::vector<bool> used(scene.materials.size(), false);
  for (uint32_t m : scene.triangleMaterials) {
    if (m < used.size()) used[m] = true;
  }
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    if (used[i] && MaterialEmits(m)) return true;
  }
  return false;
}

// What lights the model besides the default environment, for the summary line.
std::string DefaultEnvironmentNote(size_t lightCount, bool emitters) {
  std::string own;
  if (lightCount > 0) own = std::to_string(lightCount) + (lightCount == 1 ? " light" : " lights");
  if (emitters) own += std::string(own.empty() ? "" : " and ") + "emissive materials";
  return "lit by the default environment, a uniform radiance of " +
         FormatNumber(kDefaultEnvironmentRadiance) + " from every direction" +
         (own.empty() ? "" : ", and by the file's " + own) +
         " (--env FILE replaces the environment, --env none removes it)";
}

RenderSettings ModelRenderSettings(float aspect) {
  RenderSettings r;
  r.aspect = aspect > 0.0f ? aspect : kModelSceneAspect;
  r.height = kModelSceneHeight;
  long width = std::lround(double(kModelSceneHeight) * double(r.aspect));
  r.width = int(std::clamp(width, 1L, long(kMaxModelSceneSide)));
  r.spp = kModelSceneSpp;
  r.maxDepth = kModelSceneMaxDepth;
  return r;
}

}  // namespace

bool IsModelFile(const std::string& path) {
  std::string ext = LowerExtension(path);
  return ext == ".gltf" || ext == ".glb" || ext == ".obj";
}

void AddGltfLights(const GltfSceneContents& contents, SceneDesc& scene) {
  scene.pointLights.insert(scene.pointLights.end(), contents.pointLights.begin(),
                           contents.pointLights.end());
  scene.spotLights.insert(scene.spotLights.end(), contents.spotLights.begin(),
                          contents.spotLights.end());
  scene.directionalLights.insert(scene.directionalLights.end(),
                                 contents.directionalLights.begin(),
                                 contents.directionalLights.end());
}

GltfSceneContents LoadModelFile(const std::string& path, MeshSink& sink,
                                const GltfAnimationChoice& animation) {
  if (LowerExtension(path) == ".obj") {
    if (!sink.Variant().empty())
      throw GltfVariantError("no material variant \"" + sink.Variant() +
                             "\": an OBJ file has no KHR_materials_variants");
    LoadObjMesh(path, sink);
    return {};
  }
  return LoadGltfMesh(path, sink, animation);
}

GltfAnimationChoice AnimationChoice(const LoadOptions& options, const JsonObject* o) {
  GltfAnimationChoice choice;
  if (o && o->Has("animation")) {
    bool index = o->Field("animation").Raw().is_number();
    choice.animation = index ? std::to_string(o->Integer("animation", 0, INT32_MAX))
                             : o->String("animation");
    if (choice.animation.empty()) o->Fail("animation", "give an index or a name");
  }
  if (o && o->Has("time")) choice.time = double(o->Number("time"));
  if (!options.animation.empty()) choice.animation = options.animation;
  if (options.time) choice.time = options.time;
  return choice;
}

std::string GltfSceneSummary(const std::string& label, const GltfSceneContents& contents,
                             const std::vector<std::string>& notes) {
  std::string line;
  for (const std::string& note : notes) line += (line.empty() ? "" : "; ") + note;
  std::string ignored;
  for (const std::string& phrase : contents.ignored) {
    ignored += (ignored.empty() ? "" : ", ") + phrase;
  }
  if (!ignored.empty()) line += (line.empty() ? "" : "; ") + std::string("ignored: ") + ignored;
  return line.empty() ? "" : label + ": " + line;
}

SceneDesc LoadModelScene(const std::string& path, const LoadOptions& options) {
  CheckRegularFile(path);
  SceneDesc scene;
  scene.path = path;
  MeshSink sink(scene, glm::dmat4(1.0), -1, path);
  sink.SetVariant(options.variant);
  GltfSceneContents contents;
  try {
    contents = LoadModelFile(path, sink, AnimationChoice(options, nullptr));
  } catch (const GltfVariantError& e) {
    throw SceneError(path, "--variant", e.what());
  } catch (const std::runtime_error& e) {
    throw SceneError(path, "", e.what());
  }
  if (scene.triangles.empty()) {
    throw SceneError(path, "", "the default scene has no triangles to render");
  }
  const GltfCamera* camera = nullptr;
  try {
    camera = SelectGltfCamera(contents, options.camera);
  } catch (const std::runtime_error& e) {
    throw SceneError(path, "--camera", e.what());
  }
  std::vector<std::string> notes;
  scene.render = ModelRenderSettings(camera ? camera->aspectRatio : 0.0f);
  if (camera) {
    scene.camera = camera->desc;
  } else {
    scene.camera.autoFrame = true;
    scene.camera.fovY = kAutoCameraFovY;
    notes.push_back(contents.cameras.empty() ? "no camera, framed automatically"
                                             : "no perspective camera, framed automatically");
  }
  AddGltfLights(contents, scene);
  // As in every glTF viewer, the environment lights the model whatever lights the file brings
  // (those add to it); the command line's --env replaces or (--env none) removes it.
  if (!options.environmentGiven) {
    scene.background = vec3(kDefaultEnvironmentRadiance);
    notes.push_back(DefaultEnvironmentNote(contents.LightCount(), AnyEmitter(scene)));
  }
  std::string summary = GltfSceneSummary(path, contents, notes);
  if (!summary.empty()) scene.warnings.push_back(summary);
  if (scene.skippedDegenerateTriangles > 0) {
    scene.warnings.push_back("skipped " + std::to_string(scene.skippedDegenerateTriangles) +
                             " degenerate triangles (zero area or non-finite vertices) in " + path);
  }
  return scene;
}

CameraDesc ParseCameraFromFile(const JsonObject& c, const std::string& baseDir,
                               const LoadOptions& options) {
  c.AllowOnly({"from_file", "name", "index", "transform", "fov_y", "aperture_radius",
               "focus_distance", "animation", "time"},
              "a camera from a file");
  const std::string& selector = options.camera;
  GltfAnimationChoice animation = AnimationChoice(options, &c);
  std::string file = c.String("from_file");
  if (LowerExtension(file) != ".gltf" && LowerExtension(file) != ".glb") {
    c.Fail("from_file", "\"" + file + "\" is not a glTF file (.gltf or .glb): only glTF has cameras");
  }
  if (c.Has("name") && c.Has("index")) c.Fail("index", "give name or index, not both");
  std::string pick = selector;
  if (pick.empty() && c.Has("name")) pick = c.String("name");
  if (pick.empty() && c.Has("index")) pick = std::to_string(c.Integer("index", 0, INT32_MAX));
  fs::path resolved = fs::path(file).is_absolute() ? fs::path(file) : fs::path(baseDir) / file;
  std::error_code ec;
  if (!fs::is_regular_file(resolved, ec)) {
    c.Fail("from_file", "cannot open \"" + resolved.string() + "\": no such file");
  }
  CameraDesc camera;
  try {
    GltfSceneContents contents = ReadGltfSceneParts(resolved.string(), animation);
    const GltfCamera* chosen = SelectGltfCamera(contents, pick);
    if (!chosen) throw std::runtime_error("the file has no perspective camera");
    camera = chosen->desc;
  } catch (const std::runtime_error& e) {
    c.Fail(selector.empty() ? "from_file" : "--camera", "\"" + resolved.string() + "\": " + e.what());
  }
  if (c.Has("transform")) {
    glm::dmat4 m(ParseTransform(c.Object("transform")));
    glm::dvec3 position = glm::dvec3(m * glm::dvec4(glm::dvec3(camera.position), 1.0));
    glm::dvec3 forward = m * glm::dvec4(glm::dvec3(camera.lookAt - camera.position), 0.0);
    glm::dvec3 up = m * glm::dvec4(glm::dvec3(camera.up), 0.0);
    double sine = glm::length(glm::cross(glm::normalize(forward), glm::normalize(up)));
    if (!(sine > 1e-6) || !std::isfinite(glm::dot(position, position))) {
      c.Fail("transform", "leaves the camera without a view direction or up");
    }
    camera.position = vec3(position);
    camera.lookAt = vec3(position + glm::normalize(forward) * std::max(1.0, glm::length(position)));
    camera.up = vec3(up);
  }
  camera.fovY = c.NumberOr("fov_y", camera.fovY, Range{0.0, 180.0, true, true});
  camera.apertureRadius = c.NumberOr("aperture_radius", 0.0f, Range::NonNegative());
  if (camera.apertureRadius > 0.0f && !c.Has("focus_distance")) {
    c.Fail("aperture_radius", "a camera from a file needs focus_distance for depth of field");
  }
  camera.focusDistance = c.NumberOr("focus_distance", -1.0f, Range::Positive());
  return camera;
}

}  // namespace pt
