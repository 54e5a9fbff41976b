// Texture filtering scales with the sample count (src/materials/surface_attributes.h): each
// lookup prefilters over 1 / sqrt(spp) of a pixel, at least 1/8, so a converged render keeps
// detail a fixed half-pixel footprint averaged away while one sample per pixel stays unaliased
// (tests/gltf_material_render_test.cpp: DistantCheckerIsFilteredNotAliased).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "src/materials/surface_attributes.h"
#include "tests/pixel_checker_scene.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

TEST(TextureFootprint, ShrinksAsOneOverTheRootOfTheSampleCountDownToAnEighth) {
  const std::pair<int, float> rule[] = {{1, 1.0f},   {2, 0.70710677f}, {4, 0.5f}, {16, 0.25f},
                                        {64, 0.125f}, {65, 0.125f},    {4096, 0.125f}};
  for (auto [spp, scale] : rule) EXPECT_FLOAT_EQ(TextureFootprintScale(spp), scale) << spp;
  // The render's spp sets the camera's footprint once, on the host, for every backend.
  std::string dir = TempDir();
  for (int spp : {1, 9, 256}) {
    SceneSpec spec;
    spec.spp = spp;
    Scene scene = PixelCheckerScene(dir, spec);
    EXPECT_EQ(scene.camera.textureFootprint, TextureFootprintScale(spp)) << spp;
  }
  CameraDesc desc;
  desc.lookAt = vec3(0, 0, -1);
  EXPECT_EQ(MakeCamera(desc, 8, 8).textureFootprint, 1.0f);  // as one sample
  EXPECT_EQ(MakeCamera(desc, 8, 8, 100).textureFootprint, 0.125f);
}

struct Contrast {
  double value, standardError;
};

// Mean of the white checks' pixels minus the black ones', with the standard error from the
// spread between pixels of each colour (it covers the pixel's own sampling noise).
Contrast CheckerContrast(const FilmImage& img) {
  double sum[2] = {0, 0}, sumSq[2] = {0, 0}, n[2] = {0, 0};
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      double v = img.rgb[3 * (size_t(y) * img.width + x)];
      int k = PixelCheckIsWhite(x, y);
      sum[k] += v;
      sumSq[k] += v * v;
      n[k] += 1;
    }
  double mean[2], var[2];
  for (int k = 0; k < 2; ++k) {
    mean[k] = sum[k] / n[k];
    var[k] = (sumSq[k] - n[k] * mean[k] * mean[k]) / (n[k] - 1) / n[k];
  }
  return {mean[1] - mean[0], std::sqrt(var[0] + var[1])};
}

// One-pixel checks, 4 texels each. A lookup of footprint F pixels reads level log2(4 F)
// bilinearly, whose ramps blur each check's border: pixel means are a + b - 2ab with a, b the
// 1D means of the linear ramps, so the contrast between white and black pixels is
//   level 2 (F = 1, 1 spp): 0.25;  level 1 (F = 1/2, 4 spp): 0.5625;
//   level 0 (F <= 1/4, 16 spp and more): 0.766.
// The old fixed half-pixel footprint gave 0.5625 at every sample count.
TEST(TextureFootprint, PixelCheckerIsResolvedAsSamplesGrow) {
  std::string dir = TempDir();
  const std::pair<int, double> expected[] = {{1, 0.25}, {4, 0.5625}, {256, 0.765625}};
  for (auto [spp, contrast] : expected) {
    SceneSpec spec;
    spec.spp = spp;
    spec.size = spp == 256 ? 32 : 64;
    Contrast c = CheckerContrast(RenderOnCpu(PixelCheckerScene(dir, spec)).image);
    // 5 standard errors, plus 0.01 for what the rule above leaves out: the lod grows a little
    // towards the image's edges (the distance from the camera), mixing in the next level.
    EXPECT_NEAR(c.value, contrast, 5.0 * c.standardError + 0.01) << spp << " spp";
  }
}

// A checkpoint of a textured scene records its footprint: --resume with a --spp that changes it
// is refused (exit 2, the difference named), one that keeps it (both >= 64 spp) continues.
TEST(TextureFootprint, ResumeKeepsTheFootprintOfTheCheckpoint) {
  std::string dir = TempDir();
  std::string model = WritePixelCheckerModel(dir, 8);
  std::ofstream(dir + "/checker.json")
      << R"({"render": {"width": 8, "height": 8, "spp": 2, "max_depth": 1},
          "camera": {"position": [0, 0, 60], "look_at": [0, 0, 0], "fov_y": 1.9},
          "materials": {}, "objects": [{"type": "mesh", "file": ")" + model + "\"}]}";
  auto render = [&](const std::string& name, const std::string& extra, std::string* out) {
    return RunCommand(BinaryPath("pathtracer") + " " + dir + "/checker.json -o " + dir + "/" +
                          name + ".pfm --hdr " + dir + "/" + name +
                          ".exr --backend cpu --quiet --checkpoint-every 1000" + extra,
                      out);
  };
  std::string out;
  ASSERT_EQ(render("two", " --spp 2", &out), 0) << out;
  EXPECT_EQ(render("four", " --spp 4 --resume " + dir + "/two.exr", &out), 2) << out;
  EXPECT_NE(out.find("texture filter footprint (follows --spp below 64 spp): 0.707106"),
            std::string::npos) << out;
  ASSERT_EQ(render("many", " --spp 64", &out), 0) << out;
  EXPECT_EQ(render("more", " --spp 100 --resume " + dir + "/many.exr", &out), 0) << out;
}

}  // namespace
}  // namespace pt::test
