// glTF materials (core metallic-roughness, KHR_materials_transmission, _volume, _ior,
// _emissive_strength) as MaterialType::kGltfPbr, per docs/gltf-materials.md; what the
// renderer does not honour is collected into one warning per file.
#include "src/io/gltf_material.h"
#include "src/io/gltf_value.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace pt {
namespace {

using tinygltf::Value;

vec3 Vec3Of(const std::vector<double>& v, vec3 fallback) {
  return v.size() >= 3 ? vec3(float(v[0]), float(v[1]), float(v[2])) : fallback;
}

double Clamped01(double v, double ifNan) { return std::isnan(v) ? ifNan : std::clamp(v, 0.0, 1.0); }

// Material extensions whose meaning the mapping honours; any other is named.
bool HandledExtension(const std::string& name) {
  return name == "KHR_materials_transmission" || name == "KHR_materials_ior" ||
         name == "KHR_materials_volume" || name == "KHR_materials_emissive_strength" ||
         LayeredGltfExtension(name);
}

// KHR_materials_ior (default 1.5); a non-finite or non-positive index is replaced.
float IorOf(const tinygltf::Material& m, std::vector<std::string>& notes) {
  double ior = GltfNumber(GltfExtension(m.extensions, "KHR_materials_ior"), "ior", 1.5);
  if (!(ior > 0.0) || !std::isfinite(ior)) {
    notes.push_back("invalid KHR_materials_ior replaced by 1.5");
    ior = 1.5;
  }
  return float(ior);
}

// Beer-Lambert coefficient -ln(attenuationColor) / attenuationDistance (0: no absorption).
vec3 AbsorptionOf(const Value* volume) {
  double distance = GltfNumber(volume, "attenuationDistance", INFINITY);
  vec3 color = GltfVec3(volume, "attenuationColor", vec3(1.0f));
  vec3 sigma(0.0f);
  if (!(distance > 0.0 && std::isfinite(distance))) return sigma;
  for (int i = 0; i < 3; ++i) {
    double c = std::clamp(double(color[i]), 1e-6, 1.0);  // black would be infinite absorption
    sigma[i] = float(-std::log(c) / distance);
  }
  return sigma;
}

// emissiveFactor x KHR_materials_emissive_strength, negative or non-finite parts dropped.
vec3 EmissionOf(const tinygltf::Material& m, std::vector<std::string>& notes) {
  double strength =
      GltfNumber(GltfExtension(m.extensions, "KHR_materials_emissive_strength"), "emissiveStrength", 1.0);
  vec3 e = Vec3Of(m.emissiveFactor, vec3(0.0f)) * float(strength);
  if (!IsFinite(e) || MinComponent(e) < 0.0f) {
    notes.push_back("invalid emission (negative or not finite) set to 0");
    for (int i = 0; i < 3; ++i) e[i] = std::isfinite(e[i]) && e[i] > 0.0f ? e[i] : 0.0f;
  }
  return e;
}

void MapAlpha(const tinygltf::Material& m, Material& out, std::vector<std::string>& notes) {
  if (m.alphaMode == "MASK") {
    out.flags |= kMaterialAlphaMask;
    out.alphaCutoff = float(m.alphaCutoff);
  } else if (m.alphaMode == "BLEND") {
    out.flags |= kMaterialAlphaBlend;
  } else if (!m.alphaMode.empty() && m.alphaMode != "OPAQUE") {
    notes.push_back("unknown alphaMode rendered OPAQUE");
  }
}

// Where the glTF material is exactly one of the plain materials, that one: metallic 1 is
// lobes.h's conductor (GGX with Schlick F0 = baseColor, the same lobe and sampling) and full
// transmission through an untinted, untextured volume is its dielectric. The plain types run in
// the specialised shade variants (a smooth gold mesh needs no general kernel). Anything else
// (metallic 0's coated diffuse, tints, textures other than base colour on a metal, emission,
// COLOR_0) stays kGltfPbr.
void UsePlainMaterialWhereExact(Material& m, bool hasVertexColors) {
  if (m.ext >= 0 || (m.flags & kMaterialUnlit)) return;  // the layered BSDF's
  bool textured = m.metallicRoughnessTexture >= 0 || m.normalTexture >= 0 ||
                  m.emissiveTexture >= 0 || m.transmissionTexture >= 0;
  bool alpha = (m.flags & (kMaterialAlphaMask | kMaterialAlphaBlend)) != 0;
  if (textured || alpha || hasVertexColors || !IsBlack(m.radiance)) return;
  if (m.metallic == 1.0f) {
    m.type = MaterialType::kConductor;
  } else if (m.metallic == 0.0f && m.transmission == 1.0f && !(m.flags & kMaterialThinWalled) &&
             m.albedo == vec3(1.0f) && m.baseColorTexture < 0) {
    m.type = MaterialType::kDielectric;
  }
}

}  // namespace

MappedGltfMaterial MapGltfMaterial(const tinygltf::Material& m) {
  MappedGltfMaterial mapped;
  std::vector<std::string>& notes = mapped.approximations;
  Material& out = mapped.material;
  out.type = MaterialType::kGltfPbr;
  const auto& pbr = m.pbrMetallicRoughness;
  const std::vector<double>& f = pbr.baseColorFactor;
  vec3 rawBase = Vec3Of(f, vec3(1.0f));
  out.albedo = glm::clamp(rawBase, vec3(0.0f), vec3(1.0f));
  if (out.albedo != rawBase) notes.push_back("baseColorFactor clamped to [0, 1]");
  out.alpha = float(Clamped01(f.size() >= 4 ? f[3] : 1.0, 1.0));
  out.metallic = float(Clamped01(pbr.metallicFactor, 1.0));
  out.roughness = float(Clamped01(pbr.roughnessFactor, 1.0));
  out.radiance = EmissionOf(m, notes);
  out.twoSided = m.doubleSided ? 1u : 0u;
  out.ior = IorOf(m, notes);
  out.normalScale = float(m.normalTexture.scale);
  const Value* transmission = GltfExtension(m.extensions, "KHR_materials_transmission");
  out.transmission = float(Clamped01(GltfNumber(transmission, "transmissionFactor", 0.0), 0.0));
  bool transmissive = out.transmission > 0.0f;
  const Value* volume = GltfExtension(m.extensions, "KHR_materials_volume");
  // A volume needs thickness > 0; without one the surface is a thin wall (the extension's
  // rule). thicknessTexture is a rasterizer's estimate: a path tracer measures the geometry.
  if (GltfNumber(volume, "thicknessFactor", 0.0) > 0.0) {
    out.absorption = AbsorptionOf(volume);
  } else {
    out.flags |= kMaterialThinWalled;
  }
  MapAlpha(m, out, notes);
  // glTF culls back faces of single-sided materials. Transmissive ones are exempt: rays inside
  // a volume must meet its boundary from behind to leave it.
  if (!m.doubleSided && !transmissive) out.flags |= kMaterialCullBack;
  if (m.occlusionTexture.index >= 0) notes.push_back("occlusionTexture ignored");
  if (GltfExtension(m.extensions, "KHR_materials_unlit")) {
    // Unlit: the base colour is what the surface shows (as if emissive); nothing else applies.
    out.flags |= kMaterialUnlit;
    out.radiance = vec3(0.0f);
  } else {
    mapped.extension = MapGltfExtensions(m, notes);
    // Diffuse transmission lets light through from behind: its back faces are not culled.
    if (mapped.extension.mask & kExtDiffuseTransmission) out.flags &= ~kMaterialCullBack;
  }
  for (const auto& [name, value] : m.extensions) {
    if (!HandledExtension(name)) notes.push_back(name + " ignored");
  }
  return mapped;
}

MappedGltfMaterial MapGltfMaterialLegacy(const tinygltf::Material& m) {
  MappedGltfMaterial mapped;
  std::vector<std::string>& notes = mapped.approximations;
  Material& out = mapped.material;
  const auto& pbr = m.pbrMetallicRoughness;
  vec3 base = glm::clamp(Vec3Of(pbr.baseColorFactor, vec3(1.0f)), vec3(0.0f), vec3(1.0f));
  float roughness = float(Clamped01(pbr.roughnessFactor, 1.0));
  vec3 emission = EmissionOf(m, notes);
  if (MaxComponent(emission) > 0.0f) {
    out.type = MaterialType::kEmissive;
    out.radiance = emission;
    out.twoSided = m.doubleSided ? 1u : 0u;
  } else if (GltfNumber(GltfExtension(m.extensions, "KHR_materials_transmission"), "transmissionFactor",
                      0.0) > 0.0) {
    out.type = MaterialType::kDielectric;
    out.roughness = roughness;
    out.ior = IorOf(m, notes);
    out.absorption = AbsorptionOf(GltfExtension(m.extensions, "KHR_materials_volume"));
  } else {
    out.albedo = base;
    out.roughness = roughness;
    out.type = pbr.metallicFactor >= 0.5 ? MaterialType::kConductor : MaterialType::kPlastic;
    out.ior = 1.5f;
  }
  notes.push_back("legacy mapping (PT_GLTF_MATERIALS=legacy)");
  return mapped;
}

bool UseLegacyGltfMaterials() {
  static const bool legacy = [] {
    const char* v = std::getenv("PT_GLTF_MATERIALS");
    return v != nullptr && std::string(v) == "legacy";
  }();
  return legacy;
}

// ---- GltfMaterialTable ----

GltfMaterialTable::GltfMaterialTable(const tinygltf::Model& model, const GltfEncodedImages& images,
                                     MeshSink& sink)
    : model_(model),
      images_(images),
      sink_(sink),
      materials_(model.materials.size(), -1),
      needs_(model.materials.size() + 1) {
  for (const tinygltf::Mesh& mesh : model.meshes)
    for (const tinygltf::Primitive& p : mesh.primitives)
      if (p.attributes.count("COLOR_0")) colored_.insert(p.material < 0 ? -1 : p.material);
}

GltfVertexNeeds GltfMaterialTable::Needs(int material) const {
  return material < 0 ? needs_.back() : needs_.at(size_t(material));
}

void GltfMaterialTable::Note(const std::string& what, int material) {
  notes_[what].insert(material < 0 ? -1 : material);
}

void GltfMaterialTable::Finish() {
  if (notes_.empty()) return;
  std::string line;
  for (const auto& [what, materials] : notes_) {
    size_t n = materials.size();
    line += (line.empty() ? "" : ", ") + what + " (" + std::to_string(n) +
            (n == 1 ? " material)" : " materials)");
  }
  sink_.Warn("materials: " + line);
  notes_.clear();
}

uint32_t GltfMaterialTable::Index(int index) {
  if (index >= int(model_.materials.size())) {
    throw std::runtime_error("material " + std::to_string(index) + " does not exist");
  }
  int64_t& slot = index < 0 ? defaultMaterial_ : materials_[index];
  if (slot >= 0) return uint32_t(slot);
  tinygltf::Material fallback;  // the glTF default: white, metallic 1, roughness 1
  fallback.emissiveFactor = {0.0, 0.0, 0.0};
  const tinygltf::Material& source = index < 0 ? fallback : model_.materials[index];
  bool legacy = UseLegacyGltfMaterials();
  MappedGltfMaterial mapped = legacy ? MapGltfMaterialLegacy(source) : MapGltfMaterial(source);
  for (const std::string& a : mapped.approximations) Note(a, index);
  Material& m = mapped.material;
  GltfVertexNeeds& needs = needs_[index < 0 ? needs_.size() - 1 : size_t(index)];
  try {  // a texture a used material needs and cannot have is an error naming the material
    if (!legacy) {
      needs.colors = true;
      ResolveTextures(source, index, m);
      if (mapped.extension.mask != 0) {
        ResolveExtensionTextures(source, index, mapped.extension);
        m.ext = sink_.AddMaterialExtension(mapped.extension);
      }
      UsePlainMaterialWhereExact(m, colored_.count(index) > 0);
    } else if (m.type == MaterialType::kConductor || m.type == MaterialType::kPlastic) {
      Slot base{source.pbrMetallicRoughness.baseColorTexture.index, 0, nullptr};
      m.baseColorTexture = AddSlot(base, true, "baseColorTexture", index);
    }
  } catch (const std::runtime_error& e) {
    std::string which = index < 0 ? std::string("default material")
                                  : "material \"" + source.name + "\" (#" + std::to_string(index) + ")";
    throw std::runtime_error(which + ": " + e.what());
  }
  std::string name = source.name;
  if (index < 0) {
    name = "default";
  } else if (name.empty()) {
    name = std::string("#").append(std::to_string(index));  // GCC 12 -Wrestrict false alarm
  }
  slot = sink_.AddMaterial(m, sink_.Label() + ":" + name);
  return uint32_t(slot);
}

void GltfMaterialTable::ResolveTextures(const tinygltf::Material& source, int material,
                                        Material& m) {
  auto slotOf = [](const auto& info) {
    return Slot{info.index, info.texCoord, GltfExtension(info.extensions, "KHR_texture_transform")};
  };
  const auto& pbr = source.pbrMetallicRoughness;
  m.baseColorTexture = AddSlot(slotOf(pbr.baseColorTexture), true, "baseColorTexture", material);
  m.metallicRoughnessTexture =
      AddSlot(slotOf(pbr.metallicRoughnessTexture), false, "metallicRoughnessTexture", material);
  m.normalTexture = AddSlot(slotOf(source.normalTexture), false, "normalTexture", material);
  if (m.normalTexture >= 0) needs_[material < 0 ? needs_.size() - 1 : size_t(material)].tangents = true;
  if (!IsBlack(m.radiance))  // a black factor makes the texture irrelevant: not decoded
    m.emissiveTexture = AddSlot(slotOf(source.emissiveTexture), true, "emissiveTexture", material);
  const Value* transmission = GltfExtension(source.extensions, "KHR_materials_transmission");
  if (m.transmission > 0.0f)
    m.transmissionTexture = AddSlot(SlotIn(transmission, "transmissionTexture"), false,
                                    "transmissionTexture", material);
}

}  // namespace pt
