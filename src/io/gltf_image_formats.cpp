#include "src/io/gltf_image_formats.h"

#include <tiny_gltf.h>
#include <webp/decode.h>

#include <cstring>
#include <stdexcept>

namespace pt {

int GltfTextureImageSource(const tinygltf::Texture& texture) {
  auto webp = texture.extensions.find("EXT_texture_webp");
  if (webp != texture.extensions.end() && webp->second.IsObject() &&
      webp->second.Has("source") && webp->second.Get("source").IsInt()) {
    return webp->second.Get("source").GetNumberAsInt();
  }
  return texture.source;
}

bool DecodeGltfImageFormat(const unsigned char* bytes, size_t size, const std::string& which,
                           tinygltf::Image* out) {
  static const unsigned char kKtx2[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
  if (size >= 12 && std::memcmp(bytes, kKtx2, 12) == 0) {
    throw std::runtime_error(which + " is a KTX2 image (KHR_texture_basisu), which this renderer "
                             "cannot decode; give the texture a PNG or JPEG fallback \"source\"");
  }
  bool webp = size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 && std::memcmp(bytes + 8, "WEBP", 4) == 0;
  if (!webp) return false;
  int width = 0, height = 0;
  uint8_t* rgba = nullptr;
  if (WebPGetInfo(bytes, size, &width, &height)) rgba = WebPDecodeRGBA(bytes, size, &width, &height);
  if (!rgba) throw std::runtime_error(which + " (WebP) cannot be decoded: truncated or corrupt");
  out->width = width;
  out->height = height;
  out->component = 4;
  out->bits = 8;
  out->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  out->image.assign(rgba, rgba + size_t(width) * size_t(height) * 4);
  WebPFree(rgba);
  return true;
}

}  // namespace pt
