// Participating media against closed forms, rendered on the CPU backend (small images):
//  - transmittance of a slab: exp(-sigma_t d) per channel, grey and chromatic;
//  - single scattering of a delta directional light in a slab seen along the light's axis:
//      L = E sigma_s p(-1) (1 - exp(-2 sigma_t d)) / (2 sigma_t),
//    p the Henyey-Greenstein phase of backscattering, homogeneous and constant-grid media, both
//    shadow-ray estimators, grey and chromatic (spectral MIS over the hero channel);
//  - white furnace: non-absorbing media in a white environment of radiance 1 give 1 whatever
//    their scattering coefficients (chromatic included), with the camera outside or inside;
//  - emission seen along the camera ray before any scattering (max_depth 0):
//      L = Le sigma_a / sigma_t (1 - exp(-sigma_t d));
//  - chromatic media: each channel of a chromatic medium equals a grey render of that
//    channel's coefficients.
// Tolerances: z = 3.89 (two-sided p = 1e-4) times the standard error the film measures.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "src/media/medium.h"
#include "tests/render_test_util.h"

namespace pt {
namespace {

using test::kZ1e4;

std::string MediaVec(vec3 v) {
  return "[" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + "]";
}

// A camera at z = 1 looking down -z with a narrow field (rays within 0.5 degrees of the axis),
// into a slab of medium filling z in [-d, 0] (bounded by an invisible box) over black.
std::string SlabScene(const std::string& medium, float d, int maxDepth, int spp,
                      const std::string& extra) {
  return R"({"render": {"width": 8, "height": 8, "spp": )" + std::to_string(spp) +
         R"(, "max_depth": )" + std::to_string(maxDepth) + R"(, "seed": 3},
    "camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "fov_y": 1},
    "materials": {"white": {"type": "diffuse", "albedo": [1, 1, 1]}},
    "media": {"slab": )" + medium + R"(},
    "objects": [{"type": "box", "min": [-100, -100, )" + std::to_string(-d) +
         R"(], "max": [100, 100, 0], "material": "interface", "interior": "slab"}])" + extra +
         "}";
}

std::string Homogeneous(vec3 sigmaA, vec3 sigmaS, float g) {
  return R"({"type": "homogeneous", "sigma_a": )" + MediaVec(sigmaA) + R"(, "sigma_s": )" +
         MediaVec(sigmaS) + R"(, "g": )" + std::to_string(g) + "}";
}

// The same coefficients on a constant grid whose constant region is exactly the slab.
std::string ConstantGrid(vec3 sigmaA, vec3 sigmaS, float g, float d) {
  return R"({"type": "grid", "procedural": {"shape": "constant", "resolution": 9},
    "sigma_a": )" + MediaVec(sigmaA) + R"(, "sigma_s": )" + MediaVec(sigmaS) + R"(, "g": )" +
         std::to_string(g) + R"(, "transform": {"scale": [200, 200, )" + std::to_string(d) +
         R"(], "translate": [0, 0, )" + std::to_string(-0.5f * d) + "]}}";
}

// Expects channel c's image mean to be `expected` within z standard errors.
void ExpectMeanNear(const FilmImage& img, int c, double expected, const std::string& what) {
  test::WindowMean m = test::MeanOverImage(img, c);
  double tol = kZ1e4 * std::sqrt(m.varianceOfMean) + 1e-6 * std::fabs(expected);
  EXPECT_NEAR(m.mean, expected, tol) << what << " channel " << c;
}

TEST(MediaTransport, SlabTransmittanceIsExpMinusSigmaTD) {
  const float d = 0.8f;
  for (vec3 sigmaA : {vec3(1.0f), vec3(0.5f, 1.0f, 2.5f)}) {
    // Absorbing only, seen against a white background: the camera ray's transmittance.
    std::string json = SlabScene(Homogeneous(sigmaA, vec3(0.0f), 0.0f), d, 2, 64,
                                 R"(, "background": [1, 1, 1])");
    RenderResult r = test::RenderOnCpu(test::SceneFromJson(json));
    for (int c = 0; c < 3; ++c)
      ExpectMeanNear(r.image, c, std::exp(-double(sigmaA[c]) * d), "sigma_a " + MediaVec(sigmaA));
  }
}

TEST(MediaTransport, EmissionBeforeTheFirstScatteringMatchesTheClosedForm) {
  const float d = 0.7f;
  const vec3 le(1.0f, 2.0f, 4.0f);
  for (vec3 sigmaS : {vec3(0.0f), vec3(0.6f, 0.1f, 1.5f)}) {
    const vec3 sigmaA(0.5f, 1.2f, 0.3f);
    std::string medium = R"({"type": "homogeneous", "sigma_a": )" + MediaVec(sigmaA) +
                         R"(, "sigma_s": )" + MediaVec(sigmaS) + R"(, "emission": )" +
                         MediaVec(le) + "}";
    RenderResult r = test::RenderOnCpu(test::SceneFromJson(SlabScene(medium, d, 0, 128, "")));
    for (int c = 0; c < 3; ++c) {
      double sigmaT = sigmaA[c] + sigmaS[c];
      ExpectMeanNear(r.image, c, le[c] * sigmaA[c] / sigmaT * (1.0 - std::exp(-sigmaT * d)),
                     "emission, sigma_s " + MediaVec(sigmaS));
    }
  }
}

double SingleScattering(double sigmaS, double sigmaT, double g, double d, double e) {
  double phase = (1.0 - g * g) / (4.0 * M_PI * std::pow(1.0 + g * g + 2.0 * g, 1.5));
  return e * sigmaS * phase * (1.0 - std::exp(-2.0 * sigmaT * d)) / (2.0 * sigmaT);
}

void ExpectSingleScattering(const std::string& medium, vec3 sigmaA, vec3 sigmaS, float g,
                            float d, TransmittanceMode mode, const std::string& what) {
  const float e = 10.0f;
  std::string light = R"(, "lights": [{"type": "directional", "direction": [0, 0, -1],
    "irradiance": [10, 10, 10]}])";
  RenderOptions options;
  options.transmittance = mode;
  RenderResult r = test::RenderOnCpu(test::SceneFromJson(SlabScene(medium, d, 1, 128, light)),
                                     options);
  for (int c = 0; c < 3; ++c)
    ExpectMeanNear(r.image, c, SingleScattering(sigmaS[c], sigmaA[c] + sigmaS[c], g, d, e), what);
}

TEST(MediaTransport, SingleScatteringMatchesTheClosedForm) {
  const float d = 0.5f;
  struct Case {
    vec3 sigmaA, sigmaS;
    float g;
  };
  for (const Case& k : {Case{vec3(0.1f), vec3(0.3f), 0.0f},
                        Case{vec3(0.05f, 0.0f, 0.2f), vec3(0.1f, 0.4f, 0.8f), 0.0f},
                        Case{vec3(0.2f), vec3(0.5f), -0.6f},
                        Case{vec3(0.0f, 0.1f, 0.0f), vec3(0.6f, 0.2f, 0.9f), 0.4f}}) {
    std::string what = "sigma_a " + MediaVec(k.sigmaA) + " sigma_s " + MediaVec(k.sigmaS) +
                       " g " + std::to_string(k.g);
    ExpectSingleScattering(Homogeneous(k.sigmaA, k.sigmaS, k.g), k.sigmaA, k.sigmaS, k.g, d,
                           TransmittanceMode::kRatio, "homogeneous " + what);
    for (TransmittanceMode mode : {TransmittanceMode::kRatio, TransmittanceMode::kDelta}) {
      std::string label = "constant grid, ";  // appended: GCC 12 warns wrongly on a + chain
      label.append(mode == TransmittanceMode::kRatio ? "ratio " : "delta ").append(what);
      ExpectSingleScattering(ConstantGrid(k.sigmaA, k.sigmaS, k.g, d), k.sigmaA, k.sigmaS, k.g,
                             d, mode, label);
    }
  }
}

// A sphere of non-absorbing medium (radius 1) in a white environment: every path leaves it,
// so every pixel is 1, with next-event estimation through the medium and MIS at every vertex.
std::string FurnaceScene(const std::string& medium, bool cameraInside) {
  return std::string(R"({"render": {"width": 8, "height": 8, "spp": 64, "max_depth": 400,
    "seed": 5},
    "camera": {"position": )") +
         (cameraInside ? "[0, 0, 0.2]" : "[0, 0, 3]") +
         R"(, "look_at": [0, 0, 0], "fov_y": 40},
    "background": [1, 1, 1],
    "materials": {"white": {"type": "diffuse", "albedo": [1, 1, 1]}},
    "media": {"cloud": )" + medium + "}," + (cameraInside ? R"("medium": "cloud",)" : "") +
         R"("objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
      "material": "interface", "interior": "cloud", "exterior": "vacuum"}]})";
}

TEST(MediaTransport, WhiteFurnaceOfNonAbsorbingMediaIsOne) {
  for (bool inside : {false, true}) {
    for (vec3 sigmaS : {vec3(2.0f), vec3(0.5f, 2.0f, 5.0f)}) {
      for (float g : {0.0f, 0.7f}) {
        RenderResult r = test::RenderOnCpu(
            test::SceneFromJson(FurnaceScene(Homogeneous(vec3(0.0f), sigmaS, g), inside)));
        for (int c = 0; c < 3; ++c)
          ExpectMeanNear(r.image, c, 1.0,
                         std::string(inside ? "inside, " : "outside, ") + "sigma_s " +
                             MediaVec(sigmaS) + " g " + std::to_string(g));
      }
    }
  }
  // A grid medium (a noise cloud, densities in [0, 1]) in the same furnace.
  std::string cloud = R"({"type": "grid", "procedural": {"shape": "cloud", "resolution": 32},
    "sigma_a": [0, 0, 0], "sigma_s": [6, 8, 12], "transform": {"scale": [1.6, 1.6, 1.6]}})";
  for (TransmittanceMode mode : {TransmittanceMode::kRatio, TransmittanceMode::kDelta}) {
    RenderOptions options;
    options.transmittance = mode;
    RenderResult r = test::RenderOnCpu(test::SceneFromJson(FurnaceScene(cloud, false)), options);
    for (int c = 0; c < 3; ++c) ExpectMeanNear(r.image, c, 1.0, "noise cloud");
  }
}

// A diffuse floor lit by an area light through a box of chromatic medium: channel c of the
// render equals channel c of a render whose medium is grey with channel c's coefficients.
std::string ChromaticScene(vec3 sigmaA, vec3 sigmaS) {
  return R"({"render": {"width": 8, "height": 8, "spp": 96, "max_depth": 6, "seed": 9},
    "camera": {"position": [0, 1, 3], "look_at": [0, 0.5, 0], "fov_y": 45},
    "materials": {"white": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]},
                  "lamp": {"type": "emissive", "radiance": [8, 8, 8]}},
    "media": {"haze": )" + Homogeneous(sigmaA, sigmaS, 0.3f) + R"(},
    "objects": [
      {"type": "quad", "origin": [-2, 0, -2], "u": [0, 0, 4], "v": [4, 0, 0], "material": "white"},
      {"type": "quad", "origin": [-0.5, 2, -0.5], "u": [1, 0, 0], "v": [0, 0, 1], "material": "lamp"},
      {"type": "box", "min": [-1, 0.01, -1], "max": [1, 1.5, 1], "material": "interface",
       "interior": "haze"}]})";
}

TEST(MediaTransport, ChromaticMediaMatchPerChannelGreyRenders) {
  const vec3 sigmaA(0.1f, 0.4f, 0.0f), sigmaS(1.5f, 0.3f, 0.8f);
  RenderResult chromatic = test::RenderOnCpu(test::SceneFromJson(ChromaticScene(sigmaA, sigmaS)));
  for (int c = 0; c < 3; ++c) {
    RenderResult grey = test::RenderOnCpu(
        test::SceneFromJson(ChromaticScene(vec3(sigmaA[c]), vec3(sigmaS[c]))));
    test::WindowMean a = test::MeanOverImage(chromatic.image, c);
    test::WindowMean b = test::MeanOverImage(grey.image, c);
    EXPECT_NEAR(a.mean, b.mean, kZ1e4 * std::sqrt(a.varianceOfMean + b.varianceOfMean))
        << "channel " << c;
    EXPECT_GT(a.mean, 0.01) << "channel " << c;
  }
}

// Media inside glass: a glass sphere holding an absorbing medium renders as the same glass
// with that absorption as its Beer-Lambert coefficient (exact attenuation against delta
// tracking: the same expectation).
std::string GlassBallScene(const std::string& glass, const std::string& extra) {
  return R"({"render": {"width": 12, "height": 12, "spp": 128, "max_depth": 8, "seed": 4},
    "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov_y": 30},
    "background": [1, 1, 1],
    "materials": {"glass": )" + glass + R"(},)" + extra + R"(
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.7, "material": "glass")" +
         (extra.empty() ? "" : R"(, "interior": "ink")") + "}]}";
}

TEST(MediaTransport, MediumInsideGlassMatchesBeerLambertGlass) {
  std::string beer = GlassBallScene(
      R"({"type": "dielectric", "ior": 1.4, "absorption": [0.3, 1.0, 2.5]})", "");
  std::string medium = GlassBallScene(R"({"type": "dielectric", "ior": 1.4})",
                                      R"("media": {"ink": {"type": "homogeneous",
                                          "sigma_a": [0.3, 1.0, 2.5], "sigma_s": [0, 0, 0]}},)");
  RenderResult a = test::RenderOnCpu(test::SceneFromJson(beer));
  RenderResult b = test::RenderOnCpu(test::SceneFromJson(medium));
  EXPECT_GT(b.stats.stages.medium, 0.0);
  test::ExpectWindowsAgree(a.image, b.image, test::BlockWindows(a.image, 3), "glass ball");
}

// A scene that defines media but puts nothing in one renders bit for bit as without them: the
// media stages do not run.
TEST(MediaTransport, UnusedMediaChangeNothing) {
  std::string base = test::ReadText(test::SourcePath("scenes/cornell_box.json"));
  SceneDesc plain = LoadSceneFromString(base, "cornell.json", test::SourcePath("scenes"));
  size_t brace = base.rfind('}');
  std::string withMedia = base.substr(0, brace) +
                          R"(, "media": {"fog": {"type": "homogeneous", "sigma_a": [0, 0, 0],
                             "sigma_s": [1, 1, 1]}}})";
  SceneDesc defined = LoadSceneFromString(withMedia, "cornell.json", test::SourcePath("scenes"));
  ASSERT_EQ(defined.media.media.size(), 1u);
  for (SceneDesc* d : {&plain, &defined}) {
    d->render.width = 24;
    d->render.height = 24;
    d->render.spp = 4;
  }
  RenderResult a = test::RenderOnCpu(BuildScene(std::move(plain)));
  RenderResult b = test::RenderOnCpu(BuildScene(std::move(defined)));
  EXPECT_TRUE(test::SameImage(a.image, b.image));
  EXPECT_EQ(b.stats.stages.medium, 0.0);
}

}  // namespace
}  // namespace pt
