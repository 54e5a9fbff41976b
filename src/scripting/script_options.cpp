#include "src/scripting/script_options.h"

#include <algorithm>

namespace pt {
namespace {

// Options of the command line that a script does not take, and what it uses instead.
const std::vector<std::pair<const char*, const char*>>& RefusedKeywords() {
  static const std::vector<std::pair<const char*, const char*>> table = {
      {"o", "use result.save(PATH)"},
      {"hdr", "use result.save(\"FILE.exr\"), which keeps variance and the AOVs"},
      {"spp_map", "the sample counts are result.aovs[\"samples\"]"},
      {"stats_json", "the statistics are result.stats"},
      {"reference", "compare result.image with the reference in numpy"},
      {"preview_every", "use pathtracer.render_progressive"},
      {"progress_every", "use pathtracer.render_progressive"},
      {"checkpoint_every", "resumable renders are the command line's"},
      {"resume", "resumable renders are the command line's"},
      {"rank_timeout", "MPI jobs are the command line's"},
      {"lanes", "MPI jobs are the command line's"},
      {"serve", "the live preview is the command line's"},
      {"bind", "the live preview is the command line's"},
      {"camera", "pass it to pathtracer.Scene(source, camera=...)"},
  };
  return table;
}

}  // namespace

std::string OptionFlagName(const std::string& keyword) {
  std::string name = keyword;
  std::replace(name.begin(), name.end(), '_', '-');
  return "--" + name;
}

CliOptions OptionsFromKeywords(const OptionKeywords& keywords) {
  CliOptions options;
  for (const auto& [keyword, value] : keywords) {
    for (const auto& [name, instead] : RefusedKeywords()) {
      if (keyword == name) {
        throw UnknownOptionError("'" + keyword + "' is not a render option here: " + instead);
      }
    }
    if (keyword == "denoise") {  // the CLI's --denoise, a flag: here True or False
      if (value != "on" && value != "off") throw CliError("denoise takes True or False");
      options.denoise = value == "on";
      continue;
    }
    bool wellFormed = !keyword.empty() && keyword.find('-') == std::string::npos;
    try {
      if (!wellFormed) throw CliError("unknown option");
      ApplyCliOption(OptionFlagName(keyword), value, &options);
    } catch (const CliError& e) {
      if (std::string(e.what()).rfind("unknown option", 0) != 0) throw;
      throw UnknownOptionError("unknown option '" + keyword +
                               "' (the keywords are the command line's options: max_depth for "
                               "--max-depth; docs/python.md lists them)");
    }
  }
  return options;
}

}  // namespace pt
