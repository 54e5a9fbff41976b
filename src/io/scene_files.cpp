#include "src/io/scene_files.h"

#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace pt {
namespace {

namespace fs = std::filesystem;

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw std::runtime_error(path + ": cannot read");
  return text.str();
}

// Lenient: a file that does not parse names no further files (the loader has accepted it).
nlohmann::json ParseOrNull(const std::string& text) {
  return nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false,
                               /*ignore_comments=*/true);
}

void AddIfFile(const fs::path& path, std::vector<std::string>& files) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) files.push_back(path.string());
}

void CollectFileKeys(const nlohmann::json& j, const fs::path& base,
                     std::vector<std::string>& files) {
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) {
      if (key == "file" && value.is_string()) {
        fs::path p(value.get<std::string>());
        AddIfFile(p.is_absolute() ? p : base / p, files);
      } else {
        CollectFileKeys(value, base, files);
      }
    }
  } else if (j.is_array()) {
    for (const auto& value : j) CollectFileKeys(value, base, files);
  }
}

// A .gltf's external buffers and images (data: URIs are inside the file already).
void CollectGltfUris(const std::string& gltfPath, std::vector<std::string>& files) {
  nlohmann::json j = ParseOrNull(ReadAll(gltfPath));
  fs::path base = fs::path(gltfPath).parent_path();
  for (const char* list : {"buffers", "images"}) {
    if (!j.is_object() || !j.contains(list) || !j[list].is_array()) continue;
    for (const auto& item : j[list]) {
      if (!item.is_object() || !item.contains("uri") || !item["uri"].is_string()) continue;
      std::string uri = item["uri"].get<std::string>();
      if (uri.rfind("data:", 0) != 0) AddIfFile(base / uri, files);
    }
  }
}

// 64-bit multiply-xorshift over 8-byte words (the tail zero-padded), seeded per file with its
// length: not cryptographic, only a guard against resuming with other inputs.
uint64_t Mix(uint64_t h, uint64_t word) {
  h ^= word * 0x9E3779B97F4A7C15ull;
  h = (h << 27 | h >> 37) * 0xC2B2AE3D27D4EB4Full;
  return h ^ (h >> 31);
}

}  // namespace

std::vector<std::string> SceneInputFiles(const std::string& scenePath) {
  std::vector<std::string> files{scenePath};
  nlohmann::json scene = ParseOrNull(ReadAll(scenePath));
  CollectFileKeys(scene, fs::path(scenePath).parent_path(), files);
  size_t named = files.size();
  for (size_t i = 1; i < named; ++i) {
    std::string ext = fs::path(files[i]).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".gltf") CollectGltfUris(files[i], files);
  }
  return files;
}

uint64_t HashFiles(const std::vector<std::string>& files) {
  uint64_t h = 0x243F6A8885A308D3ull;
  for (const std::string& file : files) {
    std::string bytes = ReadAll(file);
    h = Mix(h, bytes.size());
    size_t whole = bytes.size() / 8 * 8;
    for (size_t i = 0; i < whole; i += 8) {
      uint64_t word;
      std::memcpy(&word, bytes.data() + i, 8);
      h = Mix(h, word);
    }
    uint64_t tail = 0;
    std::memcpy(&tail, bytes.data() + whole, bytes.size() - whole);
    h = Mix(h, tail);
  }
  return h;
}

std::string HashHex(uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace pt
