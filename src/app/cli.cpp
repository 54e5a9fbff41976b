#include "src/app/cli.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <utility>

#include "src/io/image_io.h"
#include "src/server/api.h"

namespace pt {
namespace {

constexpr int kMaxImageSide = 1 << 16;
constexpr int64_t kMaxImagePixels = int64_t(1) << 28;
constexpr int kIntMax = std::numeric_limits<int>::max();

// The tokens after one option: its `=value`, or the next arguments.
class ValueSource {
 public:
  ValueSource(std::string option, std::optional<std::string> inlineValue,
              const std::vector<std::string>& args, size_t* next)
      : option_(std::move(option)), inline_(std::move(inlineValue)), args_(args), next_(next) {}

  const std::string& Option() const { return option_; }

  // The option's value; a following `--option` is not taken as one.
  std::string Take() {
    if (inline_) return *std::exchange(inline_, std::nullopt);
    if (*next_ >= args_.size() || args_[*next_].rfind("--", 0) == 0) {
      throw CliError("missing value for " + option_);
    }
    return args_[(*next_)++];
  }

 private:
  std::string option_;
  std::optional<std::string> inline_;
  const std::vector<std::string>& args_;
  size_t* next_;
};

int64_t ParseInteger(const std::string& option, const std::string& text, int64_t lo,
                     int64_t hi) {
  int64_t value = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) {
    throw CliError("bad number for " + option + ": '" + text + "'");
  }
  if (value < lo || value > hi) {
    throw CliError(option + " must be between " + std::to_string(lo) + " and " +
                   std::to_string(hi) + ", not " + text);
  }
  return value;
}

int ParseInt(ValueSource& src, int lo, int hi) {
  return int(ParseInteger(src.Option(), src.Take(), lo, hi));
}

// A finite number > 0 that fits a float; `what` names it in messages.
double ParsePositiveNumber(ValueSource& src, const char* what) {
  std::string text = src.Take();
  char* end = nullptr;
  double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value) || value > 1e30) {
    throw CliError("bad number for " + src.Option() + ": '" + text + "' (expected " + what +
                   ")");
  }
  if (value <= 0.0) throw CliError(src.Option() + " must be greater than 0, not " + text);
  return value;
}

double ParsePositiveSeconds(ValueSource& src) { return ParsePositiveNumber(src, "seconds"); }

template <typename T>
T ParseChoice(ValueSource& src, std::initializer_list<std::pair<const char*, T>> choices) {
  std::string text = src.Take();
  std::string names;
  for (const auto& [name, value] : choices) {
    if (text == name) return value;
    names += names.empty() ? name : std::string("|") + name;
  }
  throw CliError("bad value for " + src.Option() + ": '" + text + "' (expected " + names + ")");
}

CropWindow ParseCrop(ValueSource& src) {
  std::vector<std::string> parts;
  std::string first = src.Take();
  if (first.find(',') != std::string::npos) {
    size_t start = 0;  // --crop=X0,Y0,X1,Y1 or --crop X0,Y0,X1,Y1
    for (size_t comma; (comma = first.find(',', start)) != std::string::npos; start = comma + 1) {
      parts.push_back(first.substr(start, comma - start));
    }
    parts.push_back(first.substr(start));
  } else {
    parts.push_back(first);
    for (int i = 0; i < 3; ++i) parts.push_back(src.Take());
  }
  if (parts.size() != 4) throw CliError("--crop needs four numbers: X0 Y0 X1 Y1");
  CropWindow crop;
  crop.x0 = int(ParseInteger("--crop", parts[0], 0, kMaxImageSide));
  crop.y0 = int(ParseInteger("--crop", parts[1], 0, kMaxImageSide));
  crop.x1 = int(ParseInteger("--crop", parts[2], 0, kMaxImageSide));
  crop.y1 = int(ParseInteger("--crop", parts[3], 0, kMaxImageSide));
  if (crop.Empty()) throw CliError("--crop needs X0 < X1 and Y0 < Y1");
  return crop;
}

std::string TakePath(ValueSource& src) {
  std::string path = src.Take();
  if (path.empty()) throw CliError("empty file name for " + src.Option());
  return path;
}

using Handler = std::function<void(CliOptions&, ValueSource&)>;

// Options that take a file or a number.
const std::vector<std::pair<std::string, Handler>>& ValueOptions() {
  static const std::vector<std::pair<std::string, Handler>> table = {
      {"-o", [](CliOptions& o, ValueSource& s) { o.outputPath = TakePath(s); }},
      {"--hdr", [](CliOptions& o, ValueSource& s) { o.hdrPath = TakePath(s); }},
      {"--reference", [](CliOptions& o, ValueSource& s) { o.referencePath = TakePath(s); }},
      {"--stats-json", [](CliOptions& o, ValueSource& s) { o.statsJsonPath = TakePath(s); }},
      {"--spp", [](CliOptions& o, ValueSource& s) { o.spp = ParseInt(s, 1, kIntMax); }},
      {"--width", [](CliOptions& o, ValueSource& s) { o.width = ParseInt(s, 1, kMaxImageSide); }},
      {"--height",
       [](CliOptions& o, ValueSource& s) { o.height = ParseInt(s, 1, kMaxImageSide); }},
      {"--max-depth",
       [](CliOptions& o, ValueSource& s) { o.maxDepth = ParseInt(s, 0, kMaxBounces); }},
      {"--seed",
       [](CliOptions& o, ValueSource& s) {
         o.seed = uint32_t(ParseInteger(s.Option(), s.Take(), 0, UINT32_MAX));
       }},
      {"--threads", [](CliOptions& o, ValueSource& s) { o.threads = ParseInt(s, 0, 1 << 16); }},
      {"--bind", [](CliOptions& o, ValueSource& s) { o.bindAddress = s.Take(); }},
      {"--env-dir", [](CliOptions& o, ValueSource& s) { o.envFolder = TakePath(s); }},
      {"--exposure",
       [](CliOptions& o, ValueSource& s) {
         std::string text = s.Take();
         char* end = nullptr;
         double v = std::strtod(text.c_str(), &end);
         if (text.empty() || *end != '\0' || !std::isfinite(v) || std::fabs(v) > 20.0) {
           throw CliError("bad value for --exposure: '" + text + "' (stops in [-20, 20])");
         }
         o.display.exposure = float(v);
       }},
      {"--tonemap",
       [](CliOptions& o, ValueSource& s) {
         std::string name = s.Take();
         if (!ParseToneMapping(name, &o.display.toneMapping)) {
           throw CliError("bad value for --tonemap: '" + name + "' (expected clip|agx)");
         }
       }},
      {"--time-limit",
       [](CliOptions& o, ValueSource& s) { o.timeLimitSeconds = ParsePositiveSeconds(s); }},
      {"--preview-every",
       [](CliOptions& o, ValueSource& s) { o.previewEverySeconds = ParsePositiveSeconds(s); }},
      {"--crop", [](CliOptions& o, ValueSource& s) { o.crop = ParseCrop(s); }},
      {"--camera",
       [](CliOptions& o, ValueSource& s) {
         o.camera = s.Take();
         if (o.camera.empty()) throw CliError("empty camera for --camera (an index or a name)");
       }},
      {"--animation",
       [](CliOptions& o, ValueSource& s) {
         o.animation = s.Take();
         if (o.animation.empty()) throw CliError("empty animation for --animation (an index or a name)");
       }},
      {"--time",
       [](CliOptions& o, ValueSource& s) {
         std::string text = s.Take();
         char* end = nullptr;
         double t = std::strtod(text.c_str(), &end);
         if (text.empty() || *end != '\0' || !std::isfinite(t) || std::fabs(t) > 1e30) {
           throw CliError("bad number for --time: '" + text + "' (expected seconds)");
         }
         o.time = t;
       }},
      {"--variant",
       [](CliOptions& o, ValueSource& s) {
         o.variant = s.Take();
         if (o.variant.empty()) throw CliError("empty name for --variant (a material variant)");
       }},
      {"--env", [](CliOptions& o, ValueSource& s) { o.envPath = TakePath(s); }},
      {"--env-strength",
       [](CliOptions& o, ValueSource& s) {
         std::string text = s.Take();
         char* end = nullptr;
         double v = std::strtod(text.c_str(), &end);
         if (text.empty() || *end != '\0' || !std::isfinite(v) || v < 0.0 || v > 1e30) {
           throw CliError("bad value for --env-strength: '" + text + "' (a number >= 0)");
         }
         o.envStrength = float(v);
       }},
      {"--fog",
       [](CliOptions& o, ValueSource& s) {
         o.fogSigmaS = float(ParsePositiveNumber(s, "a scattering coefficient per unit length"));
       }},
      {"--max-paths",
       [](CliOptions& o, ValueSource& s) { o.maxPaths = size_t(ParseInt(s, 1, kIntMax)); }},
      {"--clamp",
       [](CliOptions& o, ValueSource& s) {
         o.clampLuminance = float(ParsePositiveNumber(s, "a luminance"));
       }},
      {"--progress-every",
       [](CliOptions& o, ValueSource& s) { o.progressEverySeconds = ParsePositiveSeconds(s); }},
      {"--checkpoint-every",
       [](CliOptions& o, ValueSource& s) { o.checkpointEverySeconds = ParsePositiveSeconds(s); }},
      {"--resume", [](CliOptions& o, ValueSource& s) { o.resumePath = TakePath(s); }},
      {"--chunks", [](CliOptions& o, ValueSource& s) { o.chunks = ParseInt(s, 1, 1 << 20); }},
      {"--rank-timeout",
       [](CliOptions& o, ValueSource& s) { o.rankTimeoutSeconds = ParsePositiveSeconds(s); }},
      {"--lanes", [](CliOptions& o, ValueSource& s) { o.lanes = ParseInt(s, 1, 16); }},
      {"--denoise-radius",  // DenoiseSettingsProblem's range
       [](CliOptions& o, ValueSource& s) { o.denoiseRadius = ParseInt(s, 1, 20); }},
      {"--rr-depth",
       [](CliOptions& o, ValueSource& s) {
         std::string text = s.Take();
         o.rrDepth = text == "off" ? kRussianRouletteOff
                                   : int(ParseInteger(s.Option(), text, 0, 1 << 16));
       }},
  };
  return table;
}

// Options that pick one of a few named values.
const std::vector<std::pair<std::string, Handler>>& ChoiceOptions() {
  static const std::vector<std::pair<std::string, Handler>> table = {
      {"--backend",
       [](CliOptions& o, ValueSource& s) {
         o.backend = ParseChoice<BackendKind>(
             s, {{"auto", BackendKind::kAuto}, {"cpu", BackendKind::kCpu},
                 {"cuda", BackendKind::kCuda}});
       }},
      {"--ray-order",
       [](CliOptions& o, ValueSource& s) {
         o.rayOrder = ParseChoice<Toggle>(
             s, {{"on", Toggle::kOn}, {"off", Toggle::kOff}, {"auto", Toggle::kAuto}});
       }},
      {"--prim-pool",
       [](CliOptions& o, ValueSource& s) {
         o.primPool = ParseChoice<Toggle>(
             s, {{"on", Toggle::kOn}, {"off", Toggle::kOff}, {"auto", Toggle::kAuto}});
       }},
      {"--warm-up",
       [](CliOptions& o, ValueSource& s) {
         o.warmUp = ParseChoice<Toggle>(
             s, {{"on", Toggle::kOn}, {"off", Toggle::kOff}, {"auto", Toggle::kAuto}});
       }},
      {"--denoise-outliers",
       [](CliOptions& o, ValueSource& s) {
         o.denoiseOutliers = ParseChoice<bool>(s, {{"on", true}, {"off", false}});
       }},
      {"--denoise-variance",
       [](CliOptions& o, ValueSource& s) {
         o.denoiseCalibrate = ParseChoice<bool>(s, {{"calibrated", true}, {"sample", false}});
       }},
      {"--denoise-emission",
       [](CliOptions& o, ValueSource& s) {
         o.denoiseKeepEmission = ParseChoice<bool>(s, {{"keep", true}, {"filter", false}});
       }},
      {"--compact",
       [](CliOptions& o, ValueSource& s) {
         o.compact = ParseChoice<Toggle>(
             s, {{"on", Toggle::kOn}, {"off", Toggle::kOff}, {"auto", Toggle::kAuto}});
       }},
      {"--sort",
       [](CliOptions& o, ValueSource& s) {
         o.sort = ParseChoice<SortMode>(
             s, {{"off", SortMode::kOff}, {"material", SortMode::kMaterial},
                 {"queues", SortMode::kQueues}, {"auto", SortMode::kAuto}});
       }},
      {"--sort-method",
       [](CliOptions& o, ValueSource& s) {
         o.sortMethod = ParseChoice<SortMethod>(
             s, {{"auto", SortMethod::kAuto}, {"counting", SortMethod::kCounting},
                 {"radix", SortMethod::kRadix}, {"radix32", SortMethod::kRadixFullWidth}});
       }},
      {"--integrator",
       [](CliOptions& o, ValueSource& s) {
         o.integrator = ParseChoice<IntegratorMode>(
             s, {{"mis", IntegratorMode::kMis}, {"bsdf", IntegratorMode::kBsdf},
                 {"nee", IntegratorMode::kNee}});
       }},
      {"--env-sampling",
       [](CliOptions& o, ValueSource& s) {
         o.envSampling = ParseChoice<EnvSampling>(
             s, {{"importance", EnvSampling::kImportance}, {"uniform", EnvSampling::kUniform}});
        }},
      {"--light-sampler",
       [](CliOptions& o, ValueSource& s) {
         o.lightSampler = ParseChoice<LightSampler>(
             s, {{"uniform", LightSampler::kUniform}, {"power", LightSampler::kPower},
                 {"bvh", LightSampler::kBvh}, {"auto", LightSampler::kAuto}});
       }},
      {"--sampler",
       [](CliOptions& o, ValueSource& s) {
         o.sampler = ParseChoice<SamplerKind>(
             s, {{"independent", SamplerKind::kIndependent}, {"sobol", SamplerKind::kSobol}});
       }},
      {"--transmittance",
       [](CliOptions& o, ValueSource& s) {
         o.transmittance = ParseChoice<TransmittanceMode>(
             s, {{"ratio", TransmittanceMode::kRatio}, {"delta", TransmittanceMode::kDelta}});
       }},
      {"--bvh",
       [](CliOptions& o, ValueSource& s) {
         o.bvhLayout = ParseChoice<std::optional<BvhLayout>>(
             s, {{"binary", BvhLayout::kBinary}, {"wide", BvhLayout::kWide}, {"auto", std::nullopt}});
       }},
      {"--bvh-build",
       [](CliOptions& o, ValueSource& s) {
         o.bvhBuilder =
             ParseChoice<BvhBuilder>(s, {{"sah", BvhBuilder::kSah}, {"sbvh", BvhBuilder::kSbvh},
                                         {"gpu", BvhBuilder::kLbvh}, {"auto", BvhBuilder::kAuto}});
       }},
  };
  return table;
}

// Options of later features: checked for a well-formed value, then refused or accepted.
const std::vector<std::pair<std::string, Handler>>& LaterOptions() {
  static const std::vector<std::pair<std::string, Handler>> table = {
      {"--adaptive",
       [](CliOptions& o, ValueSource& s) {
         o.adaptive = ParseChoice<Toggle>(s, {{"on", Toggle::kOn}, {"off", Toggle::kOff}});
       }},
      {"--spp-map", [](CliOptions& o, ValueSource& s) { o.sppMapPath = TakePath(s); }},
      {"--light-paths",
       [](CliOptions& o, ValueSource& s) {
         o.lightPaths = ParseChoice<LightPaths>(s, {{"all", LightPaths::kAll},
                                                    {"direct", LightPaths::kDirect},
                                                    {"indirect", LightPaths::kIndirect}});
       }},
      {"--tri-test",
       [](CliOptions& o, ValueSource& s) {
         o.triangleTest = ParseChoice<TriangleTest>(
             s, {{"watertight", TriangleTest::kWatertight},
                 {"box-clamped", TriangleTest::kBoxClamped},
                 {"mt", TriangleTest::kMollerTrumbore}});
       }},
      {"--film",
       [](CliOptions& o, ValueSource& s) {
         o.filmDouble = ParseChoice<bool>(s, {{"float", false}, {"double", true}});
       }},
      {"--energy-compensation",
       [](CliOptions& o, ValueSource& s) {
         o.energyCompensation = ParseChoice<bool>(s, {{"on", true}, {"off", false}});
       }},
      {"--specialize",
       [](CliOptions& o, ValueSource& s) {
         o.specialize = ParseChoice<bool>(s, {{"on", true}, {"off", false}});
       }},
      {"--ray-offset",
       [](CliOptions& o, ValueSource& s) {
         std::string text = s.Take();
         if (text == "robust") {
           o.rayOffsetEpsilon = 0.0f;
           return;
         }
         char* end = nullptr;
         double eps = std::strtod(text.c_str(), &end);
         if (text.empty() || *end != '\0' || !(eps > 0.0) || !std::isfinite(eps) || eps > 1e30) {
           throw CliError("bad value for --ray-offset: '" + text + "' (expected robust|EPS)");
         }
         o.rayOffsetEpsilon = float(eps);
       }},
  };
  return table;
}

const Handler* FindHandler(const std::string& name) {
  for (const auto* table : {&ValueOptions(), &ChoiceOptions(), &LaterOptions()}) {
    for (const auto& [option, handler] : *table) {
      if (option == name) return &handler;
    }
  }
  return nullptr;
}

// Flags that take no value; false when name is not one.
bool ApplyFlag(const std::string& name, CliOptions* options) {
  if (name == "--quiet") options->quiet = true;
  else if (name == "--denoise") options->denoise = true;
  else if (name == "--help" || name == "-h") options->help = true;
  else if (name == "--version") options->version = true;
  else return false;
  return true;
}

void ParseOption(const std::string& token, const std::vector<std::string>& args, size_t* next,
                 CliOptions* options) {
  size_t eq = token.find('=');
  std::string name = token.substr(0, eq);
  std::optional<std::string> inlineValue;
  if (eq != std::string::npos) inlineValue = token.substr(eq + 1);
  if (ApplyFlag(name, options)) {
    if (inlineValue) throw CliError(name + " takes no value");
    return;
  }
  if (name == "--serve") {  // the port is optional: taken only when a number follows
    bool numberFollows = *next < args.size() && !args[*next].empty() &&
                         args[*next].find_first_not_of("0123456789") == std::string::npos;
    std::string port = inlineValue ? *inlineValue
                       : numberFollows ? args[(*next)++]
                                       : std::to_string(kDefaultServePort);
    options->servePort = int(ParseInteger(name, port, 0, 65535));
    return;
  }
  const Handler* handler = FindHandler(name);
  if (!handler) throw CliError("unknown option " + name);
  ValueSource source(name, inlineValue, args, next);
  (*handler)(*options, source);
}

void CheckExtension(const std::string& option, const std::string& path, bool allowPng) {
  ImageFormat format;
  if (!ImageFormatFromPath(path, &format) || (!allowPng && format == ImageFormat::kPng)) {
    throw CliError(option + " " + path + ": unknown image format (use " +
                   (allowPng ? ".png, " : "") + ".exr or .pfm)");
  }
}

// The live preview writes -o and --hdr only when it stops (Ctrl-C), and renders every pixel
// alike.
void CheckServe(const CliOptions& o) {
  if (!o.outputPath.empty()) CheckExtension("-o", o.outputPath, true);
  if (!o.hdrPath.empty()) CheckExtension("--hdr", o.hdrPath, false);
  std::pair<bool, const char*> refused[] = {
      {!o.sppMapPath.empty(), "--spp-map"},   {!o.statsJsonPath.empty(), "--stats-json"},
      {!o.referencePath.empty(), "--reference"}, {o.crop.has_value(), "--crop"},
      {!o.resumePath.empty(), "--resume"},    {o.checkpointEverySeconds > 0.0, "--checkpoint-every"},
      {o.timeLimitSeconds > 0.0, "--time-limit"}, {o.previewEverySeconds > 0.0, "--preview-every"},
      {o.adaptive == Toggle::kOn, "--adaptive on"}};
  for (const auto& [given, name] : refused) {
    if (given) {
      throw CliError(std::string(name) + " does not go with --serve (the page shows the render "
                     "and saves the image and scene)");
    }
  }
}

void CheckRequired(const CliOptions& options) {
  if (options.scenePath.empty()) throw CliError("missing the scene file (SCENE.json)");
  if (!options.bindAddress.empty() && !options.servePort) throw CliError("--bind needs --serve");
  if (!options.envFolder.empty() && !options.servePort) throw CliError("--env-dir needs --serve");
  if (options.servePort) return CheckServe(options);
  if (options.outputPath.empty()) throw CliError("missing -o FILE");
  CheckExtension("-o", options.outputPath, true);
  if (!options.hdrPath.empty()) CheckExtension("--hdr", options.hdrPath, false);
  if (!options.referencePath.empty()) {
    CheckExtension("--reference", options.referencePath, false);
  }
  if (!options.resumePath.empty() && !IsExrPath(options.resumePath)) {
    throw CliError("--resume " + options.resumePath +
                   ": a render resumes from the .exr its --hdr wrote");
  }
  if (options.checkpointEverySeconds > 0.0 && !IsExrPath(options.hdrPath)) {
    throw CliError("--checkpoint-every needs --hdr FILE.exr: the checkpoint is that EXR");
  }
}

}  // namespace

CliOptions ParseCli(int argc, const char* const* argv) {
  std::vector<std::string> args(argv + std::min(argc, 1), argv + argc);
  CliOptions options;
  options.arguments.assign(argv, argv + std::max(argc, 0));
  bool optionsEnded = false;
  for (size_t next = 0; next < args.size();) {
    const std::string& token = args[next++];
    bool isOption = !optionsEnded && token.size() > 1 && token[0] == '-';
    if (isOption && token == "--") {
      optionsEnded = true;
    } else if (isOption) {
      ParseOption(token, args, &next, &options);
    } else if (options.scenePath.empty()) {
      options.scenePath = token;
    } else {
      throw CliError("unexpected argument '" + token + "' (one scene file only)");
    }
  }
  if (!options.help && !options.version) CheckRequired(options);
  return options;
}

void ApplyCliOption(const std::string& name, const std::string& value, CliOptions* options) {
  const Handler* handler = FindHandler(name);
  if (!handler) throw CliError("unknown option " + name);
  const std::vector<std::string> noArguments;
  size_t next = 0;
  ValueSource source(name, value, noArguments, &next);
  (*handler)(*options, source);
}

void ApplyCliOverrides(const CliOptions& cli, RenderSettings* settings) {
  if (cli.spp) settings->spp = *cli.spp;
  if (cli.width) settings->width = *cli.width;
  if (cli.height) settings->height = *cli.height;
  if (settings->aspect > 0.0f && cli.width.has_value() != cli.height.has_value()) {
    double side = cli.width ? double(*cli.width) / settings->aspect
                            : double(*cli.height) * settings->aspect;  // the other side
    int other = int(std::clamp(std::lround(side), 1L, long(kMaxImageSide)));
    (cli.width ? settings->height : settings->width) = other;
  }
  if (cli.maxDepth) settings->maxDepth = *cli.maxDepth;
  if (cli.seed) settings->seed = *cli.seed;
  if (cli.rrDepth) settings->russianRouletteDepth = *cli.rrDepth;
  if (settings->width < 1 || settings->height < 1 ||
      int64_t(settings->width) * settings->height > kMaxImagePixels) {
    throw CliError("image size " + std::to_string(settings->width) + "x" +
                   std::to_string(settings->height) + " is empty or too large");
  }
  if (settings->spp < 1) throw CliError("spp must be at least 1");
  if (settings->maxDepth < 0) throw CliError("max depth must not be negative");
  if (cli.crop && (cli.crop->x1 > settings->width || cli.crop->y1 > settings->height)) {
    throw CliError("--crop window reaches outside the " + std::to_string(settings->width) +
                   "x" + std::to_string(settings->height) + " image");
  }
}

}  // namespace pt
