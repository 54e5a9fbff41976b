// The glTF extension lobes (the layered shade variant) give the CPU's answer on the GPU: one
// scene per extension (tests/gltf_extensions_scenes.h), rendered on both backends with
// independent seeds, window means compared with the films' variances. Skips without a GPU.
#include <gtest/gtest.h>

#include "tests/gltf_extensions_scenes.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

void ExpectExtensionBackendsAgree(const ExtensionSceneSpec& e, const char* what, double relative = 0.0) {
  std::string dir = TempDir();
  SceneSpec spec;
  spec.size = 16;
  spec.spp = 256;
  spec.maxDepth = 4;
  spec.seed = 11;
  Scene cpuScene = ExtensionScene(dir, e, spec);
  spec.seed = 12;
  Scene gpuScene = ExtensionScene(dir, e, spec);
  FilmImage cpu = RenderOnCpu(cpuScene).image, gpu = RenderCuda(gpuScene, {}).image;
  ExpectWindowsAgree(cpu, gpu, BlockWindows(cpu, 2), what, relative);
}

ExtensionSceneSpec GpuExtSpec(const std::string& name, const std::string& material, double theta,
                        const std::string& extra = kWhiteBackground) {
  ExtensionSceneSpec s;
  s.name = name;
  s.material = material;
  s.camera = ObliqueCamera(theta, 1.5);  // the square and the background around it
  s.extra = extra;
  return s;
}

TEST(GltfExtensionsGpu, ExtensionScenesMatchTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  ExpectExtensionBackendsAgree(GpuExtSpec("gcc", ClearcoatMaterial(true), 50.0), "clearcoat");
  ExpectExtensionBackendsAgree(GpuExtSpec("gsp", SpecularMaterial(true), 20.0), "specular");
  ExpectExtensionBackendsAgree(GpuExtSpec("gsh", SheenMaterial(true), 65.0), "sheen");
  ExpectExtensionBackendsAgree(GpuExtSpec("gir", IridescenceMaterial(true), 30.0), "iridescence");
  ExpectExtensionBackendsAgree(GpuExtSpec("gan", AnisotropyMaterial(true), 0.0, DirectionalLight(OffNormalLightDirection())),
                      "anisotropy", 2e-3);
  ExpectExtensionBackendsAgree(GpuExtSpec("gdt", DiffuseTransmissionMaterial(true), 10.0, DirectionalLight(vec3(0, 0, 1))),
                      "diffuse transmission", 2e-3);
  ExpectExtensionBackendsAgree(GpuExtSpec("gul", UnlitMaterial(true), 0.0, ""), "unlit", 2e-3);
  ExtensionSceneSpec metal = GpuExtSpec("gec", RoughWhiteMetal(), 40.0);
  metal.energyCompensation = true;
  ExpectExtensionBackendsAgree(metal, "energy compensation");
}

}  // namespace
}  // namespace pt::test
