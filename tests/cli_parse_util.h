// Helpers for tests of the command-line parser: parse an argument list as `pathtracer ARGS`,
// or get the parser's message for one it refuses.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "src/app/cli.h"

namespace pt::test {

inline CliOptions Parse(std::vector<const char*> args) {
  args.insert(args.begin(), "pathtracer");
  return ParseCli(int(args.size()), args.data());
}

// The parser's message, or "" when the command line was accepted.
inline std::string ParseError(std::vector<const char*> args) {
  try {
    Parse(std::move(args));
  } catch (const CliError& e) {
    return e.what();
  }
  return "";
}

}  // namespace pt::test
