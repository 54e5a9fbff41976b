#include "src/app/resume.h"

#include <algorithm>

#include "src/app/app_failure.h"
#include "src/app/run.h"
#include "src/io/film_state_exr.h"
#include "src/io/image_io.h"
#include "src/io/scene_files.h"

namespace pt {
namespace {

using Json = nlohmann::ordered_json;

constexpr int kDescriptionFormat = 1;

// The keys that must be equal, with the words a message uses for each.
constexpr std::pair<const char*, const char*> kIdentity[] = {
    {"scene_hash", "scene files (the scene and the files it names, by content)"},
    {"image_size", "image size"},
    {"crop", "crop window"},
    {"seed", "seed"},
    {"max_depth", "max depth"},
    {"rr_depth", "Russian roulette depth"},
    {"integrator", "integrator"},
    {"light_paths", "light paths"},
    {"clamp", "firefly clamp"},
    {"ray_offset", "ray offset"},
    {"tri_test", "triangle test"},
    {"adaptive", "adaptive sampling"},
    {"environment", "environment (--env, --env-strength)"},
    {"env_sampling", "environment sampling"},
    {"sampler", "sampler (--sampler)"},
    {"texture_filter", "texture filter footprint (follows --spp below 64 spp)"},
    {"media", "media (--fog, --transmittance)"},
};

const char* IntegratorName(IntegratorMode m) {
  return m == IntegratorMode::kBsdf ? "bsdf" : m == IntegratorMode::kNee ? "nee" : "mis";
}

const char* TriangleTestName(TriangleTest t) {
  if (t == TriangleTest::kMollerTrumbore) return "mt";
  return t == TriangleTest::kBoxClamped ? "box-clamped" : "watertight";
}

const char* LightPathsName(LightPaths l) {
  return l == LightPaths::kDirect ? "direct" : l == LightPaths::kIndirect ? "indirect" : "all";
}

// What the command line does to the scene's environment: a --env map (by content) and a
// --env-strength; the scene's own environment is in scene_hash.
std::string EnvironmentOverrides(const CliOptions& cli) {
  std::string text = cli.envPath.empty()      ? "the scene's"
                     : cli.envPath == kEnvNone ? "none"
                                               : "--env map " + HashHex(HashFiles({cli.envPath}));
  if (cli.envStrength) text += ", strength " + Json(*cli.envStrength).dump();
  return text;
}

std::string Text(const Json& j) { return j.is_string() ? j.get<std::string>() : j.dump(); }

[[noreturn]] void Refuse(const CliOptions& cli, const std::string& why) {
  throw AppFailure{kExitBadInput, cli.resumePath + ": cannot resume: " + why};
}

// Each identity key that differs, one per line.
std::string Differences(const Json& saved, const Json& current) {
  std::string lines;
  for (const auto& [key, words] : kIdentity) {
    Json was = saved.contains(key) ? saved[key] : Json(nullptr);
    // Checkpoints from before --sampler drew independent numbers.
    if (was.is_null() && std::string(key) == "sampler") was = "independent";
    if (was == current[key]) continue;
    lines += std::string("\n  ") + words + ": " +
             (std::string(key) == "scene_hash"
                  ? "changed since the checkpoint (" + Text(current["scene_file"]) + ")"
                  : Text(was) + " in the checkpoint, " + Text(current[key]) + " now");
  }
  return lines;
}

}  // namespace

Json DescribeRender(const CliOptions& cli, const Scene& scene, const RenderOptions& options,
                    bool adaptive) {
  const RenderSettings& r = scene.desc.render;
  CropWindow crop = options.crop;
  std::string cropText = crop.Empty() ? "whole image"
                                      : std::to_string(crop.x0) + " " + std::to_string(crop.y0) +
                                            " " + std::to_string(crop.x1) + " " +
                                            std::to_string(crop.y1);
  return Json{
      {"format", kDescriptionFormat},
      {"version", PT_VERSION},
      {"scene_file", cli.scenePath},
      {"scene_hash", HashHex(HashFiles(SceneInputFiles(cli.scenePath)))},
      {"image_size", std::to_string(r.width) + "x" + std::to_string(r.height)},
      {"crop", cropText},
      {"seed", r.seed},
      {"spp", r.spp},
      {"max_depth", r.maxDepth},
      {"rr_depth", r.russianRouletteDepth >= kRussianRouletteOff ? Json("off")
                                                                 : Json(r.russianRouletteDepth)},
      {"integrator", IntegratorName(options.integrator)},
      {"light_paths", LightPathsName(options.lightPaths)},
      {"clamp", options.clampLuminance > 0.0f ? Json(options.clampLuminance) : Json("off")},
      {"ray_offset", options.rayOffsetEpsilon > 0.0f ? Json(options.rayOffsetEpsilon)
                                                     : Json("robust")},
      {"tri_test", TriangleTestName(options.triangleTest)},
      {"adaptive", adaptive},
      {"environment", EnvironmentOverrides(cli)},
      {"env_sampling", options.envSampling == EnvSampling::kUniform ? "uniform" : "importance"},
      {"sampler", SamplerKindName(options.sampler.value_or(r.sampler))},
      {"media", (cli.fogSigmaS ? "--fog " + Json(*cli.fogSigmaS).dump() : std::string("no --fog")) +
                    (options.transmittance == TransmittanceMode::kDelta ? ", delta tracking"
                                                                        : ", ratio tracking")},
      {"film", options.filmDouble ? "double" : "float"},
      // Only a textured scene's image depends on it (a larger --spp then changes the image).
      {"texture_filter", scene.desc.textures.empty() ? Json("no textures")
                                                     : Json(scene.camera.textureFootprint)},
  };
}

FilmState LoadResumeFilm(const CliOptions& cli, const std::string& currentText) {
  Json current = Json::parse(currentText);
  ResumableExr saved;
  try {
    saved = ReadResumableExr(cli.resumePath);
  } catch (const ImageError& e) {
    throw AppFailure{kExitBadInput, e.what()};
  }
  Json description = Json::parse(saved.description, nullptr, false);
  if (!description.is_object() || description.value("format", 0) != kDescriptionFormat) {
    Refuse(cli, "its state was written by another version of the renderer (" +
                    saved.description.substr(0, 80) + ")");
  }
  std::string differences = Differences(description, current);
  if (!differences.empty()) {
    Refuse(cli, "it is a render of another scene or with other settings:" + differences);
  }
  if (current["adaptive"].get<bool>()) {
    Refuse(cli, "resuming an adaptive render is not supported yet (--adaptive off renders "
                "one that can be resumed)");
  }
  uint32_t most = saved.film.count.empty()
                      ? 0
                      : *std::max_element(saved.film.count.begin(), saved.film.count.end());
  int spp = current["spp"].get<int>();
  if (most > uint32_t(spp)) {
    Refuse(cli, "its pixels hold up to " + std::to_string(most) + " samples, more than the " +
                    std::to_string(spp) + " spp asked for now (give --spp " +
                    std::to_string(description.value("spp", int(most))) + " as before)");
  }
  return std::move(saved.film);
}

}  // namespace pt
