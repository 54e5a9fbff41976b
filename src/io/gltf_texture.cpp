// The textures of glTF materials: KHR_texture_transform and the UV set of each slot, samplers'
// wrap modes, and images decoded (on first use, once per colour space) to RGBA8 pyramids.
#include <tiny_gltf.h>

#include <climits>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "src/io/gltf_image_formats.h"
#include "src/io/gltf_material.h"
#include "src/materials/texture_pyramid.h"

namespace pt {
namespace {

using tinygltf::Value;

TextureWrap WrapOf(int mode, bool* unknown) {
  switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_REPEAT: return TextureWrap::kRepeat;
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TextureWrap::kClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TextureWrap::kMirroredRepeat;
    default: *unknown = true; return TextureWrap::kRepeat;
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

// Decoded pixels (1 to 4 channels of 8 or 16 bits, as tinygltf gives them) as packed RGBA8:
// grey fills RGB, a missing alpha is opaque, 16-bit values round to the nearest 8-bit code.
std::vector<uint32_t> Rgba8Texels(const tinygltf::Image& img, bool* wide) {
  size_t count = size_t(img.width) * size_t(img.height);
  int comp = img.component, bytes = img.bits / 8;
  if (comp < 1 || comp > 4 || (bytes != 1 && bytes != 2) ||
      img.image.size() < count * size_t(comp) * size_t(bytes)) {
    throw std::runtime_error("image \"" + img.name + "\" was decoded inconsistently");
  }
  *wide = bytes == 2;
  auto channel = [&](size_t i, int c) -> uint32_t {
    size_t at = (i * comp + c) * bytes;
    if (bytes == 1) return img.image[at];
    uint16_t v;
    std::memcpy(&v, &img.image[at], 2);
    return (uint32_t(v) * 255u + 32767u) / 65535u;
  };
  std::vector<uint32_t> out(count);
  for (size_t i = 0; i < count; ++i) {
    bool grey = comp < 3;
    uint32_t r = channel(i, 0), g = grey ? r : channel(i, 1), b = grey ? r : channel(i, 2);
    uint32_t a = comp == 2 ? channel(i, 1) : (comp == 4 ? channel(i, 3) : 255u);
    out[i] = PackRgba8(r, g, b, a);
  }
  return out;
}

double NumberOr(const Value& v, double fallback) {
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

// KHR_texture_transform's T * R * S as the reference's two rows; false when malformed.
bool TransformRows(const Value& t, TextureRef* r) {
  double offset[2] = {0, 0}, scale[2] = {1, 1}, rotation = 0;
  for (const char* key : {"offset", "scale"}) {
    if (!t.Has(key)) continue;
    const Value& v = t.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 2) return false;
    double* out = key[0] == 'o' ? offset : scale;
    for (int i = 0; i < 2; ++i) out[i] = NumberOr(v.Get(i), NAN);
  }
  if (t.Has("rotation")) rotation = NumberOr(t.Get("rotation"), NAN);
  double c = std::cos(rotation), s = std::sin(rotation);
  r->row0 = vec3(float(c * scale[0]), float(s * scale[1]), float(offset[0]));
  r->row1 = vec3(float(-s * scale[0]), float(c * scale[1]), float(offset[1]));
  return IsFinite(r->row0) && IsFinite(r->row1);
}

}  // namespace

int32_t GltfMaterialTable::AddSlot(const Slot& slot, bool srgb, const char* name, int material) {
  if (slot.texture < 0) return -1;
  TextureRef ref;
  int set = slot.texCoord;
  if (slot.transform) {
    if (slot.transform->Has("texCoord") && slot.transform->Get("texCoord").IsInt())
      set = slot.transform->Get("texCoord").GetNumberAsInt();
    if (!TransformRows(*slot.transform, &ref)) {
      Note("malformed KHR_texture_transform ignored", material);
      ref = TextureRef{};
    }
  }
  if (set < 0 || set > 1) {
    Note(std::string(name) + " TEXCOORD_" + std::to_string(set) + " read as TEXCOORD_0", material);
    set = 0;
  }
  ref.texture = SceneTexture(slot.texture, srgb, material);
  if (ref.texture < 0) return -1;
  ref.texCoord = uint32_t(set);
  needs_[material < 0 ? needs_.size() - 1 : size_t(material)].uv[set] = true;
  return sink_.AddTextureRef(ref);
}

// The scene texture for glTF texture `texture` in one colour space (its image's texels with
// its sampler's wrap modes), or -1 with a note when it cannot be used.
int32_t GltfMaterialTable::SceneTexture(int texture, bool srgb, int material) {
  if (size_t(texture) >= model_.textures.size()) {
    throw std::runtime_error("texture " + std::to_string(texture) + " does not exist");
  }
  auto cached = textures_.find({texture, srgb});
  if (cached != textures_.end()) {
    if (cached->second < 0) Note("unusable textures ignored, factors used", material);
    return cached->second;
  }
  int32_t& slot = textures_[{texture, srgb}];
  slot = -1;
  const tinygltf::Texture& t = model_.textures[texture];
  TextureWrap wrapS = TextureWrap::kRepeat, wrapT = TextureWrap::kRepeat;
  if (t.sampler >= 0) {
    if (size_t(t.sampler) >= model_.samplers.size()) {
      throw std::runtime_error("sampler " + std::to_string(t.sampler) + " does not exist");
    }
    const tinygltf::Sampler& s = model_.samplers[t.sampler];
    bool unknown = false;
    wrapS = WrapOf(s.wrapS, &unknown);
    wrapT = WrapOf(s.wrapT, &unknown);
    if (unknown) Note("unknown sampler wrap mode read as REPEAT", material);
    if (s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST) {
      Note("NEAREST magnification rendered bilinear", material);
    }
  }
  int source = GltfTextureImageSource(t);  // EXT_texture_webp's, or KHR_texture_basisu's fallback
  if (source < 0) {
    std::string extensions;
    for (const auto& [name, value] : t.extensions) extensions += " " + name;
    Note("textures without an image this renderer reads (" +
             (extensions.empty() ? std::string("no source") : extensions.substr(1)) +
             ") ignored, factors used",
         material);
    return -1;
  }
  if (size_t(source) >= model_.images.size()) {
    throw std::runtime_error("image " + std::to_string(source) + " does not exist");
  }
  auto texels = imageTexels_.find({source, srgb});
  int32_t stored = texels != imageTexels_.end() ? texels->second
                                                : ImageTexels(source, srgb, wrapS, wrapT, material);
  imageTexels_[{source, srgb}] = stored;
  if (stored < 0) {
    Note("unusable textures ignored, factors used", material);
    return -1;
  }
  slot = stored;
  const pt::Texture& kept = sink_.TextureAt(stored);
  if (kept.wrapS != wrapS || kept.wrapT != wrapT) {
    slot = sink_.AddTextureView(stored, wrapS, wrapT);  // same texels, other sampler
  }
  return slot;
}

// Decodes image `image` and stores it as a scene texture. An image a used material needs that
// is missing or that stb cannot decode is bad input (the picture would silently lose it).
int32_t GltfMaterialTable::ImageTexels(int image, bool srgb, TextureWrap wrapS, TextureWrap wrapT,
                                       int material) {
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
  bool other = DecodeGltfImageFormat(bytes, size, which, &decoded);  // WebP; KTX2 refused
  if (!other && (size > size_t(INT_MAX) || !tinygltf::LoadImageData(&decoded, image, &err, &warn,
                                                                     0, 0, bytes, int(size), nullptr))) {
    std::string type = source.mimeType.empty() ? std::string() : " (" + source.mimeType + ")";
    throw std::runtime_error(which + type + " cannot be decoded" +
                             (err.empty() ? std::string() : " (" + OneLine(err) + ")"));
  }
  bool wide = false;
  std::vector<uint32_t> texels = Rgba8Texels(decoded, &wide);
  if (wide) Note("16-bit images stored with 8 bits per channel", material);
  return sink_.AddTexture(uint32_t(decoded.width), uint32_t(decoded.height), wrapS, wrapT, srgb,
                          texels);
}

}  // namespace pt
