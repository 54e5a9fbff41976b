// The files a scene is made of, and a hash of their bytes: what identifies "the same scene"
// when a render is resumed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pt {

// The scene file, every file it names (the value of any "file" key, anywhere in it, relative to
// its folder), and for each .gltf among them its external buffers and images. In a fixed
// order; names that do not exist are left out (the loader reports those).
std::vector<std::string> SceneInputFiles(const std::string& scenePath);

// A 64-bit hash of the files' contents, in order (not of their names: a moved scene folder
// is the same scene). Throws std::runtime_error when a file cannot be read.
uint64_t HashFiles(const std::vector<std::string>& files);

// The hash as 16 hex digits.
std::string HashHex(uint64_t hash);

}  // namespace pt
