// What a glTF file's default scene holds besides its triangles: the cameras and the
// KHR_lights_punctual lights its nodes place, and the parts of the file the renderer ignores
// (for one summary line per file). Units: a light's intensity (candela for point and spot
// lights, lux for directional ones) is taken 1:1 as the renderer's W/sr and W/m^2, the scale
// at which glTF viewers put punctual lights beside emissive materials.
#pragma once

#include <string>
#include <vector>

#include "src/scene/scene.h"

namespace tinygltf {
class Model;
}  // namespace tinygltf

namespace pt {

// A camera of the file as the first node of the default scene that places it sees it.
struct GltfCamera {
  int index = -1;          // into the file's cameras
  std::string name;        // the camera's name ("" when it has none)
  std::string nodeName;    // the name of the node that places it
  bool perspective = true;
  float aspectRatio = 0.0f;  // 0: the file gives none
  CameraDesc desc;           // in world space (the object's transform applied)
};

struct GltfSceneContents {
  std::vector<GltfCamera> cameras;  // by camera index; each placed at most once
  std::vector<PointLightDesc> pointLights;
  std::vector<SpotLightDesc> spotLights;
  std::vector<DirectionalLightDesc> directionalLights;
  // Phrases for the file's summary line, e.g. "2 orthographic cameras (unsupported)".
  std::vector<std::string> ignored;

  size_t LightCount() const {
    return pointLights.size() + spotLights.size() + directionalLights.size();
  }
};

// Refuses a file that requires an extension the renderer cannot read (one it does not know):
// std::runtime_error naming it. Called on the JSON before tinygltf parses the file
// (src/io/gltf_document.h), so a parser error cannot come first.
void CheckGltfRequiredExtensions(const std::vector<std::string>& required);
void CheckGltfRequiredExtensions(const tinygltf::Model& model);

// Walks the default scene's nodes for cameras and lights (objectToWorld applied after the
// node transforms) and lists what is ignored. Throws std::runtime_error naming the glTF part
// ("cameras[2]", "KHR_lights_punctual.lights[0]") for a malformed one.
// `animated`: an animation posed the nodes (the file's animations are then not "ignored").
GltfSceneContents ReadGltfSceneContents(const tinygltf::Model& model,
                                        const glm::dmat4& objectToWorld, bool animated = false);

// The camera a selector picks: "" for the first perspective camera (lowest index) or null when
// there is none; otherwise a camera index ("2") or a camera or node name. Throws
// std::runtime_error listing the cameras for an unknown selector or an orthographic camera.
const GltfCamera* SelectGltfCamera(const GltfSceneContents& contents, const std::string& selector);

// "0 \"Camera\" (node \"CameraNode\"), 1 ..." or "none", for messages.
std::string DescribeGltfCameras(const GltfSceneContents& contents);

}  // namespace pt
