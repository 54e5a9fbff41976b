#include "src/io/gltf_scene.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "src/io/gltf_nodes.h"

namespace pt {
namespace {

constexpr double kPiD = 3.14159265358979323846;

[[noreturn]] void Fail(const std::string& what) { throw std::runtime_error(what); }

std::string Quote(const std::string& s) { return "\"" + s + "\""; }

std::string Plural(size_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// Extensions read here or by the mesh and material loaders (KHR_mesh_quantization only widens
// the accessor types, which the accessor reader takes generally). Material and texture
// extensions the material mapping cannot honour are named in its own summary line. Draco and
// meshopt data are decoded before tinygltf parses the file (src/io/gltf_document.h); WebP is
// decoded, and KHR_texture_basisu's KTX2 images are replaced by their fallback (a texture
// without one is refused there).
bool IsReadExtension(const std::string& name) {
  return name == "KHR_lights_punctual" || name == "KHR_mesh_quantization" ||
         name.rfind("KHR_materials_", 0) == 0 || name.rfind("KHR_texture_", 0) == 0 ||
         name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression" ||
         name == "KHR_meshopt_compression" || name == "EXT_texture_webp";
}

// Required extensions that are harmless when unread: none change geometry or visibility
// except the compression and image-format ones, which would leave the renderer nothing to
// read, so a file requiring any other unread extension is refused too.
bool IsReadableWhenRequired(const std::string& name) { return IsReadExtension(name); }

// A unit direction of the node's frame in world space; throws when the transform collapses it.
glm::dvec3 WorldDirection(const glm::dmat4& world, glm::dvec3 local, const std::string& part) {
  glm::dvec3 d = glm::dvec3(world * glm::dvec4(local, 0.0));
  double len = glm::length(d);
  if (!(len > 0.0) || !std::isfinite(len)) {
    Fail(part + ": its node's transform is degenerate (no direction)");
  }
  return d / len;
}

glm::dvec3 WorldPosition(const glm::dmat4& world, const std::string& part) {
  glm::dvec3 p(world[3]);
  if (!std::isfinite(glm::dot(p, p))) Fail(part + ": its node's position is not finite");
  return p;
}

class SceneReader {
 public:
  SceneReader(const tinygltf::Model& model, GltfSceneContents& out)
      : model_(model), out_(out), placed_(model.cameras.size(), false) {}

  void Visit(int index, const glm::dmat4& parent, int depth) {
    const tinygltf::Node& node = GltfNodeAt(model_, index, depth);
    glm::dmat4 world = parent * GltfLocalMatrix(node);
    if (node.camera >= 0) PlaceCamera(node, world);
    auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext != node.extensions.end()) PlaceLight(index, ext->second, world);
    for (int child : node.children) Visit(child, world, depth + 1);
  }

  size_t ignoredRanges = 0;

 private:
  void PlaceCamera(const tinygltf::Node& node, const glm::dmat4& world) {
    size_t index = size_t(node.camera);
    std::string part = "cameras[" + std::to_string(node.camera) + "]";
    if (index >= model_.cameras.size()) Fail(part + " does not exist (a node names it)");
    if (placed_[index]) return;  // the first node that places a camera wins
    placed_[index] = true;
    const tinygltf::Camera& c = model_.cameras[index];
    GltfCamera cam;
    cam.index = int(index);
    cam.name = c.name;
    cam.nodeName = node.name;
    cam.perspective = c.type == "perspective";
    if (cam.perspective) {
      double yfov = c.perspective.yfov, aspect = c.perspective.aspectRatio;
      if (!(yfov > 0.0 && yfov < kPiD)) {
        Fail(part + ".perspective.yfov: " + std::to_string(yfov) + " is outside (0, pi)");
      }
      if (!(aspect >= 0.0) || !std::isfinite(aspect)) {  // tinygltf's 0: not given
        Fail(part + ".perspective.aspectRatio: must be a number > 0");
      }
      cam.aspectRatio = float(aspect);
      cam.desc.fovY = float(yfov * 180.0 / kPiD);
    }
    // glTF cameras look down their local -Z with +Y up; scale is not part of a camera.
    glm::dvec3 position = WorldPosition(world, part);
    glm::dvec3 forward = WorldDirection(world, glm::dvec3(0, 0, -1), part);
    glm::dvec3 up = WorldDirection(world, glm::dvec3(0, 1, 0), part);
    if (!(glm::length(glm::cross(forward, up)) > 1e-6)) {
      Fail(part + ": its node's transform makes up parallel to the view direction");
    }
    // look_at one unit or |position| ahead, so the float direction keeps double accuracy.
    double reach = std::max(1.0, glm::length(position));
    cam.desc.position = vec3(position);
    cam.desc.lookAt = vec3(position + reach * forward);
    cam.desc.up = vec3(up);
    out_.cameras.push_back(cam);
  }

  void PlaceLight(int nodeIndex, const tinygltf::Value& ext, const glm::dmat4& world) {
    std::string nodePart = "nodes[" + std::to_string(nodeIndex) + "].extensions.KHR_lights_punctual";
    if (!ext.IsObject() || !ext.Has("light") || !ext.Get("light").IsNumber()) {
      Fail(nodePart + ": needs a light index");
    }
    double light = ext.Get("light").GetNumberAsDouble();
    if (!(light >= 0.0 && light < double(model_.lights.size())) || light != std::floor(light)) {
      Fail(nodePart + ".light: no light " + std::to_string(light) + " (the file has " +
           std::to_string(model_.lights.size()) + ")");
    }
    AddLight(size_t(light), world);
  }

  void AddLight(size_t index, const glm::dmat4& world) {
    const tinygltf::Light& l = model_.lights[index];
    std::string part = "KHR_lights_punctual.lights[" + std::to_string(index) + "]";
    glm::dvec3 color(1.0);
    if (!l.color.empty()) {
      if (l.color.size() != 3) Fail(part + ".color: needs 3 numbers");
      for (int c = 0; c < 3; ++c) {
        if (!(l.color[c] >= 0.0 && l.color[c] <= 1.0)) Fail(part + ".color: outside [0, 1]");
        color[c] = l.color[c];
      }
    }
    if (!(l.intensity >= 0.0) || !std::isfinite(l.intensity)) {
      Fail(part + ".intensity: must be a finite number >= 0");
    }
    if (!(l.range >= 0.0) || !std::isfinite(l.range)) Fail(part + ".range: must be > 0");
    if (l.range > 0.0) ++ignoredRanges;
    vec3 intensity = vec3(color * l.intensity);
    if (l.type == "directional") {
      DirectionalLightDesc d;  // light travels along -Z: the direction towards it is +Z
      d.direction = vec3(WorldDirection(world, glm::dvec3(0, 0, 1), part));
      d.irradiance = intensity;
      out_.directionalLights.push_back(d);
      return;
    }
    vec3 position = vec3(WorldPosition(world, part));
    if (l.type == "point") {
      out_.pointLights.push_back(PointLightDesc{position, intensity});
      return;
    }
    if (l.type != "spot") {
      Fail(part + ".type: unknown light type " + Quote(l.type) +
           " (expected point, spot or directional)");
    }
    double inner = l.spot.innerConeAngle, outer = l.spot.outerConeAngle;
    if (!(inner >= 0.0 && inner < outer && outer <= 0.5 * kPiD)) {
      Fail(part + ".spot: needs 0 <= innerConeAngle < outerConeAngle <= pi/2 (has " +
           std::to_string(inner) + " and " + std::to_string(outer) + ")");
    }
    SpotLightDesc s;
    s.position = position;
    s.direction = vec3(WorldDirection(world, glm::dvec3(0, 0, -1), part));
    s.intensity = intensity;
    s.innerAngle = float(inner);
    s.outerAngle = float(outer);
    out_.spotLights.push_back(s);
  }

  const tinygltf::Model& model_;
  GltfSceneContents& out_;
  std::vector<bool> placed_;
};

// What the file has that no loader reads, as summary phrases.
void ListIgnored(const tinygltf::Model& model, const SceneReader& reader, bool animated,
                 GltfSceneContents& out) {
  size_t orthographic = 0;
  for (const GltfCamera& c : out.cameras) orthographic += c.perspective ? 0 : 1;
  if (orthographic > 0) {
    out.ignored.push_back(Plural(orthographic, "orthographic camera", "orthographic cameras") +
                          " (unsupported)");
  }
  if (reader.ignoredRanges > 0) {
    out.ignored.push_back("the range of " + Plural(reader.ignoredRanges, "light", "lights") +
                          " (inverse-square falloff everywhere)");
  }
  if (!model.animations.empty() && !animated) {
    out.ignored.push_back(Plural(model.animations.size(), "animation", "animations") +
                          " (the static pose is rendered; --time SECONDS poses one)");
  }
  for (const std::string& name : model.extensionsUsed) {
    if (!IsReadExtension(name)) out.ignored.push_back("extension " + name);
  }
}

}  // namespace

void CheckGltfRequiredExtensions(const tinygltf::Model& model) {
  CheckGltfRequiredExtensions(model.extensionsRequired);
}

void CheckGltfRequiredExtensions(const std::vector<std::string>& required) {
  for (const std::string& name : required) {
    if (!IsReadableWhenRequired(name)) {
      Fail("extensionsRequired: the file requires " + name + ", which this renderer cannot read");
    }
  }
}

GltfSceneContents ReadGltfSceneContents(const tinygltf::Model& model,
                                        const glm::dmat4& objectToWorld, bool animated) {
  GltfSceneContents out;
  SceneReader reader(model, out);
  for (int root : GltfRootNodes(model)) reader.Visit(root, objectToWorld, 0);
  std::sort(out.cameras.begin(), out.cameras.end(),
            [](const GltfCamera& a, const GltfCamera& b) { return a.index < b.index; });
  ListIgnored(model, reader, animated, out);
  return out;
}

std::string DescribeGltfCameras(const GltfSceneContents& contents) {
  std::string list;
  for (const GltfCamera& c : contents.cameras) {
    // append() piecewise: "x" + std::string trips GCC 12's -Wrestrict false positive here.
    list.append(list.empty() ? "" : ", ").append(std::to_string(c.index));
    if (!c.name.empty()) list.append(" ").append(Quote(c.name));
    if (!c.nodeName.empty()) list.append(" (node ").append(Quote(c.nodeName)).append(")");
    if (!c.perspective) list.append(" [orthographic]");
  }
  return list.empty() ? "none" : list;
}

const GltfCamera* SelectGltfCamera(const GltfSceneContents& contents, const std::string& selector) {
  if (selector.empty()) {
    for (const GltfCamera& c : contents.cameras) {
      if (c.perspective) return &c;
    }
    return nullptr;
  }
  bool numeric = selector.size() <= 9 &&
                 selector.find_first_not_of("0123456789") == std::string::npos;
  const GltfCamera* found = nullptr;
  for (const GltfCamera& c : contents.cameras) {  // names first, then the node's names
    if (numeric ? c.index == std::stoi(selector) : c.name == selector) {
      found = &c;
      break;
    }
  }
  for (size_t i = 0; !found && !numeric && i < contents.cameras.size(); ++i) {
    if (contents.cameras[i].nodeName == selector) found = &contents.cameras[i];
  }
  std::string what = numeric ? "camera " + selector : "camera " + Quote(selector);
  if (!found) {
    Fail("no " + what + " placed in the default scene (cameras: " +
         DescribeGltfCameras(contents) + ")");
  }
  if (!found->perspective) {
    Fail(what + " is orthographic; only perspective cameras are supported (cameras: " +
         DescribeGltfCameras(contents) + ")");
  }
  return found;
}

}  // namespace pt
