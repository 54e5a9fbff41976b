// A failure with its exit status: thrown by the app's steps, caught once in RunApp, which
// prints the message and returns the status.
#pragma once

#include <string>

namespace pt {

struct AppFailure {
  int status;
  std::string message;
};

}  // namespace pt
