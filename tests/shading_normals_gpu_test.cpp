// Shading normals (bent, and the BSDF folded about the geometric surface) and the texture
// footprint that follows the sample count give the CPU's answer on the GPU: the same stage
// bodies in the diffuse, smooth and general variants, and the footprint read from the camera
// both backends are given. Independent seeds per backend; window means compared with the
// films' variances. Skip without a GPU.
#include <gtest/gtest.h>

#include "tests/pixel_checker_scene.h"
#include "tests/render_test_util.h"
#include "tests/shading_normal_scenes.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

void ExpectShadingAgrees(SceneDesc desc, const char* what) {
  SceneDesc other = desc;
  other.render.seed += 100;
  FilmImage cpu = RenderOnCpu(BuildScene(std::move(desc))).image;
  FilmImage gpu = RenderCuda(BuildScene(std::move(other)), {}).image;
  ExpectWindowsAgree(cpu, gpu, BlockWindows(cpu, 4), what, 1e-4);
}

TEST(ShadingNormalsGpu, BentAndFoldedNormalsMatchTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  ExpectShadingAgrees(TiltedNormalSquare(kNtDiffuse, 40.0f), "tilted normals, diffuse");
  ExpectShadingAgrees(TiltedNormalSquare(kNtMirror, 40.0f), "tilted normals, mirror");
  ExpectShadingAgrees(TiltedNormalSquare(kNtPlastic, 40.0f), "tilted normals, plastic");
  SceneDesc sphere = NormalTestScene(R"(, "background": [1, 1, 1])");
  AddNormalTestIcosphere(sphere, vec3(0.0f), 1.0f, 1, kNtRough, true, 7);
  ExpectShadingAgrees(sphere, "wild normals, rough conductor");
  std::string dir = TempDir();
  for (int i = 0; i < 4; ++i) {
    SceneSpec spec;
    spec.spp = 64;
    spec.maxDepth = 8;
    spec.seed = 1;
    FilmImage cpu = RenderOnCpu(WildNormalFurnace(dir, i, spec)).image;
    spec.seed = 2;
    FilmImage gpu = RenderCuda(WildNormalFurnace(dir, i, spec), {}).image;
    ExpectWindowsAgree(cpu, gpu, BlockWindows(cpu, 4), "wild normal map furnace", 1e-4);
  }
}

TEST(ShadingNormalsGpu, TextureFootprintFollowsTheSampleCountOnBothBackends) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  std::string dir = TempDir();
  for (int spp : {1, 4, 256}) {
    SceneSpec spec;
    spec.size = 32;
    spec.spp = spp;
    spec.seed = 5;
    // The same seed on both backends: the same samples, so the windows differ only where the
    // backends' texel reads do (an independent seed's noise exceeded the 1-spp bound on an H100).
    Scene a = PixelCheckerScene(dir, spec);
    Scene b = PixelCheckerScene(dir, spec);
    ASSERT_EQ(a.camera.textureFootprint, b.camera.textureFootprint);
    FilmImage cpu = RenderOnCpu(a).image, gpu = RenderCuda(b, {}).image;
    // Emission only: each sample is a texture lookup at the same point on both backends, so
    // the windows' means agree up to the GPU's rounding (a different footprint moves them by
    // the contrast differences the CPU test measures, 0.2-0.3).
    ExpectWindowsAgree(cpu, gpu, BlockWindows(cpu, 4), "pixel checker", 2e-3);
  }
}

}  // namespace
}  // namespace pt::test
