// Shared test helpers: paths to the project and ../shared, and running the CLI.
#pragma once

#include <string>

namespace pt::test {

std::string SourcePath(const std::string& relative);   // inside the repository
std::string SharedPath(const std::string& relative);   // inside ../shared
bool HaveShared();                                       // false in a user's clone
std::string BinaryPath(const std::string& relative);   // inside the build folder
std::string TempDir();                                   // a fresh folder for this test

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
