// glTF metallic-roughness materials (and KHR_materials_*) mapped to the renderer's materials,
// per shared/scene-format.md. What the renderer cannot honour yet is approximated and named.
#include "src/io/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pt {
namespace {

using tinygltf::Value;

const Value* Extension(const tinygltf::Material& m, const char* name) {
  auto it = m.extensions.find(name);
  return (it == m.extensions.end() || !it->second.IsObject()) ? nullptr : &it->second;
}

double NumberIn(const Value* ext, const char* key, double fallback) {
  if (!ext || !ext->Has(key)) return fallback;
  const Value& v = ext->Get(key);
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

vec3 Vec3In(const Value* ext, const char* key, vec3 fallback) {
  if (!ext || !ext->Has(key)) return fallback;
  const Value& v = ext->Get(key);
  if (!v.IsArray() || v.ArrayLen() < 3) return fallback;
  vec3 out;
  for (int i = 0; i < 3; ++i) {
    if (!v.Get(i).IsNumber()) return fallback;
    out[i] = float(v.Get(i).GetNumberAsDouble());
  }
  return out;
}

vec3 Vec3Of(const std::vector<double>& v, vec3 fallback) {
  return v.size() >= 3 ? vec3(float(v[0]), float(v[1]), float(v[2])) : fallback;
}

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3g", v);
  return buf;
}

// Textures and alpha modes have no counterpart yet: each is named in the warning.
void NoteIgnoredFeatures(const tinygltf::Material& m, std::vector<std::string>& notes) {
  const auto& pbr = m.pbrMetallicRoughness;
  std::string textures;
  auto note = [&textures](bool present, const char* name) {
    if (present) textures += (textures.empty() ? "" : ", ") + std::string(name);
  };
  note(pbr.baseColorTexture.index >= 0, "baseColorTexture");
  note(pbr.metallicRoughnessTexture.index >= 0, "metallicRoughnessTexture");
  note(m.normalTexture.index >= 0, "normalTexture");
  note(m.emissiveTexture.index >= 0, "emissiveTexture");
  const Value* transmission = Extension(m, "KHR_materials_transmission");
  note(transmission && transmission->Has("transmissionTexture"), "transmissionTexture");
  const Value* volume = Extension(m, "KHR_materials_volume");
  note(volume && volume->Has("thicknessTexture"), "thicknessTexture");
  if (!textures.empty()) notes.push_back("textures ignored (" + textures + "), factors used");
  if (!m.alphaMode.empty() && m.alphaMode != "OPAQUE") {
    notes.push_back("alphaMode " + m.alphaMode + " ignored (rendered opaque)");
  }
}

Material MapTransmissive(const tinygltf::Material& m, double transmission, double roughness,
                         vec3 base, std::vector<std::string>& notes) {
  Material out;
  out.type = MaterialType::kDielectric;
  double ior = NumberIn(Extension(m, "KHR_materials_ior"), "ior", 1.5);
  if (!(ior > 0.0) || !std::isfinite(ior)) {
    notes.push_back("KHR_materials_ior " + Num(ior) + " replaced by 1.5");
    ior = 1.5;
  }
  out.ior = float(ior);
  const Value* volume = Extension(m, "KHR_materials_volume");
  if (!volume || !(NumberIn(volume, "thicknessFactor", 0.0) > 0.0)) {
    notes.push_back("thin-walled transmission rendered as solid glass");
  }
  double distance = NumberIn(volume, "attenuationDistance", INFINITY);
  vec3 color = Vec3In(volume, "attenuationColor", vec3(1.0f));
  if (distance > 0.0 && std::isfinite(distance)) {
    for (int i = 0; i < 3; ++i) {
      double c = std::clamp(double(color[i]), 1e-6, 1.0);  // black would be infinite absorption
      out.absorption[i] = float(-std::log(c) / distance);
    }
  }
  if (roughness > 0.0) {
    notes.push_back("rough transmission (roughness " + Num(roughness) + ") rendered as smooth glass");
  }
  if (transmission < 1.0) {
    notes.push_back("partial transmission " + Num(transmission) + " rendered as full");
  }
  if (MinComponent(base) < 1.0f) notes.push_back("baseColor tint of the transmission ignored");
  return out;
}

Material MapOpaque(double metallic, double roughness, vec3 base, std::vector<std::string>& notes) {
  Material out;
  out.albedo = base;
  if (metallic >= 0.5) {
    out.type = MaterialType::kConductor;
    if (metallic < 1.0) notes.push_back("metallic " + Num(metallic) + " rendered as fully metallic");
    if (roughness > 0.0) {
      notes.push_back("rough conductor (roughness " + Num(roughness) + ") rendered as a mirror");
    }
    return out;
  }
  // Plastic (a dielectric coat of ior 1.5 over the base) arrives with rough materials.
  out.type = MaterialType::kDiffuse;
  notes.push_back("plastic (ior 1.5 coat, roughness " + Num(roughness) +
                  ") rendered as diffuse" +
                  (metallic > 0.0 ? ", metallic " + Num(metallic) + " as 0" : std::string()));
  return out;
}

}  // namespace

MappedGltfMaterial MapGltfMaterial(const tinygltf::Material& m) {
  MappedGltfMaterial mapped;
  const auto& pbr = m.pbrMetallicRoughness;
  vec3 rawBase = Vec3Of(pbr.baseColorFactor, vec3(1.0f));
  vec3 base = glm::clamp(rawBase, vec3(0.0f), vec3(1.0f));
  if (base != rawBase) mapped.approximations.push_back("baseColorFactor clamped to [0, 1]");
  double metallic = std::clamp(pbr.metallicFactor, 0.0, 1.0);
  double roughness = std::clamp(pbr.roughnessFactor, 0.0, 1.0);
  double strength = NumberIn(Extension(m, "KHR_materials_emissive_strength"), "emissiveStrength", 1.0);
  vec3 emission = Vec3Of(m.emissiveFactor, vec3(0.0f)) * float(strength);
  double transmission = NumberIn(Extension(m, "KHR_materials_transmission"), "transmissionFactor", 0.0);

  std::vector<std::string>& notes = mapped.approximations;
  if (MaxComponent(emission) > 0.0f && IsFinite(emission)) {
    mapped.material.type = MaterialType::kEmissive;
    mapped.material.radiance = glm::max(emission, vec3(0.0f));
    mapped.material.twoSided = m.doubleSided ? 1u : 0u;
    if (MaxComponent(base) > 0.0f) notes.push_back("its reflection dropped (emitters reflect nothing)");
  } else if (transmission > 0.0) {
    mapped.material = MapTransmissive(m, transmission, roughness, base, notes);
  } else {
    mapped.material = MapOpaque(metallic, roughness, base, notes);
  }
  NoteIgnoredFeatures(m, notes);
  return mapped;
}

}  // namespace pt
