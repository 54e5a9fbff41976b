// The glTF material features give the CPU's answer on the GPU (same stage bodies, software
// texture lookups): normal maps, emissive textures (seen and as lights for next-event
// estimation), alpha MASK and BLEND for shadow rays, tinted and absorbing transmission,
// COLOR_0, mip filtering, and the DamagedHelmet model. Independent seeds per backend; window
// means compared with the films' variances. Skip without a GPU.
#include <gtest/gtest.h>

#include <filesystem>

#include "tests/gltf_material_scenes.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

// The four quadrants' interiors of a size x size image.
std::vector<Window> Quadrants(int size) {
  int h = size / 2, m = size / 16 + 1;
  int lo[2] = {m, h + m}, hi[2] = {h - m, size - m};
  std::vector<Window> w;
  for (int q = 0; q < 4; ++q) w.push_back({lo[q % 2], lo[q / 2], hi[q % 2], hi[q / 2]});
  return w;
}

template <typename MakeScene>
void ExpectBackendsAgree(MakeScene make, SceneSpec spec, const char* what, double relative = 0.0) {
  spec.seed = 11;
  Scene cpuScene = make(spec);
  spec.seed = 12;
  Scene gpuScene = make(spec);
  FilmImage cpu = RenderOnCpu(cpuScene).image, gpu = RenderCuda(gpuScene, {}).image;
  ExpectWindowsAgree(cpu, gpu, Quadrants(spec.size), what, relative);
}

TEST(GltfMaterialGpu, FeatureScenesMatchTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  std::string dir = TempDir();
  SceneSpec spec;
  spec.size = 32;
  spec.spp = 64;
  // Point-lit and emission-only images are nearly noise-free: 0.2% for rounding differences.
  ExpectBackendsAgree([&](SceneSpec s) { return NormalMapScene(dir, 0, s); }, spec, "normal map", 2e-3);
  ExpectBackendsAgree([&](SceneSpec s) { return NormalMapScene(dir, 1, s); }, spec, "tangents", 2e-3);
  ExpectBackendsAgree([&](SceneSpec s) { return EmissiveTextureScene(dir, false, s); }, spec,
                      "emissive texture", 2e-3);
  ExpectBackendsAgree([&](SceneSpec s) { return EmissiveTextureScene(dir, true, s); }, spec,
                      "emissive texture as a light");
  ExpectBackendsAgree([&](SceneSpec s) { return AlphaShadowScene(dir, "mask", s); }, spec,
                      "alpha mask shadow", 2e-3);
  ExpectBackendsAgree([&](SceneSpec s) { return AlphaShadowScene(dir, "blend", s); }, spec,
                      "alpha blend shadow");
  ExpectBackendsAgree([&](SceneSpec s) { return AlphaShadowScene(dir, "up", s); }, spec,
                      "culled back face", 2e-3);
  SceneSpec deep = spec;
  deep.maxDepth = 12;
  ExpectBackendsAgree([&](SceneSpec s) { return TransmissionScene(dir, false, vec3(1, 0.2f, 0.5f), 1, s); },
                      deep, "thin tinted transmission", 2e-3);
  ExpectBackendsAgree([&](SceneSpec s) { return TransmissionScene(dir, true, vec3(1, 0.2f, 0.5f), 0.5f, s); },
                      deep, "tinted absorbing volume");
  SceneSpec two = spec;
  two.maxDepth = 2;
  ExpectBackendsAgree([&](SceneSpec s) { return VertexColorScene(dir, vec4(0.5f, 0.25f, 1, 1), s); },
                      two, "vertex colour");
  SceneSpec one = spec;
  one.spp = 4;
  ExpectBackendsAgree([&](SceneSpec s) { return DistantCheckerScene(dir, s); }, one,
                      "mip-filtered checker", 2e-3);
}

TEST(GltfMaterialGpu, DamagedHelmetMatchesTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  if (!HaveShared()) GTEST_SKIP() << "../shared is not present (a user's clone)";
  const std::string helmet =
      SharedPath("assets/khronos/DamagedHelmet/glTF-Binary/DamagedHelmet.glb");
  if (!std::filesystem::exists(helmet)) GTEST_SKIP() << helmet << " is not present";
  auto scene = [&helmet](uint32_t seed) {
    std::string json = R"({"render": {"width": 64, "height": 64, "spp": 64, "max_depth": 4, "seed": )" +
                       std::to_string(seed) + R"(}, "camera": {"position": [0, 0, 3],
        "look_at": [0, 0, -0.1], "fov_y": 40}, "background": [0.5, 0.5, 0.5], "materials": {},
        "objects": [{"type": "mesh", "file": ")" + helmet + "\"}]}";
    return BuildScene(LoadSceneFromString(json, "helmet.json", "."));
  };
  FilmImage cpu = RenderOnCpu(scene(1)).image, gpu = RenderCuda(scene(2), {}).image;
  ExpectWindowsAgree(cpu, gpu, Quadrants(64), "DamagedHelmet quadrant");
}

}  // namespace
}  // namespace pt::test
