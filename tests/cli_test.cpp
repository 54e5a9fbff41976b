// The command-line parser of cli.md: every option in both syntaxes, the errors (exit status 1
// in the app), the refusals of options whose features are not built yet, and the overrides.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "src/app/cli.h"
#include "tests/cli_parse_util.h"

namespace pt {
namespace {

using test::Parse;
using test::ParseError;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(CliParse, MinimalCommandLineKeepsDefaults) {
  CliOptions o = Parse({"scene.json", "-o", "out.png"});
  EXPECT_EQ(o.scenePath, "scene.json");
  EXPECT_EQ(o.outputPath, "out.png");
  EXPECT_TRUE(o.hdrPath.empty());
  EXPECT_FALSE(o.spp || o.width || o.height || o.maxDepth || o.seed || o.rrDepth || o.crop);
  EXPECT_EQ(o.backend, BackendKind::kAuto);
  EXPECT_EQ(o.threads, 0);
  EXPECT_EQ(o.compact, Toggle::kAuto);
  EXPECT_EQ(o.sort, SortMode::kAuto);
  EXPECT_EQ(o.integrator, IntegratorMode::kMis);
  EXPECT_EQ(o.timeLimitSeconds, 0.0);
  EXPECT_EQ(o.previewEverySeconds, 0.0);
  EXPECT_FALSE(o.quiet || o.help || o.version);
}

void ExpectEveryOption(const CliOptions& o) {
  EXPECT_EQ(o.scenePath, "s.json");
  EXPECT_EQ(o.outputPath, "o.exr");
  EXPECT_EQ(o.hdrPath, "h.pfm");
  EXPECT_EQ(o.referencePath, "r.exr");
  EXPECT_EQ(o.statsJsonPath, "stats.json");
  EXPECT_EQ(o.spp, 7);
  EXPECT_EQ(o.width, 320);
  EXPECT_EQ(o.height, 200);
  EXPECT_EQ(o.maxDepth, 0);
  EXPECT_EQ(o.seed, 4294967295u);
  EXPECT_EQ(o.rrDepth, 5);
  EXPECT_EQ(o.backend, BackendKind::kCpu);
  EXPECT_EQ(o.threads, 3);
  EXPECT_EQ(o.compact, Toggle::kOff);
  EXPECT_EQ(o.sort, SortMode::kMaterial);
  EXPECT_EQ(o.integrator, IntegratorMode::kNee);
  EXPECT_DOUBLE_EQ(o.timeLimitSeconds, 2.5);
  EXPECT_DOUBLE_EQ(o.previewEverySeconds, 0.75);
  ASSERT_TRUE(o.crop);
  EXPECT_EQ(o.crop->x0, 1);
  EXPECT_EQ(o.crop->y0, 2);
  EXPECT_EQ(o.crop->x1, 30);
  EXPECT_EQ(o.crop->y1, 40);
  EXPECT_TRUE(o.quiet);
}

TEST(CliParse, EveryOptionWithSeparateValues) {
  ExpectEveryOption(Parse({"s.json", "-o", "o.exr", "--hdr", "h.pfm", "--reference", "r.exr",
                           "--stats-json", "stats.json", "--spp", "7", "--width", "320",
                           "--height", "200", "--max-depth", "0", "--seed", "4294967295",
                           "--rr-depth", "5", "--backend", "cpu", "--threads", "3", "--compact",
                           "off", "--sort", "material", "--integrator", "nee", "--time-limit",
                           "2.5", "--preview-every", "0.75", "--crop", "1", "2", "30", "40",
                           "--quiet", "--tri-test", "watertight", "--ray-offset", "robust",
                           "--film", "float", "--specialize", "on"}));
}

TEST(CliParse, EveryOptionWithEqualsValues) {
  ExpectEveryOption(Parse({"-o=o.exr", "--hdr=h.pfm", "--reference=r.exr",
                           "--stats-json=stats.json", "--spp=7", "--width=320", "--height=200",
                           "--max-depth=0", "--seed=4294967295", "--rr-depth=5", "--backend=cpu",
                           "--threads=3", "--compact=off", "--sort=material", "--integrator=nee",
                           "--time-limit=2.5", "--preview-every=0.75", "--crop=1,2,30,40",
                           "--quiet", "--tri-test=watertight", "--ray-offset=robust",
                           "--film=float", "--specialize=on", "s.json"}));
}

TEST(CliParse, CropForms) {
  for (auto args : std::vector<std::vector<const char*>>{
           {"--crop", "1", "2", "30", "40"},
           {"--crop=1", "2", "30", "40"},
           {"--crop", "1,2,30,40"},
           {"--crop=1,2,30,40"}}) {
    args.insert(args.begin(), {"s.json", "-o", "o.png"});
    CliOptions o = Parse(args);
    ASSERT_TRUE(o.crop);
    EXPECT_EQ(o.crop->x0, 1);
    EXPECT_EQ(o.crop->y1, 40);
  }
  EXPECT_TRUE(Contains(ParseError({"s.json", "-o", "o.png", "--crop", "1", "2", "3"}),
                       "missing value"));
  EXPECT_TRUE(Contains(ParseError({"s.json", "-o", "o.png", "--crop=1,2,3"}), "four numbers"));
  EXPECT_TRUE(Contains(ParseError({"s.json", "-o", "o.png", "--crop", "5", "0", "2", "8"}),
                       "X0 < X1"));
  EXPECT_TRUE(Contains(ParseError({"s.json", "-o", "o.png", "--crop", "-1", "0", "2", "8"}),
                       "--crop"));
}

TEST(CliParse, EnumValues) {
  auto with = [](const char* option, const char* value) {
    return Parse({"s.json", "-o", "o.png", option, value});
  };
  EXPECT_EQ(with("--backend", "auto").backend, BackendKind::kAuto);
  EXPECT_EQ(with("--backend", "cpu").backend, BackendKind::kCpu);
  EXPECT_EQ(with("--backend", "cuda").backend, BackendKind::kCuda);
  EXPECT_EQ(with("--compact", "on").compact, Toggle::kOn);
  EXPECT_EQ(with("--compact", "off").compact, Toggle::kOff);
  EXPECT_EQ(with("--compact", "auto").compact, Toggle::kAuto);
  EXPECT_EQ(with("--sort", "off").sort, SortMode::kOff);
  EXPECT_EQ(with("--sort", "material").sort, SortMode::kMaterial);
  EXPECT_EQ(with("--sort", "auto").sort, SortMode::kAuto);
  EXPECT_EQ(with("--sort", "queues").sort, SortMode::kQueues);
  EXPECT_EQ(with("--sort-method", "counting").sortMethod, SortMethod::kCounting);
  EXPECT_EQ(with("--sort-method", "radix").sortMethod, SortMethod::kRadix);
  EXPECT_EQ(with("--sort-method", "radix32").sortMethod, SortMethod::kRadixFullWidth);
  EXPECT_EQ(with("--sort-method", "auto").sortMethod, SortMethod::kAuto);
  EXPECT_EQ(with("--integrator", "mis").integrator, IntegratorMode::kMis);
  EXPECT_EQ(with("--integrator", "bsdf").integrator, IntegratorMode::kBsdf);
  EXPECT_EQ(with("--integrator", "nee").integrator, IntegratorMode::kNee);
  EXPECT_FALSE(with("--bvh", "auto").bvhLayout.has_value());
  EXPECT_EQ(with("--bvh", "binary").bvhLayout, BvhLayout::kBinary);
  EXPECT_EQ(with("--bvh", "wide").bvhLayout, BvhLayout::kWide);
  EXPECT_EQ(with("--bvh-build", "sah").bvhBuilder, BvhBuilder::kSah);
  EXPECT_EQ(with("--bvh-build", "sbvh").bvhBuilder, BvhBuilder::kSbvh);
  EXPECT_EQ(with("--bvh-build", "gpu").bvhBuilder, BvhBuilder::kLbvh);
  EXPECT_EQ(with("--bvh-build", "auto").bvhBuilder, BvhBuilder::kAuto);
  EXPECT_EQ(with("--rr-depth", "off").rrDepth, kRussianRouletteOff);
  EXPECT_EQ(with("--rr-depth", "0").rrDepth, 0);
  EXPECT_FALSE(Parse({"s.json", "-o", "o.png"}).sampler.has_value());  // the scene's
  EXPECT_EQ(with("--sampler", "independent").sampler, SamplerKind::kIndependent);
  EXPECT_EQ(with("--sampler", "sobol").sampler, SamplerKind::kSobol);
}

TEST(CliParse, HelpAndVersionNeedNothingElse) {
  EXPECT_TRUE(Parse({"--help"}).help);
  EXPECT_TRUE(Parse({"-h"}).help);
  EXPECT_TRUE(Parse({"--version"}).version);
  std::string usage = CliUsage();
  for (const char* option :
       {"-o FILE", "--hdr", "--spp", "--width", "--height", "--max-depth", "--seed", "--rr-depth",
        "--backend", "--threads", "--compact", "--sort", "--integrator", "--reference",
        "--time-limit", "--preview-every", "--crop", "--stats-json", "--quiet", "--version",
        "--adaptive", "--spp-map", "--light-paths", "--tri-test", "--film", "--specialize",
        "--ray-offset", "--max-paths", "--clamp", "--checkpoint-every", "--resume",
        "--progress-every", "--denoise-radius", "143 SIGTERM"}) {
    EXPECT_TRUE(Contains(usage, option)) << option;
  }
}

TEST(CliParse, BadCommandLines) {
  struct Case {
    std::vector<const char*> args;
    const char* message;
  };
  std::vector<Case> cases = {
      {{"s.json", "-o", "o.png", "--bogus"}, "unknown option --bogus"},
      {{"s.json", "-o", "o.png", "--bogus=1"}, "unknown option --bogus"},
      {{"s.json", "-o"}, "missing value for -o"},
      {{"s.json", "-o", "o.png", "--spp"}, "missing value for --spp"},
      {{"s.json", "-o", "o.png", "--spp", "--quiet"}, "missing value for --spp"},
      {{"s.json", "-o", "o.png", "--spp", "abc"}, "bad number for --spp"},
      {{"s.json", "-o", "o.png", "--spp", "1.5"}, "bad number for --spp"},
      {{"s.json", "-o", "o.png", "--spp=12x"}, "bad number for --spp"},
      {{"s.json", "-o", "o.png", "--spp", "0"}, "--spp must be between"},
      {{"s.json", "-o", "o.png", "--width", "-3"}, "--width must be between"},
      {{"s.json", "-o", "o.png", "--height", "0"}, "--height must be between"},
      {{"s.json", "-o", "o.png", "--max-depth", "-1"}, "--max-depth must be between"},
      {{"s.json", "-o", "o.png", "--seed", "4294967296"}, "--seed must be between"},
      {{"s.json", "-o", "o.png", "--rr-depth", "never"}, "bad number for --rr-depth"},
      {{"s.json", "-o", "o.png", "--threads", "-1"}, "--threads must be between"},
      {{"s.json", "-o", "o.png", "--time-limit", "0"}, "greater than 0"},
      {{"s.json", "-o", "o.png", "--time-limit", "nan"}, "bad number for --time-limit"},
      {{"s.json", "-o", "o.png", "--preview-every", "soon"}, "bad number for --preview-every"},
      {{"s.json", "-o", "o.png", "--backend", "gpu"}, "bad value for --backend"},
      {{"s.json", "-o", "o.png", "--compact", "yes"}, "bad value for --compact"},
      {{"s.json", "-o", "o.png", "--sort", "random"}, "bad value for --sort"},
      {{"s.json", "-o", "o.png", "--integrator", "bdpt"}, "bad value for --integrator"},
      {{"s.json", "-o", "o.png", "--bvh", "quad"}, "bad value for --bvh"},
      {{"s.json", "-o", "o.png", "--bvh-build", "lbvh"}, "bad value for --bvh-build"},
      {{"s.json", "-o", "o.png", "--quiet=yes"}, "--quiet takes no value"},
      {{"-o", "o.png"}, "missing the scene file"},
      {{"s.json"}, "missing -o"},
      {{"s.json", "t.json", "-o", "o.png"}, "unexpected argument"},
      {{"s.json", "-o", "o.jpg"}, "unknown image format"},
      {{"s.json", "-o", "o.png", "--hdr", "h.png"}, "unknown image format"},
      {{"s.json", "-o", "o.png", "--reference", "r.txt"}, "unknown image format"},
      {{"s.json", "-o", ""}, "empty file name"},
      {{"s.json", "-o", "o.png", "--max-paths", "0"}, "--max-paths must be between"},
      {{"s.json", "-o", "o.png", "--denoise-radius", "0"}, "--denoise-radius must be between 1"},
      {{"s.json", "-o", "o.png", "--denoise-radius", "21"}, "--denoise-radius must be between 1"},
      {{"s.json", "-o", "o.png", "--denoise-radius", "five"}, "bad number for --denoise-radius"},
      {{"s.json", "-o", "o.png", "--clamp", "0"}, "--clamp must be greater than 0"},
      {{"s.json", "-o", "o.png", "--clamp", "inf"}, "bad number for --clamp"},
      {{"s.json", "-o", "o.png", "--progress-every", "-1"}, "greater than 0"},
      {{"s.json", "-o", "o.png", "--checkpoint-every", "5"}, "needs --hdr FILE.exr"},
      {{"s.json", "-o", "o.png", "--hdr", "h.pfm", "--checkpoint-every", "5"},
       "needs --hdr FILE.exr"},
      {{"s.json", "-o", "o.png", "--resume", "r.pfm"}, "resumes from the .exr"},
  };
  for (const Case& c : cases) {
    std::string message = ParseError(c.args);
    EXPECT_TRUE(Contains(message, c.message)) << "got '" << message << "', wanted " << c.message;
  }
}

TEST(CliParse, LaterFeatureOptionsParse) {
  CliOptions o = Parse({"s.json", "-o", "o.png", "--adaptive", "on", "--spp-map=map.png",
                        "--light-paths", "indirect", "--ray-offset", "1e-4", "--film=double"});
  EXPECT_EQ(o.adaptive, Toggle::kOn);
  EXPECT_EQ(o.sppMapPath, "map.png");
  EXPECT_EQ(o.lightPaths, LightPaths::kIndirect);
  EXPECT_FLOAT_EQ(o.rayOffsetEpsilon, 1e-4f);
  EXPECT_TRUE(o.filmDouble);
  CliOptions d = Parse({"s.json", "-o", "o.png", "--adaptive=off", "--light-paths=direct",
                        "--ray-offset", "robust", "--film", "float"});
  EXPECT_EQ(d.adaptive, Toggle::kOff);
  EXPECT_EQ(d.lightPaths, LightPaths::kDirect);
  EXPECT_EQ(d.rayOffsetEpsilon, 0.0f);
  EXPECT_FALSE(d.filmDouble);
  EXPECT_EQ(Parse({"s.json", "-o", "o.png"}).adaptive, Toggle::kAuto);
  EXPECT_TRUE(Parse({"s.json", "-o", "o.png"}).specialize);
  EXPECT_FALSE(Parse({"s.json", "-o", "o.png", "--specialize=off"}).specialize);
  EXPECT_EQ(Parse({"s.json", "-o", "o.png", "--tri-test", "mt"}).triangleTest,
            TriangleTest::kMollerTrumbore);
  EXPECT_EQ(Parse({"s.json", "-o", "o.png", "--tri-test", "box-clamped"}).triangleTest,
            TriangleTest::kBoxClamped);
}

TEST(CliParse, MalformedValuesOfChoiceOptionsAreErrors) {
  for (auto args : std::vector<std::vector<const char*>>{{"--adaptive", "maybe"},
                                                         {"--tri-test", "fast"},
                                                         {"--ray-offset", "-1"},
                                                         {"--film", "half"},
                                                         {"--specialize", "yes"},
                                                         {"--light-paths", "some"},
                                                         {"--sort-method", "bogo"},
                                                         {"--sampler", "halton"},
                                                         {"--denoise-variance", "exact"}}) {
    args.insert(args.begin(), {"s.json", "-o", "o.png"});
    std::string message = ParseError(args);
    EXPECT_TRUE(Contains(message, "bad value")) << args[3] << ": " << message;
  }
}

TEST(CliParse, LongRenderOptions) {
  CliOptions o = Parse({"s.json", "-o", "o.png", "--hdr", "h.exr", "--checkpoint-every", "30",
                        "--resume=h.exr", "--progress-every", "2.5", "--max-paths", "4096",
                        "--clamp=20"});
  EXPECT_DOUBLE_EQ(o.checkpointEverySeconds, 30.0);
  EXPECT_EQ(o.resumePath, "h.exr");
  EXPECT_DOUBLE_EQ(o.progressEverySeconds, 2.5);
  EXPECT_EQ(o.maxPaths, 4096u);
  EXPECT_FLOAT_EQ(o.clampLuminance, 20.0f);
  ASSERT_EQ(o.arguments.size(), 14u);
  EXPECT_EQ(o.arguments[0], "pathtracer");
  EXPECT_EQ(o.arguments[13], "--clamp=20");
  CliOptions d = Parse({"s.json", "-o", "o.png"});
  EXPECT_DOUBLE_EQ(d.progressEverySeconds, 10.0);
  EXPECT_EQ(d.checkpointEverySeconds, 0.0);
  EXPECT_TRUE(d.resumePath.empty());
  EXPECT_EQ(d.maxPaths, 0u);
  EXPECT_EQ(d.clampLuminance, 0.0f);
}

TEST(CliParse, ServeOptions) {
  CliOptions d = Parse({"s.json", "--serve"});
  ASSERT_TRUE(d.servePort.has_value());
  EXPECT_EQ(*d.servePort, 8765);  // the documented default (docs/serve.md)
  EXPECT_TRUE(d.bindAddress.empty());
  CliOptions p = Parse({"s.json", "--serve", "9000", "--bind", "0.0.0.0", "--backend", "cpu"});
  EXPECT_EQ(*p.servePort, 9000);
  EXPECT_EQ(p.bindAddress, "0.0.0.0");
  EXPECT_EQ(*Parse({"--serve=0", "s.json"}).servePort, 0);
  // A scene path after --serve is not taken as the port.
  CliOptions s = Parse({"--serve", "s.json"});
  EXPECT_EQ(s.scenePath, "s.json");
  EXPECT_EQ(*s.servePort, 8765);
  EXPECT_TRUE(Contains(ParseError({"s.json", "--serve", "70000"}), "--serve"));
  EXPECT_TRUE(Contains(ParseError({"s.json", "-o", "o.png", "--bind", "0.0.0.0"}),
                       "--bind needs --serve"));
  // -o and --hdr are where Ctrl-C saves the preview; their formats are checked as a render's.
  CliOptions saved = Parse({"s.json", "--serve", "-o", "o.png", "--hdr", "o.exr", "--tonemap", "agx"});
  EXPECT_EQ(saved.outputPath, "o.png");
  EXPECT_EQ(saved.display.toneMapping, ToneMapping::kAgx);
  EXPECT_FALSE(ParseError({"s.json", "--serve", "-o", "o.xyz"}).empty());
  EXPECT_TRUE(Contains(ParseError({"s.json", "-o", "o.png", "--env-dir", "maps"}),
                       "--env-dir needs --serve"));
  EXPECT_TRUE(Contains(ParseError({"s.json", "-o", "o.png", "--exposure", "nan"}), "--exposure"));
  EXPECT_TRUE(Contains(ParseError({"s.json", "--serve", "--crop", "0,0,4,4"}),
                       "--crop does not go with --serve"));
  EXPECT_TRUE(Contains(ParseError({"s.json", "--serve", "--resume", "a.exr"}),
                       "--resume does not go with --serve"));
}

TEST(CliParse, DoubleDashEndsOptions) {
  CliOptions o = Parse({"-o", "o.png", "--", "-scene.json"});
  EXPECT_EQ(o.scenePath, "-scene.json");
}

TEST(CliOverrides, ApplyAndValidate) {
  RenderSettings settings;
  settings.width = 64;
  settings.height = 32;
  settings.spp = 16;
  settings.maxDepth = 8;
  settings.seed = 1;
  CliOptions cli = Parse({"s.json", "-o", "o.png", "--spp", "2", "--width", "100",
                          "--max-depth", "0", "--seed", "9", "--rr-depth", "off"});
  ApplyCliOverrides(cli, &settings);
  EXPECT_EQ(settings.spp, 2);
  EXPECT_EQ(settings.width, 100);
  EXPECT_EQ(settings.height, 32);  // not overridden
  EXPECT_EQ(settings.maxDepth, 0);
  EXPECT_EQ(settings.seed, 9u);
  EXPECT_EQ(settings.russianRouletteDepth, kRussianRouletteOff);

  CliOptions crop = Parse({"s.json", "-o", "o.png", "--crop", "0", "0", "101", "10"});
  EXPECT_THROW(ApplyCliOverrides(crop, &settings), CliError);  // outside the 100-wide image
  CliOptions huge = Parse({"s.json", "-o", "o.png", "--width", "65536", "--height", "65536"});
  EXPECT_THROW(ApplyCliOverrides(huge, &settings), CliError);
}

// A model scene's settings carry its camera's aspect ratio: --width or --height alone keeps it,
// both given set the size as asked. A JSON scene (aspect 0) keeps the other side as it is.
TEST(CliOverrides, OneSideAloneKeepsAModelScenesAspect) {
  auto apply = [](float aspect, std::vector<const char*> args) {
    RenderSettings s;
    s.width = 1280;
    s.height = 720;
    s.spp = 1;
    s.maxDepth = 1;
    s.aspect = aspect;
    args.insert(args.begin(), {"m.glb", "-o", "o.png"});
    ApplyCliOverrides(Parse(args), &s);
    return std::pair<int, int>(s.width, s.height);
  };
  EXPECT_EQ(apply(16.0f / 9.0f, {"--width", "320"}), std::make_pair(320, 180));
  EXPECT_EQ(apply(16.0f / 9.0f, {"--height", "90"}), std::make_pair(160, 90));
  EXPECT_EQ(apply(2.0f, {"--width", "3"}), std::make_pair(3, 2));  // 1.5 rounds up
  EXPECT_EQ(apply(16.0f / 9.0f, {"--width", "64", "--height", "64"}), std::make_pair(64, 64));
  EXPECT_EQ(apply(0.0f, {"--width", "320"}), std::make_pair(320, 720));
}

}  // namespace
}  // namespace pt
