// The render options of a script (the Python module's keywords) as the command line's: each
// keyword is the option of the same name (max_depth is --max-depth), parsed by the CLI's own
// handlers, so values, checks and messages are the CLI's and an option added there is a
// keyword here with no further code. Options about files the CLI writes, or about the
// command line itself, are refused with what to use instead.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "src/app/cli.h"

namespace pt {

// A keyword that names no render option (TypeError in Python, as for any unknown keyword).
struct UnknownOptionError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

using OptionKeywords = std::vector<std::pair<std::string, std::string>>;  // name, value text

// "max_depth" -> "--max-depth".
std::string OptionFlagName(const std::string& keyword);

// Applies the keywords in order to a default CliOptions. Throws UnknownOptionError for a name
// that is no option (or one a script does not take) and CliError for a bad value.
CliOptions OptionsFromKeywords(const OptionKeywords& keywords);

}  // namespace pt
