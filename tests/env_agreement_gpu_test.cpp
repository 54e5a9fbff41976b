// Environment maps, skies and suns on the GPU run the same stage bodies as on the CPU and
// agree with it: a sky with its sun disk over diffuse and glossy objects (the diffuse and
// general stage variants with map code), uniform map sampling, a hidden environment, and a
// delta sun. Skip without a GPU.
#include <gtest/gtest.h>

#include "tests/env_test_util.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

std::string SceneWith(const std::string& environment, const std::string& ball, int seed,
                  const std::string& lights = "[]") {
  return R"({"render": {"width": 48, "height": 48, "spp": 64, "max_depth": 4, "seed": )" +
         std::to_string(seed) + R"(},
    "camera": {"position": [0, 1, 5], "look_at": [0, 0.5, 0], "fov_y": 40}, )" + environment +
         R"(, "materials": {"ball": )" + ball + R"(,
      "floor": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "objects": [{"type": "sphere", "center": [0, 0.6, 0], "radius": 0.6, "material": "ball"},
      {"type": "quad", "origin": [-20, 0, 20], "u": [40, 0, 0], "v": [0, 0, -40],
       "material": "floor"}], "lights": )" + lights + "}";
}

const char* kDiffuse = R"({"type": "diffuse", "albedo": [0.7, 0.6, 0.5]})";
const char* kGlossy =
    R"({"type": "plastic", "albedo": [0.7, 0.2, 0.1], "ior": 1.5, "roughness": 0.3})";
const char* kSky = R"("environment": {"sky": {"sun_elevation": 30, "sun_azimuth": 40, "width": 256},
    "strength": 0.02})";

void ExpectAgree(const std::string& a, const std::string& b, RenderOptions options,
                 const char* what) {
  ScopedDir dir;
  WriteMap(dir / "sky.pfm", 64, [](int i, int j) {
    return j < 32 && i == 20 ? vec3(20.0f) : vec3(0.2f + 0.01f * j, 0.3f, 0.5f);
  });
  FilmImage cpu = RenderOnCpu(SceneIn(dir, a), options).image;
  options.backend = BackendKind::kCuda;
  FilmImage gpu = RenderCuda(SceneIn(dir, b), options).image;
  ExpectWindowsAgree(cpu, gpu, BlockWindows(cpu, 4), what);
}

TEST(EnvAgreementGpu, SkyAndSunDiskMatchTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  ExpectAgree(SceneWith(kSky, kDiffuse, 1), SceneWith(kSky, kDiffuse, 2), {}, "sky, diffuse");
  ExpectAgree(SceneWith(kSky, kGlossy, 3), SceneWith(kSky, kGlossy, 4), {}, "sky, glossy");
}

TEST(EnvAgreementGpu, MapSamplingStrategiesMatchTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  std::string map = R"("environment": {"file": "sky.pfm", "rotate": [10, 60, 0]})";
  RenderOptions uniform;
  uniform.envSampling = EnvSampling::kUniform;
  ExpectAgree(SceneWith(map, kDiffuse, 5), SceneWith(map, kDiffuse, 6), {}, "map, importance");
  ExpectAgree(SceneWith(map, kGlossy, 7), SceneWith(map, kGlossy, 8), uniform, "map, uniform");
  std::string hidden = R"("environment": {"file": "sky.pfm", "visible_to_camera": false,
      "camera_color": [0.1, 0.2, 0.3]})";
  ExpectAgree(SceneWith(hidden, kDiffuse, 9), SceneWith(hidden, kDiffuse, 10), {}, "map, hidden");
}

TEST(EnvAgreementGpu, DeltaSunMatchesTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  std::string sun = R"([{"type": "directional", "direction": [0.3, -1, -0.4],
      "irradiance": [3, 2.5, 2]}])";
  std::string env = R"("background": [0.1, 0.15, 0.2])";
  ExpectAgree(SceneWith(env, kGlossy, 11, sun), SceneWith(env, kGlossy, 12, sun), {}, "delta sun");
}

}  // namespace
}  // namespace pt::test
