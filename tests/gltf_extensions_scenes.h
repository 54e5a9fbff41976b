// Tiny generated glTF scenes for the material extensions (one square, one material), shared by
// the CPU render tests (tests/gltf_extensions_render_test.cpp) and the GPU agreement test.
// Under a uniform white background and max_depth 1 a pixel's expectation is the BSDF's
// directional albedo for the view, so each render has an exact expectation.
#pragma once

#include <cmath>
#include <fstream>
#include <string>

#include "src/scene/energy_compensation.h"
#include "tests/gltf_material_scenes.h"

namespace pt::test {

// A camera 60 units away, theta degrees from the square's normal (+z) towards +x, seeing only
// [-half, half]^2 of the square around its centre.
inline std::string ObliqueCamera(double thetaDeg, double half = 0.2) {
  double t = thetaDeg * M_PI / 180.0;
  double fov = 2.0 * std::atan(half / 60.0) * 180.0 / M_PI;
  return R"({"position": [)" + std::to_string(60.0 * std::sin(t)) + ", 0, " +
         std::to_string(60.0 * std::cos(t)) + R"(], "look_at": [0, 0, 0], "fov_y": )" +
         std::to_string(fov) + "}";
}

inline const std::string kWhiteBackground = R"(, "background": [1, 1, 1])";

// A directional light of irradiance 1 travelling along `direction`.
inline std::string DirectionalLight(vec3 direction) {
  return R"(, "lights": [{"type": "directional", "direction": [)" + std::to_string(direction.x) +
         ", " + std::to_string(direction.y) + ", " + std::to_string(direction.z) +
         R"(], "irradiance": [1, 1, 1]}])";
}

struct ExtensionSceneSpec {
  std::string name;      // file name stem
  std::string material;  // the glTF material (JSON)
  std::string camera = ObliqueCamera(0.0);
  std::string extra = kWhiteBackground;  // lights / background
  std::string variant;                   // the mesh's "variant" field, empty for none
  bool energyCompensation = false;
};

inline SceneDesc ExtensionSceneDesc(const std::string& dir, const ExtensionSceneSpec& e,
                                    const SceneSpec& spec) {
  GltfWriter w(e.name);
  w.AddMaterial(e.material);
  w.AddPrimitive(Square());
  std::string file = w.Write(dir);
  std::string mesh = R"({"type": "mesh", "file": ")" + file + "\"" +
                     (e.variant.empty() ? "" : R"(, "variant": ")" + e.variant + "\"") + "}";
  std::string json = R"({"render": {"width": )" + std::to_string(spec.size) + R"(, "height": )" +
                     std::to_string(spec.size) + R"(, "spp": )" + std::to_string(spec.spp) +
                     R"(, "max_depth": )" + std::to_string(spec.maxDepth) +
                     R"(, "russian_roulette_depth": 100, "seed": )" + std::to_string(spec.seed) +
                     R"(}, "camera": )" + e.camera + R"(, "materials": {}, "objects": [)" + mesh +
                     "]" + e.extra + "}";
  SceneDesc desc = LoadSceneFromString(json, "generated.json", dir);
  if (e.energyCompensation) EnableEnergyCompensation(&desc);
  return desc;
}

inline Scene ExtensionScene(const std::string& dir, const ExtensionSceneSpec& e, const SceneSpec& spec) {
  return BuildScene(ExtensionSceneDesc(dir, e, spec));
}

// The extension materials of the render tests: each with the extension and, as a control, the
// same material without it (`with` false).
inline std::string ClearcoatMaterial(bool with) {
  return std::string(R"({"pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.1, 0.1, 1],
      "metallicFactor": 0, "roughnessFactor": 0.6})") +
         (with ? R"(, "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1,
                    "clearcoatRoughnessFactor": 0.1}})" : "") + "}";
}
inline std::string SpecularMaterial(bool with) {
  return std::string(R"({"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1],
      "metallicFactor": 0, "roughnessFactor": 0.3})") +
         (with ? R"(, "extensions": {"KHR_materials_specular": {"specularFactor": 0.8,
                    "specularColorFactor": [5, 2, 1]}})" : "") + "}";
}
inline std::string SheenMaterial(bool with) {
  return std::string(R"({"pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.05, 0.05, 1],
      "metallicFactor": 0, "roughnessFactor": 0.8})") +
         (with ? R"(, "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1, 0.2, 0.2],
                    "sheenRoughnessFactor": 0.5}})" : "") + "}";
}
inline std::string IridescenceMaterial(bool with) {
  return std::string(R"({"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1],
      "metallicFactor": 0, "roughnessFactor": 0.3})") +
         (with ? R"(, "extensions": {"KHR_materials_iridescence": {"iridescenceFactor": 1,
                    "iridescenceIor": 1.8, "iridescenceThicknessMaximum": 450}})" : "") + "}";
}
inline std::string AnisotropyMaterial(bool with, float rotation = 0.0f) {
  return std::string(R"({"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1],
      "metallicFactor": 1, "roughnessFactor": 0.3})") +
         (with ? R"(, "extensions": {"KHR_materials_anisotropy": {"anisotropyStrength": 0.9,
                    "anisotropyRotation": )" + std::to_string(rotation) + "}}" : "") + "}";
}
inline std::string DiffuseTransmissionMaterial(bool with) {
  return std::string(R"({"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
      "metallicFactor": 0, "roughnessFactor": 0.5})") +
         (with ? R"(, "extensions": {"KHR_materials_diffuse_transmission": {
                    "diffuseTransmissionFactor": 1, "diffuseTransmissionColorFactor": [1, 0.5, 0.2]}})"
               : "") + "}";
}
inline std::string UnlitMaterial(bool with) {
  return std::string(R"({"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.6, 0.9, 1],
      "metallicFactor": 0, "roughnessFactor": 1})") +
         (with ? R"(, "extensions": {"KHR_materials_unlit": {}})" : "") + "}";
}
inline std::string RoughWhiteMetal() {
  return R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 1,
      "roughnessFactor": 0.8}})";
}

// A directional light 30 degrees off the square's normal, travelling towards the square from
// the +x side, and (behind) one travelling along +z into the square's back.
inline vec3 OffNormalLightDirection() { return -glm::normalize(vec3(0.5f, 0.0f, 0.866f)); }

}  // namespace pt::test
