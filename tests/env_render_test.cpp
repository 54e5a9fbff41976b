// Environment maps, skies and suns through the whole renderer (CPU backend): a constant map
// renders as the constant background, a white furnace under a map of radiance 1 is 1, the
// importance and uniform strategies estimate the same image, one bright texel lights the
// side of the scene the convention says and with the irradiance its solid angle gives, a sun
// gives its stated irradiance, a hidden environment shows the camera colour without changing
// the lighting, and the analytic sky with its sun renders as the map make_sky writes of them.
//
// Statistical assertions state their false-alarm probability (1e-4 per assertion or per
// Bonferroni-split group); seeds are fixed.
#include <gtest/gtest.h>

#include <cstring>

#include "tests/env_test_util.h"
#include "tests/render_test_util.h"

namespace pt::test {
namespace {

const char* kCamera = R"("camera": {"position": [0, 1, 5], "look_at": [0, 0.5, 0], "fov_y": 40})";

// A diffuse sphere on a diffuse floor, lit by `environment` (a JSON member or two).
const char* kDiffuseBall = R"({"type": "diffuse", "albedo": [0.7, 0.6, 0.5]})";

std::string SphereOnFloor(const std::string& environment, int spp, int seed,
                          const std::string& sphere = kDiffuseBall) {
  return R"({"render": {"width": 32, "height": 32, "spp": )" + std::to_string(spp) +
         R"(, "max_depth": 3, "seed": )" + std::to_string(seed) + "}, " + kCamera + ", " +
         environment + R"(,
    "materials": {"ball": )" + sphere + R"(,
                  "floor": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "objects": [{"type": "sphere", "center": [0, 0.6, 0], "radius": 0.6, "material": "ball"},
                {"type": "quad", "origin": [-20, 0, 20], "u": [40, 0, 0], "v": [0, 0, -40],
                 "material": "floor"}]})";
}

TEST(EnvRender, ConstantMapEqualsConstantBackground) {
  ScopedDir dir;
  WriteMap(dir / "constant.pfm", 32, [](int, int) { return vec3(0.6f, 0.5f, 0.4f); });
  FilmImage background =
      RenderOnCpu(SceneIn(dir, SphereOnFloor(R"("background": [0.6, 0.5, 0.4])", 64, 1))).image;
  FilmImage map = RenderOnCpu(SceneIn(
      dir, SphereOnFloor(R"("environment": {"file": "constant.pfm"})", 64, 2))).image;
  ExpectWindowsAgree(background, map, BlockWindows(map, 4), "constant map vs background");
  // The top row sees only the environment: the same value, sample by sample.
  for (int x = 0; x < 32; ++x)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(background.rgb[3 * x + c], map.rgb[3 * x + c]);
}

TEST(EnvRender, WhiteFurnaceUnderAMapOfRadianceOneIsOne) {
  ScopedDir dir;
  WriteMap(dir / "one.pfm", 64, [](int, int) { return vec3(1.0f); });
  std::string json = R"({"render": {"width": 24, "height": 24, "spp": 32, "max_depth": 16,
      "russian_roulette_depth": 1000},
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 30},
    "environment": {"file": "one.pfm"},
    "materials": {"white": {"type": "diffuse", "albedo": [1, 1, 1]}},
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"}]})";
  Scene scene = SceneIn(dir, json);
  // BSDF sampling alone: every path carries weight exactly 1 to the map (albedo 1, cosine
  // sampling), so every pixel is 1 up to float round-off.
  RenderOptions bsdf;
  bsdf.integrator = IntegratorMode::kBsdf;
  FilmImage exact = RenderOnCpu(scene, bsdf).image;
  for (float v : exact.rgb) ASSERT_NEAR(v, 1.0f, 1e-5f);
  // MIS and NEE, with importance and uniform map sampling: 1 in the mean. The sphere's central
  // 12 x 12 pixels; CLT bound per estimate, false-alarm probability 1e-4 each, plus round-off.
  for (IntegratorMode mode : {IntegratorMode::kMis, IntegratorMode::kNee})
    for (EnvSampling sampling : {EnvSampling::kImportance, EnvSampling::kUniform}) {
      RenderOptions o;
      o.integrator = mode;
      o.envSampling = sampling;
      FilmImage img = RenderOnCpu(scene, o).image;
      WindowMean w = MeanOverWindow(img, 1, 6, 6, 18, 18);
      EXPECT_NEAR(w.mean, 1.0, kZ1e4 * std::sqrt(w.varianceOfMean) + 1e-5)
          << "integrator " << int(mode) << " sampling " << int(sampling);
    }
}

TEST(EnvRender, ImportanceAndUniformSamplingEstimateTheSameImage) {
  ScopedDir dir;
  // A smooth sky with a bright patch, and a glossy sphere (the general stage variant).
  WriteMap(dir / "patch.pfm", 64, [](int i, int j) {
    bool patch = i >= 40 && i < 44 && j >= 8 && j < 11;
    return patch ? vec3(40.0f, 35.0f, 30.0f) : vec3(0.3f + 0.01f * j, 0.4f, 0.6f - 0.01f * j);
  });
  std::string glossy = R"({"type": "conductor", "albedo": [0.9, 0.8, 0.6], "roughness": 0.4})";
  std::string env = R"("environment": {"file": "patch.pfm", "rotate": [0, 30, 0]})";
  RenderOptions uniform;
  uniform.envSampling = EnvSampling::kUniform;
  FilmImage a = RenderOnCpu(SceneIn(dir, SphereOnFloor(env, 128, 3, glossy))).image;
  FilmImage b = RenderOnCpu(SceneIn(dir, SphereOnFloor(env, 128, 4, glossy)), uniform).image;
  ExpectWindowsAgree(a, b, BlockWindows(a, 4), "importance vs uniform");
}

// A black map but for one texel in column 3w/4 (u = 0.75: +X) just above the horizon.
void WriteOneBrightTexel(const std::string& path, int w, vec3 value) {
  WriteMap(path, w, [&](int i, int j) {
    return i == 3 * w / 4 && j == w / 4 - 1 ? value : vec3(0.0f);
  });
}

TEST(EnvRender, OneBrightTexelLightsTheSideTheConventionStates) {
  ScopedDir dir;
  WriteOneBrightTexel(dir / "bright.pfm", 32, vec3(50.0f));
  for (float turn : {0.0f, 180.0f}) {  // rotate [0, 180, 0] takes the map's +X to world -X
    std::string json = R"({"render": {"width": 32, "height": 32, "spp": 16, "max_depth": 2},
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 30},
      "environment": {"file": "bright.pfm", "rotate": [0, )" + std::to_string(turn) + R"(, 0]},
      "materials": {"m": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
      "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1.2, "material": "m"}]})";
    FilmImage img = RenderOnCpu(SceneIn(dir, json)).image;
    int lit = turn == 0.0f ? 1 : 0;  // which side: 1 = right (+X)
    for (int y = 12; y < 20; ++y)
      for (int x = 4; x < 9; ++x) {
        size_t left = size_t(y) * 32 + x, right = size_t(y) * 32 + (31 - x);
        // The far side's normals face away from every direction in the texel: exactly dark.
        EXPECT_EQ(img.rgb[3 * (lit ? left : right)], 0.0f) << "turn " << turn;
        EXPECT_GT(img.rgb[3 * (lit ? right : left)], 0.05f) << "turn " << turn;
      }
  }
}

TEST(EnvRender, OneBrightTexelGivesTheIrradianceOfItsSolidAngle) {
  ScopedDir dir;
  const int w = 32, h = 16;
  const float radiance = 50.0f, albedo = 0.6f;
  WriteOneBrightTexel(dir / "bright.pfm", w, vec3(radiance));
  // A plane facing +X fills the view. E = L * integral over the texel of cos to +X, in double.
  double e = 0.0;
  int j = h / 2 - 1, i = 3 * w / 4, n = 400;
  double z0 = std::cos(M_PI * j / h), z1 = std::cos(M_PI * (j + 1) / h);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      double z = z0 + (b + 0.5) / n * (z1 - z0), phi = 2.0 * M_PI * ((i + (a + 0.5) / n) / w - 0.5);
      e += std::sqrt(1.0 - z * z) * std::sin(phi);  // d.x, the cosine to +X
    }
  e *= radiance * (z0 - z1) * (2.0 * M_PI / w) / (double(n) * n);
  std::string json = R"({"render": {"width": 16, "height": 16, "spp": 64, "max_depth": 1},
    "camera": {"position": [3, 0, 0], "look_at": [0, 0, 0], "fov_y": 30},
    "environment": {"file": "bright.pfm"},
    "materials": {"m": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]}},
    "objects": [{"type": "quad", "origin": [0, -2, 2], "u": [0, 0, -4], "v": [0, 4, 0],
                 "material": "m"}]})";
  FilmImage img = RenderOnCpu(SceneIn(dir, json)).image;
  WindowMean m = MeanOverImage(img, 0);
  double expected = albedo / M_PI * e;
  // CLT bound, false-alarm probability 1e-4, plus 1e-4 relative for the quadrature.
  EXPECT_NEAR(m.mean, expected, kZ1e4 * std::sqrt(m.varianceOfMean) + 1e-4 * expected);
}

TEST(EnvRender, SunGivesItsStatedIrradiance) {
  // A floor of albedo 0.5 seen from above; the sun 30 degrees from the zenith.
  const double beta = M_PI / 6, expected = 0.5 / M_PI * 2.0 * std::cos(beta);
  auto render = [](const std::string& sun) {
    std::string json = R"({"render": {"width": 16, "height": 16, "spp": 16, "max_depth": 1},
      "camera": {"position": [0, 10, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 30},
      "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
      "objects": [{"type": "quad", "origin": [-20, 0, 20], "u": [40, 0, 0], "v": [0, 0, -40],
                   "material": "m"}],
      "lights": [)" + sun + "]}";
    return RenderOnCpu(SceneFromJson(json)).image;
  };
  const std::string dir = R"("type": "directional", "direction": [-0.5, -0.8660254, 0], )";
  // A delta sun: every pixel is the closed form, to float round-off.
  FilmImage delta = render("{" + dir + R"("irradiance": [2, 2, 2]})");
  for (float v : delta.rgb) ASSERT_NEAR(v, expected, 1e-5 * expected);
  // Disks of 0.27 and 3 degrees, by irradiance and by radiance (E = L pi sin^2 r).
  double r = 3.0 * M_PI / 180.0, l = 2.0 / (M_PI * std::sin(r) * std::sin(r));
  for (const std::string& sun :
       {"{" + dir + R"("irradiance": [2, 2, 2], "angular_radius": 0.2666})",
        "{" + dir + R"("radiance": [)" + std::to_string(l) + ", " + std::to_string(l) + ", " +
            std::to_string(l) + R"(], "angular_radius": 3})"}) {
    WindowMean m = MeanOverImage(render(sun), 1);
    // CLT bound, false-alarm probability 1e-4; 1e-5 relative for round-off and the six
    // printed digits of the radiance.
    EXPECT_NEAR(m.mean, expected, kZ1e4 * std::sqrt(m.varianceOfMean) + 1e-5 * expected) << sun;
  }
}

TEST(EnvRender, HiddenEnvironmentShowsTheCameraColourAndLightsAlike) {
  ScopedDir dir;
  WriteMap(dir / "sky.pfm", 32,
           [](int i, int j) { return vec3(0.2f + 0.1f * (i % 3), 0.5f, 1.0f - j * 0.05f); });
  for (std::string source : {R"("radiance": [0.8, 0.9, 1.0])", R"("file": "sky.pfm")"}) {
    FilmImage seen = RenderOnCpu(SceneIn(dir, SphereOnFloor(
        R"("environment": {)" + source + "}", 8, 5))).image;
    FilmImage hidden = RenderOnCpu(SceneIn(dir, SphereOnFloor(
        R"("environment": {)" + source +
            R"(, "visible_to_camera": false, "camera_color": [0.1, 0.2, 0.3]})", 8, 5))).image;
    for (int x = 0; x < 32; ++x) {  // the top row sees the environment only
      EXPECT_EQ(hidden.rgb[3 * x + 0], 0.1f);
      EXPECT_EQ(hidden.rgb[3 * x + 2], 0.3f);
      EXPECT_NE(seen.rgb[3 * x + 2], 0.3f);
    }
    // Rows 20 on, columns 8 to 23, see the sphere and floor only: the same random numbers,
    // the same light.
    for (int y = 20; y < 32; ++y) {
      size_t from = 3 * (size_t(y) * 32 + 8);
      EXPECT_EQ(0, std::memcmp(seen.rgb.data() + from, hidden.rgb.data() + from,
                               3 * 16 * sizeof(float)))
          << source << " row " << y;
    }
  }
}

TEST(EnvRender, SkyWithItsSunRendersAsTheMapMakeSkyWrites) {
  ScopedDir dir;
  std::string command = BinaryPath("make_sky") + " -o " + (dir / "sky.exr") +
                        " --elevation 35 --azimuth 60 --turbidity 4 --width 1024 --strength 0.02";
  std::string output;
  ASSERT_EQ(RunCommand(command, &output), 0) << output;
  std::string sky = R"("environment": {"sky": {"sun_elevation": 35, "sun_azimuth": 60,
      "turbidity": 4, "width": 1024}, "strength": 0.02})";
  Scene analytic = SceneIn(dir, SphereOnFloor(sky, 64, 6));
  Scene map = SceneIn(dir, SphereOnFloor(R"("environment": {"file": "sky.exr"})", 64, 7));
  ASSERT_EQ(analytic.desc.directionalLights.size(), 1u);  // the sun, beside the sky
  ASSERT_TRUE(map.desc.directionalLights.empty());        // the sun is in the map's texels
  FilmImage a = RenderOnCpu(analytic).image, b = RenderOnCpu(map).image;
  ExpectWindowsAgree(a, b, BlockWindows(a, 4), "sky vs its map");
}

// make_sky --help prints the usage on stdout and succeeds; a bad option still fails.
TEST(EnvRender, MakeSkyHelpPrintsItsUsage) {
  for (const char* flag : {" --help", " -h"}) {
    std::string output;
    ASSERT_EQ(RunCommand(BinaryPath("make_sky") + flag, &output), 0) << output;
    EXPECT_NE(output.find("usage: make_sky -o OUT.exr|OUT.pfm"), std::string::npos) << output;
    EXPECT_NE(output.find("--ground-albedo A"), std::string::npos) << output;
  }
  std::string output;
  EXPECT_EQ(RunCommand(BinaryPath("make_sky") + " --bogus 1", &output), 1) << output;
}

TEST(EnvRender, BitIdenticalAcrossThreadsAndCompaction) {
  SceneDesc desc = LoadScene(SourcePath("scenes/sunsky_diffuse.json"));
  desc.render.width = 40;
  desc.render.height = 30;
  desc.render.spp = 4;
  Scene scene = BuildScene(std::move(desc));
  RenderOptions one, other;
  one.threads = 1;
  other.threads = 2;
  other.compact = Toggle::kOff;
  other.maxPathsInFlight = 700;
  FilmImage a = RenderCpu(scene, one).image, b = RenderCpu(scene, other).image;
  EXPECT_EQ(0, std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)));
}

}  // namespace
}  // namespace pt::test
