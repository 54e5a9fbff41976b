// The glTF material extensions the layered BSDF honours (src/materials/gltf_layered.h):
// KHR_materials_specular, _clearcoat, _sheen, _iridescence, _anisotropy, _diffuse_transmission
// as a GltfMaterialExtension entry, and KHR_materials_unlit as a flag. Factors are clamped to
// their ranges (with a note); an extension whose factors make it inert (clearcoat 0, black
// sheen, ...) is left out, so the material stays on the plain kernels.
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "src/io/gltf_material.h"
#include "src/io/gltf_value.h"

namespace pt {
namespace {

using tinygltf::Value;

std::string FormatRange(double lo, double hi) {
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%g", v);
    return std::string(buf);
  };
  return num(lo) + ", " + num(hi);
}

// A factor clamped to [lo, hi] (a note when it was outside; NaN reads as the fallback).
float Factor(const Value* ext, const char* key, double fallback, double lo, double hi,
             const std::string& what, std::vector<std::string>& notes) {
  double v = GltfNumber(ext, key, fallback);
  if (std::isnan(v)) v = fallback;
  double c = std::clamp(v, lo, hi);
  if (c != v) notes.push_back(what + "." + key + " clamped to [" + FormatRange(lo, hi) + "]");
  return float(c);
}

vec3 ColorFactor(const Value* ext, const char* key, vec3 fallback, float hi, const std::string& what,
                 std::vector<std::string>& notes) {
  vec3 v = GltfVec3(ext, key, fallback);
  vec3 c = IsFinite(v) ? glm::clamp(v, vec3(0.0f), vec3(hi)) : fallback;
  if (c != v) notes.push_back(what + "." + key + " clamped to [" + FormatRange(0.0, hi) + "]");
  return c;
}

}  // namespace

bool LayeredGltfExtension(const std::string& name) {
  return name == "KHR_materials_specular" || name == "KHR_materials_clearcoat" ||
         name == "KHR_materials_sheen" || name == "KHR_materials_iridescence" ||
         name == "KHR_materials_anisotropy" || name == "KHR_materials_diffuse_transmission" ||
         name == "KHR_materials_unlit";
}

GltfMaterialExtension MapGltfExtensions(const tinygltf::Material& m, std::vector<std::string>& notes) {
  GltfMaterialExtension e;
  const auto& ext = m.extensions;
  if (const Value* v = GltfExtension(ext, "KHR_materials_specular")) {
    const std::string w = "KHR_materials_specular";
    e.specular = Factor(v, "specularFactor", 1.0, 0.0, 1.0, w, notes);
    e.specularColor = ColorFactor(v, "specularColorFactor", vec3(1.0f), 1e4f, w, notes);
    bool textured = v->Has("specularTexture") || v->Has("specularColorTexture");
    if (textured || e.specular != 1.0f || e.specularColor != vec3(1.0f)) e.mask |= kExtSpecular;
  }
  if (const Value* v = GltfExtension(ext, "KHR_materials_clearcoat")) {
    const std::string w = "KHR_materials_clearcoat";
    e.clearcoat = Factor(v, "clearcoatFactor", 0.0, 0.0, 1.0, w, notes);
    e.clearcoatRoughness = Factor(v, "clearcoatRoughnessFactor", 0.0, 0.0, 1.0, w, notes);
    if (e.clearcoat > 0.0f) e.mask |= kExtClearcoat;
  }
  if (const Value* v = GltfExtension(ext, "KHR_materials_sheen")) {
    const std::string w = "KHR_materials_sheen";
    e.sheenColor = ColorFactor(v, "sheenColorFactor", vec3(0.0f), 1.0f, w, notes);
    e.sheenRoughness = Factor(v, "sheenRoughnessFactor", 0.0, 0.0, 1.0, w, notes);
    if (MaxComponent(e.sheenColor) > 0.0f) e.mask |= kExtSheen;
  }
  if (const Value* v = GltfExtension(ext, "KHR_materials_iridescence")) {
    const std::string w = "KHR_materials_iridescence";
    e.iridescence = Factor(v, "iridescenceFactor", 0.0, 0.0, 1.0, w, notes);
    e.iridescenceIor = Factor(v, "iridescenceIor", 1.3, 1.0, 10.0, w, notes);
    e.thicknessMin = Factor(v, "iridescenceThicknessMinimum", 100.0, 0.0, 1e5, w, notes);
    e.thicknessMax = Factor(v, "iridescenceThicknessMaximum", 400.0, 0.0, 1e5, w, notes);
    if (e.iridescence > 0.0f) e.mask |= kExtIridescence;
  }
  if (const Value* v = GltfExtension(ext, "KHR_materials_anisotropy")) {
    const std::string w = "KHR_materials_anisotropy";
    e.anisotropy = Factor(v, "anisotropyStrength", 0.0, 0.0, 1.0, w, notes);
    e.anisotropyRotation = Factor(v, "anisotropyRotation", 0.0, -1e6, 1e6, w, notes);
    if (e.anisotropy > 0.0f) e.mask |= kExtAnisotropy;
  }
  if (const Value* v = GltfExtension(ext, "KHR_materials_diffuse_transmission")) {
    const std::string w = "KHR_materials_diffuse_transmission";
    e.diffuseTransmission = Factor(v, "diffuseTransmissionFactor", 0.0, 0.0, 1.0, w, notes);
    e.diffuseTransmissionColor =
        ColorFactor(v, "diffuseTransmissionColorFactor", vec3(1.0f), 1.0f, w, notes);
    if (e.diffuseTransmission > 0.0f) e.mask |= kExtDiffuseTransmission;
  }
  return e;
}

// ---- Texture slots of the extensions ----

GltfMaterialTable::Slot GltfMaterialTable::SlotIn(const Value* ext, const char* key) {
  Slot slot;
  if (!ext || !ext->Has(key)) return slot;
  const Value& info = ext->Get(key);
  if (!info.IsObject()) return slot;
  if (info.Has("index") && info.Get("index").IsInt()) slot.texture = info.Get("index").GetNumberAsInt();
  if (info.Has("texCoord") && info.Get("texCoord").IsInt())
    slot.texCoord = info.Get("texCoord").GetNumberAsInt();
  if (info.Has("extensions") && info.Get("extensions").IsObject()) {
    const Value& x = info.Get("extensions");
    if (x.Has("KHR_texture_transform") && x.Get("KHR_texture_transform").IsObject())
      slot.transform = &x.Get("KHR_texture_transform");
  }
  return slot;
}

void GltfMaterialTable::ResolveExtensionTextures(const tinygltf::Material& source, int material,
                                                 GltfMaterialExtension& e) {
  const auto& ext = source.extensions;
  GltfVertexNeeds& needs = needs_[material < 0 ? needs_.size() - 1 : size_t(material)];
  auto slot = [&](const char* extension, const char* key, bool srgb) {
    return AddSlot(SlotIn(GltfExtension(ext, extension), key), srgb, key, material);
  };
  if (e.mask & kExtSpecular) {
    e.specularTexture = slot("KHR_materials_specular", "specularTexture", false);
    e.specularColorTexture = slot("KHR_materials_specular", "specularColorTexture", true);
  }
  if (e.mask & kExtClearcoat) {
    e.clearcoatTexture = slot("KHR_materials_clearcoat", "clearcoatTexture", false);
    e.clearcoatRoughnessTexture = slot("KHR_materials_clearcoat", "clearcoatRoughnessTexture", false);
    e.clearcoatNormalTexture = slot("KHR_materials_clearcoat", "clearcoatNormalTexture", false);
    if (e.clearcoatNormalTexture >= 0) {
      needs.tangents = true;
      const Value* v = GltfExtension(ext, "KHR_materials_clearcoat");
      const Value& info = v->Get("clearcoatNormalTexture");
      e.clearcoatNormalScale = float(GltfNumber(&info, "scale", 1.0));
    }
  }
  if (e.mask & kExtSheen) {
    e.sheenColorTexture = slot("KHR_materials_sheen", "sheenColorTexture", true);
    e.sheenRoughnessTexture = slot("KHR_materials_sheen", "sheenRoughnessTexture", false);
  }
  if (e.mask & kExtIridescence) {
    e.iridescenceTexture = slot("KHR_materials_iridescence", "iridescenceTexture", false);
    e.iridescenceThicknessTexture =
        slot("KHR_materials_iridescence", "iridescenceThicknessTexture", false);
  }
  if (e.mask & kExtAnisotropy) {
    e.anisotropyTexture = slot("KHR_materials_anisotropy", "anisotropyTexture", false);
    needs.tangents = true;  // the direction lives in the tangent frame
    if (e.anisotropyTexture < 0) needs.uv[0] = true;
  }
  if (e.mask & kExtDiffuseTransmission) {
    e.diffuseTransmissionTexture =
        slot("KHR_materials_diffuse_transmission", "diffuseTransmissionTexture", false);
    e.diffuseTransmissionColorTexture =
        slot("KHR_materials_diffuse_transmission", "diffuseTransmissionColorTexture", true);
  }
}

}  // namespace pt
