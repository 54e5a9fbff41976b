// Test-side encoders of compressed glTF: a .gltf file's buffer views re-encoded with
// libmeshoptimizer (EXT_meshopt_compression, lossless) and its images re-encoded as lossless
// WebP (EXT_texture_webp), written next to copies of its other files. The decoded file must
// equal the original exactly. Only .gltf files whose buffers are external files are taken.
#pragma once

#include <meshoptimizer.h>
#include <tiny_gltf.h>
#include <webp/encode.h>

#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace pt::test {

struct GltfFiles {
  nlohmann::json doc;
  std::vector<std::string> buffers;  // bytes of each buffer
  std::string folder;                // where the images' URIs resolve
};

inline std::string ReadBinaryFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline GltfFiles ReadGltfFiles(const std::string& path) {
  GltfFiles f;
  f.folder = std::filesystem::path(path).parent_path().string();
  f.doc = nlohmann::json::parse(ReadBinaryFile(path));
  for (const auto& b : f.doc["buffers"]) f.buffers.push_back(ReadBinaryFile(f.folder + "/" + b["uri"].get<std::string>()));
  return f;
}

// Every buffer view of 4n bytes meshopt-encoded into buffer 0 (index views as INDICES,
// the others as ATTRIBUTES with their stride, or 4), the rest copied there as they are; buffer
// 1 is the fallback placeholder without data.
inline GltfFiles MeshoptCompressed(const GltfFiles& in, bool khrName = false) {
  const char* name = khrName ? "KHR_meshopt_compression" : "EXT_meshopt_compression";
  GltfFiles out = in;
  std::vector<int> indexComponent(in.doc["bufferViews"].size(), 0);
  for (const auto& mesh : in.doc["meshes"]) {
    for (const auto& p : mesh["primitives"]) {
      if (!p.contains("indices")) continue;
      const auto& a = in.doc["accessors"][p["indices"].get<size_t>()];
      if (a.contains("bufferView")) indexComponent[a["bufferView"].get<size_t>()] = a["componentType"];
    }
  }
  std::string packed;
  size_t fallbackSize = 0;
  for (size_t v = 0; v < in.doc["bufferViews"].size(); ++v) {
    nlohmann::json& view = out.doc["bufferViews"][v];
    size_t offset = view.value("byteOffset", size_t(0)), length = view["byteLength"];
    std::string bytes = in.buffers[view["buffer"].get<size_t>()].substr(offset, length);
    while (packed.size() % 4) packed += '\0';
    size_t stride = view.value("byteStride", size_t(4));
    if (length % 4 != 0 || length == 0) {  // left plain
      view["buffer"] = 0;
      view["byteOffset"] = packed.size();
      packed += bytes;
      continue;
    }
    nlohmann::json ext = {{"buffer", 0}, {"byteOffset", packed.size()}};
    std::vector<unsigned char> encoded;
    if (indexComponent[v] == 5123 || indexComponent[v] == 5125) {
      size_t size = indexComponent[v] == 5123 ? 2 : 4, count = length / size;
      std::vector<unsigned int> indices(count);
      for (size_t i = 0; i < count; ++i) {
        uint32_t x = 0;
        std::memcpy(&x, bytes.data() + i * size, size);
        indices[i] = x;
      }
      encoded.resize(meshopt_encodeIndexSequenceBound(count, 1u << 20));
      encoded.resize(meshopt_encodeIndexSequence(encoded.data(), encoded.size(), indices.data(), count));
      ext.update({{"mode", "INDICES"}, {"count", count}, {"byteStride", size}});
    } else {
      if (stride % 4 != 0 || length % stride != 0) stride = 4;
      size_t count = length / stride;
      encoded.resize(meshopt_encodeVertexBufferBound(count, stride));
      encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), bytes.data(), count, stride));
      ext.update({{"mode", "ATTRIBUTES"}, {"count", count}, {"byteStride", stride}});
    }
    ext["byteLength"] = encoded.size();
    packed.append(reinterpret_cast<const char*>(encoded.data()), encoded.size());
    view["buffer"] = 1;
    view["byteOffset"] = fallbackSize;
    fallbackSize += (length + 3) / 4 * 4;
    view["extensions"][name] = ext;
  }
  out.buffers = {packed};
  out.doc["buffers"] = {{{"uri", "packed.bin"}, {"byteLength", packed.size()}},
                        {{"byteLength", fallbackSize}, {"extensions", {{name, {{"fallback", true}}}}}}};
  out.doc["extensionsUsed"].push_back(name);
  out.doc["extensionsRequired"].push_back(name);
  return out;
}

// Lossless WebP of 8-bit RGBA pixels.
inline std::string EncodeWebpLossless(const unsigned char* rgba, int width, int height) {
  uint8_t* out = nullptr;
  size_t size = WebPEncodeLosslessRGBA(rgba, width, height, width * 4, &out);
  std::string bytes(reinterpret_cast<const char*>(out), size);
  WebPFree(out);
  return bytes;
}

// Every image re-encoded as lossless WebP (decoded by tinygltf's stb first), named by each
// texture's EXT_texture_webp; keepFallback keeps the texture's own source as well.
inline void WebpTextures(GltfFiles& f, const std::string& dir, bool keepFallback) {
  nlohmann::json& images = f.doc["images"];
  size_t original = images.size();
  for (size_t i = 0; i < original; ++i) {
    std::string bytes = ReadBinaryFile(f.folder + "/" + images[i]["uri"].get<std::string>());
    tinygltf::Image image;
    std::string err, warn;
    bool decoded = tinygltf::LoadImageData(&image, int(i), &err, &warn, 0, 0,
                                           reinterpret_cast<const unsigned char*>(bytes.data()),
                                           int(bytes.size()), nullptr);
    if (!decoded || image.component != 4 || image.bits != 8) {
      throw std::runtime_error("WebpTextures: cannot decode image " + std::to_string(i) + ": " + err);
    }
    std::string file = "image" + std::to_string(i) + ".webp";
    std::ofstream(dir + "/" + file, std::ios::binary)
        << EncodeWebpLossless(image.image.data(), image.width, image.height);
    images.push_back({{"uri", file}, {"mimeType", "image/webp"}});
  }
  for (auto& t : f.doc["textures"]) {
    t["extensions"]["EXT_texture_webp"]["source"] = t["source"].get<size_t>() + original;
    if (!keepFallback) t.erase("source");
  }
  f.doc["extensionsUsed"].push_back("EXT_texture_webp");
  if (!keepFallback) f.doc["extensionsRequired"].push_back("EXT_texture_webp");
}

// dir/NAME.gltf with its buffers as dir/NAMEk.bin; images still in the source folder are
// copied (their names kept). Returns the .gltf's path.
inline std::string WriteGltfFiles(GltfFiles f, const std::string& dir, const std::string& name) {
  for (size_t b = 0; b < f.buffers.size(); ++b) {
    std::string file = name + std::to_string(b) + ".bin";
    std::ofstream(dir + "/" + file, std::ios::binary) << f.buffers[b];
    f.doc["buffers"][b]["uri"] = file;
  }
  for (const auto& image : f.doc["images"]) {
    std::string uri = image.value("uri", "");
    std::filesystem::path from = std::filesystem::path(f.folder) / uri;
    if (!uri.empty() && std::filesystem::exists(from) && !std::filesystem::exists(dir + "/" + uri)) {
      std::filesystem::create_directories(std::filesystem::path(dir + "/" + uri).parent_path());
      std::filesystem::copy_file(from, dir + "/" + uri);
    }
  }
  std::ofstream(dir + "/" + name + ".gltf") << f.doc.dump();
  return dir + "/" + name + ".gltf";
}

}  // namespace pt::test
