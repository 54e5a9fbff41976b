#include "tests/test_util.h"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "src/integrator/render_api.h"

namespace pt::test {

namespace {
// The build bakes in where things were; a copy run elsewhere (the GPU machine) overrides.
std::string Dir(const char* variable, const char* builtIn) {
  const char* v = std::getenv(variable);
  return v && *v ? v : builtIn;
}
}  // namespace

std::string SourcePath(const std::string& relative) {
  return Dir("PT_SOURCE_DIR", PT_SOURCE_DIR) + "/" + relative;
}
std::string SharedPath(const std::string& relative) {
  return Dir("PT_SHARED_DIR", PT_SHARED_DIR) + "/" + relative;
}
bool HaveShared() { return std::filesystem::exists(SharedPath("assets")); }
std::string BinaryPath(const std::string& relative) {
  return Dir("PT_BINARY_DIR", PT_BINARY_DIR) + "/" + relative;
}

namespace {

std::string MakeTempFolder() {
  static std::atomic<int> counter{0};
  auto dir = std::filesystem::temp_directory_path() /
             ("pt_test_" + std::to_string(getpid()) + "_" + std::to_string(counter++));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

// The folders TempDir handed out to the running test.
std::vector<std::unique_ptr<TempFolder>>& TestFolders() {
  static std::vector<std::unique_ptr<TempFolder>> folders;
  return folders;
}

// Removes each test's folders when it ends, and any left at the end of the program.
class TempDirCleaner : public ::testing::EmptyTestEventListener {
  void OnTestEnd(const ::testing::TestInfo&) override { TestFolders().clear(); }
  void OnTestProgramEnd(const ::testing::UnitTest&) override { TestFolders().clear(); }
};

[[maybe_unused]] const bool kCleanerInstalled = [] {
  ::testing::UnitTest::GetInstance()->listeners().Append(new TempDirCleaner);
  return true;
}();

}  // namespace

TempFolder::TempFolder() : path_(MakeTempFolder()) {}

TempFolder::~TempFolder() {
  std::error_code ignored;  // a destructor must not throw; ctest's check reports leftovers
  std::filesystem::remove_all(path_, ignored);
}

std::string TempDir() {
  TestFolders().push_back(std::make_unique<TempFolder>());
  return TestFolders().back()->Path();
}

int RunCommand(const std::string& command, std::string* output) {
  std::string full = command + " 2>&1";
  FILE* pipe = popen(full.c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buffer;
  std::string text;
  while (size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) text.append(buffer.data(), n);
  int status = pclose(pipe);
  if (output) *output = text;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void AppendRaw(std::vector<char>& bin, const void* data, size_t bytes) {
  const char* p = static_cast<const char*>(data);
  bin.insert(bin.end(), p, p + bytes);
}

bool HaveGpu() { return CudaDeviceCount() > 0; }

}  // namespace pt::test
