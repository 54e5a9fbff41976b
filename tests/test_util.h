// Shared test helpers: paths to the project and ../shared, temporary folders, and running the
// CLI.
#pragma once

#include <string>

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

// A fresh folder that is removed, with everything in it, when this goes out of scope.
struct ScopedTempDir {
  std::string path = TempDir();
  ScopedTempDir() = default;
  ScopedTempDir(const ScopedTempDir&) = delete;
  ScopedTempDir& operator=(const ScopedTempDir&) = delete;
  ~ScopedTempDir();
  operator const std::string&() const { return path; }
};

// Runs a shell command; returns its exit status (the shell's, 128+n for signals).
int RunCommand(const std::string& command, std::string* output = nullptr);

}  // namespace pt::test
