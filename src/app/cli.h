// The command line of docs/cli.md parsed into one struct. Both `--flag V` and `--flag=V`
// are accepted; options of features not built yet are refused, never ignored.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "src/integrator/render_api.h"
#include "src/io/tone_mapping.h"
#include "src/scene/scene.h"

namespace pt {

// A bad command line: exit status 1, the message on one line and a hint to --help.
struct CliError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// `--env none`: the render has no environment (a file named "none" is given as ./none).
inline constexpr const char* kEnvNone = "none";

struct CliOptions {
  std::string scenePath;
  std::string outputPath;     // -o
  std::string hdrPath;        // --hdr, empty = none
  std::string referencePath;  // --reference, empty = none
  std::string statsJsonPath;  // --stats-json, empty = none

  // Overrides of the scene's render settings; empty = keep the scene's.
  std::optional<int> spp, width, height, maxDepth;
  std::optional<uint32_t> seed;
  std::optional<int> rrDepth;  // kRussianRouletteOff when --rr-depth off

  BackendKind backend = BackendKind::kAuto;
  int threads = 0;
  Toggle compact = Toggle::kAuto;
  SortMode sort = SortMode::kAuto;
  SortMethod sortMethod = SortMethod::kAuto;
  IntegratorMode integrator = IntegratorMode::kMis;
  double timeLimitSeconds = 0.0;     // 0 = none
  double previewEverySeconds = 0.0;  // 0 = none
  std::optional<CropWindow> crop;
  std::string sppMapPath;  // --spp-map, empty = none
  std::string camera;      // --camera, empty = the scene's own
  std::string animation;        // --animation, empty = the first (with --time)
  std::optional<double> time;   // --time: seconds into the animation; unset = the static pose
  std::string variant;     // --variant (KHR_materials_variants), empty = the files' own
  bool energyCompensation = false;  // --energy-compensation
  Toggle adaptive = Toggle::kAuto;  // kAuto: the scene's setting
  LightPaths lightPaths = LightPaths::kAll;
  float rayOffsetEpsilon = 0.0f;    // 0 = robust
  bool filmDouble = false;
  bool specialize = true;
  TriangleTest triangleTest = TriangleTest::kWatertight;
  Toggle rayOrder = Toggle::kAuto;
  Toggle primPool = Toggle::kAuto;
  Toggle warmUp = Toggle::kAuto;
  std::string envPath;                // --env: replaces the scene's environment (kEnvNone: removes)
  std::optional<float> envStrength;   // --env-strength
  EnvSampling envSampling = EnvSampling::kImportance;
  LightSampler lightSampler = LightSampler::kAuto;  // --light-sampler
  std::optional<SamplerKind> sampler;  // --sampler (empty: the scene's render.sampler)
  std::optional<float> fogSigmaS;     // --fog: a homogeneous medium around the camera
  TransmittanceMode transmittance = TransmittanceMode::kRatio;  // --transmittance
  std::optional<BvhLayout> bvhLayout;  // empty: auto (see ChooseBvh in run.cpp)
  BvhBuilder bvhBuilder = BvhBuilder::kAuto;
  size_t maxPaths = 0;         // --max-paths: paths in flight, 0 = the backend's default
  float clampLuminance = 0.0f;  // --clamp: 0 = off

  // Long renders.
  double progressEverySeconds = 10.0;   // progress lines when stderr is not a terminal
  double checkpointEverySeconds = 0.0;  // 0 = none; else rewrite --hdr as a resumable state
  std::string resumePath;               // --resume, empty = a fresh render
  std::vector<std::string> arguments;   // the command line as given (for the stats)
  // Sample chunks merged along a fixed tree (src/distributed/); unset: 1 for one process, 32
  // (at most spp) under mpirun. The image depends on it, never on the number of processes.
  std::optional<int> chunks;
  std::optional<double> rankTimeoutSeconds;  // under mpirun: a rank silent this long is lost
  std::optional<int> lanes;  // under mpirun: render lanes per rank (default 2 on a GPU, 1 on CPU)

  // --serve [PORT]: the live preview in a browser instead of an output file (src/app/serve.h).
  std::optional<int> servePort;
  std::string bindAddress;  // --bind, empty = 127.0.0.1
  std::string envFolder;    // --env-dir: the preview's environment maps (default: the scene's folder)
  // --exposure and --tonemap: how -o's PNG and the preview's display map radiance to 8 bits.
  DisplaySettings display;

  bool denoise = false;  // --denoise: -o is denoised, the --hdr EXR gains the denoised layer
  bool denoiseOutliers = true;  // --denoise-outliers on|off: fireflies scaled down first
  int denoiseRadius = 5;        // --denoise-radius N: the search window, (2N + 1)^2 neighbours
  // --denoise-variance calibrated|sample; empty: calibrated for Sobol samples only
  std::optional<bool> denoiseCalibrate;
  std::optional<bool> denoiseKeepEmission;  // --denoise-emission keep|filter

  bool quiet = false;
  bool help = false;
  bool version = false;
};

// `--rr-depth off`: a first roulette bounce no path ever reaches.
inline constexpr int kRussianRouletteOff = 1 << 30;

// Parses argv (argv[0] is the program). Throws CliError. With --help or --version set, the
// other checks (scene, -o) are skipped.
CliOptions ParseCli(int argc, const char* const* argv);

// One option as ParseCli applies it, by its command-line name ("--max-depth") and its value
// text: the same checks and messages. For front ends that take options from elsewhere (the
// Python module's keywords, src/scripting/). Throws CliError for an unknown option, a flag
// without a value (--quiet, --help) or a bad value.
void ApplyCliOption(const std::string& name, const std::string& value, CliOptions* options);

// The text --help prints.
std::string CliUsage();

// Applies the overrides to settings and checks the result (image size, crop inside the
// image); throws CliError when they do not fit.
void ApplyCliOverrides(const CliOptions& cli, RenderSettings* settings);

}  // namespace pt
