// The image formats of glTF textures beyond PNG and JPEG (which stb decodes): EXT_texture_webp
// (decoded by Debian's libwebp) and KHR_texture_basisu (KTX2: no Debian decoder, so the
// texture's fallback image is used; a texture without one is refused before parsing, in
// src/io/gltf_document.cpp).
#pragma once

#include <cstddef>
#include <string>

namespace tinygltf {
struct Image;
struct Texture;
}  // namespace tinygltf

namespace pt {

// The image a texture shows: EXT_texture_webp's source when it has one, else its own "source"
// (for a KHR_texture_basisu texture, the fallback PNG or JPEG); -1 when none.
int GltfTextureImageSource(const tinygltf::Texture& texture);

// Decodes what stb cannot: WebP bytes into 8-bit RGBA (true). A KTX2 image throws
// std::runtime_error naming `which`, KTX2 and KHR_texture_basisu; a broken WebP one throws too.
// Any other bytes return false (stb's turn).
bool DecodeGltfImageFormat(const unsigned char* bytes, size_t size, const std::string& which,
                           tinygltf::Image* out);

}  // namespace pt
