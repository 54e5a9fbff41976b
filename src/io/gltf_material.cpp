// glTF metallic-roughness materials (and KHR_materials_*) mapped to the renderer's materials,
// per shared/scene-format.md, with base colour textures decoded (sRGB to linear) on first use.
// What the renderer cannot honour yet is named in a warning.
#include <tiny_gltf.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "src/io/gltf_loader.h"

namespace pt {
namespace {

using tinygltf::Value;

const Value* Extension(const tinygltf::ExtensionMap& extensions, const char* name) {
  auto it = extensions.find(name);
  return (it == extensions.end() || !it->second.IsObject()) ? nullptr : &it->second;
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

// Extensions whose meaning the mapping below honours; any other material extension is named.
bool HandledExtension(const std::string& name) {
  return name == "KHR_materials_transmission" || name == "KHR_materials_ior" ||
         name == "KHR_materials_volume" || name == "KHR_materials_emissive_strength";
}

// Textures other than the base colour, alpha modes and unknown extensions: named, not honoured.
void NoteIgnoredFeatures(const tinygltf::Material& m, std::vector<std::string>& notes) {
  std::string textures;
  auto note = [&textures](bool present, const char* name) {
    if (present) textures += (textures.empty() ? "" : ", ") + std::string(name);
  };
  note(m.pbrMetallicRoughness.metallicRoughnessTexture.index >= 0, "metallicRoughnessTexture");
  note(m.normalTexture.index >= 0, "normalTexture");
  note(m.occlusionTexture.index >= 0, "occlusionTexture");
  note(m.emissiveTexture.index >= 0, "emissiveTexture");
  const Value* transmission = Extension(m.extensions, "KHR_materials_transmission");
  note(transmission && transmission->Has("transmissionTexture"), "transmissionTexture");
  const Value* volume = Extension(m.extensions, "KHR_materials_volume");
  note(volume && volume->Has("thicknessTexture"), "thicknessTexture");
  if (!textures.empty()) notes.push_back("textures ignored (" + textures + "), factors used");
  if (!m.alphaMode.empty() && m.alphaMode != "OPAQUE") {
    notes.push_back("alphaMode " + m.alphaMode + " ignored (rendered opaque)");
  }
  for (const auto& [name, value] : m.extensions) {
    if (!HandledExtension(name)) notes.push_back(name + " ignored");
  }
}

Material MapTransmissive(const tinygltf::Material& m, double roughness, vec3 base,
                         std::vector<std::string>& notes) {
  Material out;
  out.type = MaterialType::kDielectric;
  out.roughness = float(roughness);
  double ior = NumberIn(Extension(m.extensions, "KHR_materials_ior"), "ior", 1.5);
  if (!(ior > 0.0) || !std::isfinite(ior)) {
    notes.push_back("KHR_materials_ior " + Num(ior) + " replaced by 1.5");
    ior = 1.5;
  }
  out.ior = float(ior);
  const Value* volume = Extension(m.extensions, "KHR_materials_volume");
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
  if (MinComponent(base) < 1.0f || m.pbrMetallicRoughness.baseColorTexture.index >= 0) {
    notes.push_back("baseColor tint of the transmission ignored");
  }
  return out;
}

// The texture's extras the renderer does not follow, for a base colour texture in use.
void NoteTextureInfo(const tinygltf::TextureInfo& info, std::vector<std::string>& notes) {
  if (info.texCoord != 0) {
    notes.push_back("baseColorTexture reads TEXCOORD_" + std::to_string(info.texCoord) +
                    ", TEXCOORD_0 used");
  }
  if (info.extensions.count("KHR_texture_transform")) {
    notes.push_back("KHR_texture_transform of baseColorTexture ignored");
  }
}

TextureWrap WrapOf(int mode, std::vector<std::string>& notes) {
  switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_REPEAT: return TextureWrap::kRepeat;
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TextureWrap::kClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TextureWrap::kMirroredRepeat;
    default:
      notes.push_back("sampler wrap mode " + std::to_string(mode) + " unknown, REPEAT used");
      return TextureWrap::kRepeat;
  }
}

// Bytes [byteOffset, byteOffset + byteLength) of a buffer view, or null when out of bounds.
const unsigned char* ViewBytes(const tinygltf::Model& model, int index, size_t* size) {
  if (index < 0 || size_t(index) >= model.bufferViews.size()) return nullptr;
  const tinygltf::BufferView& v = model.bufferViews[index];
  if (v.buffer < 0 || size_t(v.buffer) >= model.buffers.size()) return nullptr;
  const std::vector<unsigned char>& data = model.buffers[v.buffer].data;
  if (v.byteOffset > data.size() || v.byteLength > data.size() - v.byteOffset) return nullptr;
  *size = v.byteLength;
  return data.data() + v.byteOffset;
}

// Decoded RGBA (8 or 16 bits per channel, as tinygltf gives it) to linear RGB; alpha dropped.
std::vector<vec3> LinearTexels(const tinygltf::Image& img) {
  size_t count = size_t(img.width) * size_t(img.height);
  int comp = img.component, bytes = img.bits / 8;
  if (comp < 1 || comp > 4 || (bytes != 1 && bytes != 2) ||
      img.image.size() < count * size_t(comp) * size_t(bytes)) {
    throw std::runtime_error("image \"" + img.name + "\" was decoded inconsistently");
  }
  std::vector<vec3> out(count);
  for (size_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) {
      size_t at = (i * comp + (comp >= 3 ? c : 0)) * bytes;  // grey (+ alpha): one channel
      if (bytes == 1) {
        out[i][c] = Srgb8ToLinear(img.image[at]);
      } else {
        uint16_t v;
        std::memcpy(&v, &img.image[at], 2);
        out[i][c] = float(SrgbToLinear(v / 65535.0));
      }
    }
  }
  return out;
}

}  // namespace

double SrgbToLinear(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

float Srgb8ToLinear(uint8_t code) {
  static const std::vector<float> table = [] {
    std::vector<float> t(256);
    for (int i = 0; i < 256; ++i) t[i] = float(SrgbToLinear(i / 255.0));
    return t;
  }();
  return table[code];
}

MappedGltfMaterial MapGltfMaterial(const tinygltf::Material& m) {
  MappedGltfMaterial mapped;
  const auto& pbr = m.pbrMetallicRoughness;
  vec3 rawBase = Vec3Of(pbr.baseColorFactor, vec3(1.0f));
  vec3 base = glm::clamp(rawBase, vec3(0.0f), vec3(1.0f));
  if (base != rawBase) mapped.approximations.push_back("baseColorFactor clamped to [0, 1]");
  double metallic = std::clamp(pbr.metallicFactor, 0.0, 1.0);
  double roughness = std::clamp(pbr.roughnessFactor, 0.0, 1.0);
  if (std::isnan(roughness)) roughness = 1.0;
  double strength =
      NumberIn(Extension(m.extensions, "KHR_materials_emissive_strength"), "emissiveStrength", 1.0);
  vec3 emission = Vec3Of(m.emissiveFactor, vec3(0.0f)) * float(strength);
  double transmission =
      NumberIn(Extension(m.extensions, "KHR_materials_transmission"), "transmissionFactor", 0.0);

  std::vector<std::string>& notes = mapped.approximations;
  Material& out = mapped.material;
  if (MaxComponent(emission) > 0.0f && IsFinite(emission)) {
    out.type = MaterialType::kEmissive;
    out.radiance = glm::max(emission, vec3(0.0f));
    out.twoSided = m.doubleSided ? 1u : 0u;
  } else if (transmission > 0.0) {
    out = MapTransmissive(m, roughness, base, notes);
  } else {
    out.albedo = base;  // the base colour texture, when resolved, multiplies this
    out.roughness = float(roughness);
    out.type = metallic >= 0.5 ? MaterialType::kConductor : MaterialType::kPlastic;
    if (out.type == MaterialType::kPlastic) out.ior = 1.5f;  // glTF's dielectric base
    if (pbr.baseColorTexture.index >= 0) NoteTextureInfo(pbr.baseColorTexture, notes);
  }
  NoteIgnoredFeatures(m, notes);
  return mapped;
}

// ---- GltfMaterialTable ----

GltfMaterialTable::GltfMaterialTable(const tinygltf::Model& model, const GltfEncodedImages& images,
                                     MeshSink& sink)
    : model_(model),
      images_(images),
      sink_(sink),
      materials_(model.materials.size(), -1),
      textured_(model.materials.size() + 1, false),
      textures_(model.textures.size(), -1),
      imageTextures_(model.images.size(), -1) {}

bool GltfMaterialTable::Textured(int material) const {
  return material < 0 ? textured_.back() : textured_.at(size_t(material));
}

std::string GltfMaterialTable::DisplayName(int material) const {
  if (material < 0 || size_t(material) >= model_.materials.size()) return "default material";
  return "material \"" + model_.materials[material].name + "\" (#" + std::to_string(material) + ")";
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
  std::string name = DisplayName(index);
  MappedGltfMaterial mapped = MapGltfMaterial(source);
  Material& m = mapped.material;
  bool usesAlbedo = m.type == MaterialType::kDiffuse || m.type == MaterialType::kConductor ||
                    m.type == MaterialType::kPlastic;
  int texture = source.pbrMetallicRoughness.baseColorTexture.index;
  try {
    if (usesAlbedo && texture >= 0) {
      m.baseColorTexture = BaseColorTexture(texture, mapped.approximations);
    }
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(name + ": " + e.what());
  }
  textured_[index < 0 ? textured_.size() - 1 : size_t(index)] = m.baseColorTexture >= 0;
  if (!mapped.approximations.empty()) {
    std::string notes;
    for (const std::string& a : mapped.approximations) notes += (notes.empty() ? "" : "; ") + a;
    sink_.Warn(name + ": " + notes);
  }
  std::string shortName = source.name;
  if (index < 0) {
    shortName = "default";
  } else if (shortName.empty()) {
    shortName = std::string("#").append(std::to_string(index));  // GCC 12 -Wrestrict false alarm
  }
  slot = sink_.AddMaterial(m, sink_.Label() + ":" + shortName);
  return uint32_t(slot);
}

// The scene texture for glTF texture `texture` (its image's texels with its sampler's wrap
// modes), or -1 with a note when it cannot be used.
int32_t GltfMaterialTable::BaseColorTexture(int texture, std::vector<std::string>& notes) {
  if (size_t(texture) >= model_.textures.size()) {
    throw std::runtime_error("texture " + std::to_string(texture) + " does not exist");
  }
  int64_t& slot = textures_[texture];
  std::string which = "baseColorTexture #" + std::to_string(texture);
  if (slot == -2) notes.push_back(which + " unusable (see above), factor used");
  if (slot != -1) return slot < 0 ? -1 : int32_t(slot);
  slot = -2;
  const tinygltf::Texture& t = model_.textures[texture];
  TextureWrap wrapS = TextureWrap::kRepeat, wrapT = TextureWrap::kRepeat;
  if (t.sampler >= 0) {
    if (size_t(t.sampler) >= model_.samplers.size()) {
      throw std::runtime_error("sampler " + std::to_string(t.sampler) + " does not exist");
    }
    const tinygltf::Sampler& s = model_.samplers[t.sampler];
    wrapS = WrapOf(s.wrapS, notes);
    wrapT = WrapOf(s.wrapT, notes);
    if (s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST) {
      notes.push_back("NEAREST magnification of " + which + " rendered bilinear");
    }
  }
  if (t.source < 0) {
    std::string extensions;
    for (const auto& [name, value] : t.extensions) extensions += " " + name;
    notes.push_back(which + " has no image this renderer reads (extensions:" +
                    (extensions.empty() ? " none" : extensions) + "), factor used");
    return -1;
  }
  if (size_t(t.source) >= model_.images.size()) {
    throw std::runtime_error("image " + std::to_string(t.source) + " does not exist");
  }
  int64_t& texels = imageTextures_[t.source];
  if (texels == -1) texels = ImageTexels(t.source, wrapS, wrapT);  // first use: decode
  slot = texels;
  const pt::Texture& stored = sink_.TextureAt(int32_t(texels));
  if (stored.wrapS != wrapS || stored.wrapT != wrapT) {
    slot = sink_.AddTextureView(int32_t(texels), wrapS, wrapT);  // same texels, other sampler
  }
  return int32_t(slot);
}

// Decodes image `image` and stores it as a scene texture. An image that is missing or that stb
// cannot decode is bad input (the picture would silently lose it): an error naming the image.
int32_t GltfMaterialTable::ImageTexels(int image, TextureWrap wrapS, TextureWrap wrapT) {
  const tinygltf::Image& source = model_.images[image];
  std::string which = "image #" + std::to_string(image) +
                      (source.name.empty() ? "" : " \"" + source.name + "\"");
  const unsigned char* bytes = nullptr;
  size_t size = 0;
  if (source.bufferView >= 0) {
    bytes = ViewBytes(model_, source.bufferView, &size);
    if (!bytes) throw std::runtime_error(which + ": its buffer view is out of bounds");
  } else if (size_t(image) < images_.size() && !images_[image].empty()) {
    bytes = images_[image].data();
    size = images_[image].size();
  } else {
    throw std::runtime_error(which + " (\"" + source.uri + "\") cannot be read");
  }
  tinygltf::Image decoded;
  decoded.name = source.name;
  std::string err, warn;
  if (size > size_t(INT_MAX) ||
      !tinygltf::LoadImageData(&decoded, image, &err, &warn, 0, 0, bytes, int(size), nullptr)) {
    std::string type = source.mimeType.empty() ? std::string() : " (" + source.mimeType + ")";
    throw std::runtime_error(which + type + " cannot be decoded" +
                             (err.empty() ? std::string() : " (" + OneLine(err) + ")"));
  }
  return sink_.AddTexture(uint32_t(decoded.width), uint32_t(decoded.height), wrapS, wrapT,
                          LinearTexels(decoded));
}

}  // namespace pt
