// Shared test helpers: paths to the project and ../shared, temporary folders, running the CLI,
// files as bytes, bit-for-bit comparison and whether a GPU is present.
#pragma once

#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

namespace pt::test {

std::string SourcePath(const std::string& relative);   // inside the repository
std::string SharedPath(const std::string& relative);   // inside ../shared
bool HaveShared();                                       // false in a user's clone
std::string BinaryPath(const std::string& relative);   // inside the build folder

// A fresh folder under the temporary directory, removed with its contents when destroyed.
class TempFolder {
 public:
  TempFolder();
  ~TempFolder();
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  const std::string& Path() const { return path_; }

 private:
  std::string path_;
};

// A fresh folder for the running test, removed when the test ends (passed, failed or
// skipped); ctest checks that a test run leaves nothing behind (tests/CMakeLists.txt).
std::string TempDir();

// Runs a shell command; returns its exit status (the shell's, 128+n for signals).
int RunCommand(const std::string& command, std::string* output = nullptr);

// The whole file, byte for byte ("" when it cannot be read).
std::string ReadText(const std::string& path);

// Appends `bytes` bytes from `data` to a binary buffer being assembled (a glTF .bin).
void AppendRaw(std::vector<char>& bin, const void* data, size_t bytes);

// Same size and the same bytes: floats bit for bit (NaNs and -0 too, unlike ==), structs as
// stored. memcmp only where there are bytes: an empty vector's data() may be null.
template <typename T>
bool BitIdentical(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Whether a CUDA GPU is here: the GPU tests skip without one (and on a CPU-only build).
bool HaveGpu();

}  // namespace pt::test
