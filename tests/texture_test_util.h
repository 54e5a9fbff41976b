// Hand-made textured glTF files for the texture tests: small RGBA images encoded as PNG with
// stb_image_write, and a square mesh (.gltf + .bin + .png) with TEXCOORD_0.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

// Static, as in src/io/image_io.cpp: this copy cannot clash with any other.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace pt::test {

struct RgbaImage {
  int width, height;
  std::vector<uint8_t> rgba;
  RgbaImage(int w, int h) : width(w), height(h), rgba(size_t(w) * h * 4, 0) {}
  void Set(int x, int y, uint8_t r, uint8_t g, uint8_t b, uint8_t a) {
    uint8_t* p = &rgba[(size_t(y) * width + x) * 4];
    p[0] = r, p[1] = g, p[2] = b, p[3] = a;
  }
};

// PNG bytes, rows top to bottom (as glTF and stb_image read them).
inline std::string EncodePng(const RgbaImage& image) {
  std::string out;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
  };
  stbi_write_png_to_func(append, &out, image.width, image.height, 4, image.rgba.data(),
                         image.width * 4);
  return out;
}

inline void WriteFile(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

template <typename T>
void AppendBytes(std::string& bin, const T* data, size_t count) {
  bin.append(reinterpret_cast<const char*>(data), sizeof(T) * count);
}

// dir/square.gltf (+ .bin, .png): the square [-1, 1]^2 at z = 0 facing +z, two triangles, UVs
// with the image upright seen from +z (uv (0, 0) at the top-left corner (-1, 1)), one material
// (metallic 0, base colour factor 1) with the image as its base colour texture.
inline void WriteTexturedSquareGltf(const std::string& dir, const RgbaImage& image, int wrapS,
                                    int wrapT) {
  const float positions[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const float uvs[8] = {0, 1, 1, 1, 1, 0, 0, 0};
  const uint16_t indices[6] = {0, 1, 2, 0, 2, 3};
  std::string bin;
  AppendBytes(bin, positions, 12);
  AppendBytes(bin, uvs, 8);
  AppendBytes(bin, indices, 6);
  WriteFile(dir + "/square.bin", bin);
  WriteFile(dir + "/square.png", EncodePng(image));
  std::ofstream(dir + "/square.gltf") << R"({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2,
                                "material": 0}]}],
    "materials": [{"name": "checker", "pbrMetallicRoughness": {"metallicFactor": 0,
                   "baseColorTexture": {"index": 0}}}],
    "textures": [{"source": 0, "sampler": 0}],
    "samplers": [{"wrapS": )" << wrapS << R"(, "wrapT": )" << wrapT << R"(}],
    "images": [{"uri": "square.png"}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
       "min": [-1, -1, 0], "max": [1, 1, 0]},
      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
      {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                    {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
    "buffers": [{"uri": "square.bin", "byteLength": 92}]})";
}

}  // namespace pt::test
