// --light-paths, --film double and the first-hit feature buffers.
#include <gtest/gtest.h>

#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

Scene Cornell(int size, int spp) {
  SceneDesc desc = LoadScene(SourcePath("scenes/cornell_glass_mirror.json"));
  desc.render.width = desc.render.height = size;
  desc.render.spp = spp;
  return BuildScene(std::move(desc));
}

// Direct and indirect light split the same paths (same seed, same random numbers), so their
// sum is the full image up to float rounding of the per-path sums.
TEST(LightPaths, DirectPlusIndirectIsAll) {
  Scene scene = Cornell(32, 8);
  RenderOptions opt;
  opt.threads = 2;
  opt.lightPaths = LightPaths::kAll;
  FilmImage all = RenderCpu(scene, opt).image;
  opt.lightPaths = LightPaths::kDirect;
  FilmImage direct = RenderCpu(scene, opt).image;
  opt.lightPaths = LightPaths::kIndirect;
  FilmImage indirect = RenderCpu(scene, opt).image;
  double directSum = 0, indirectSum = 0;
  for (size_t i = 0; i < all.rgb.size(); ++i) {
    float sum = direct.rgb[i] + indirect.rgb[i];
    ASSERT_NEAR(sum, all.rgb[i], 1e-4f * std::max(1.0f, all.rgb[i])) << "value " << i;
    directSum += direct.rgb[i];
    indirectSum += indirect.rgb[i];
  }
  // Both parts carry light in this closed box.
  EXPECT_GT(directSum, 0.0);
  EXPECT_GT(indirectSum, 0.0);
}

// Double accumulation changes rounding only: the images agree to float precision.
TEST(Film, DoubleAndFloatAgree) {
  Scene scene = Cornell(32, 16);
  RenderOptions opt;
  opt.threads = 2;
  FilmImage f = RenderCpu(scene, opt).image;
  opt.filmDouble = true;
  FilmImage d = RenderCpu(scene, opt).image;
  for (size_t i = 0; i < f.rgb.size(); ++i)
    ASSERT_NEAR(f.rgb[i], d.rgb[i], 1e-4f * std::max(1.0f, d.rgb[i]));
}

// Features: a diffuse sphere filling the centre: albedo is its albedo, the normal is unit
// and faces the camera, depth is the camera-to-surface distance; misses are zero.
TEST(FeatureBuffers, FirstHitAlbedoNormalDepth) {
  Scene scene = SceneFromJson(R"({
    "render": {"width": 16, "height": 16, "spp": 4, "max_depth": 2},
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 30},
    "background": [1, 1, 1],
    "materials": {"m": {"type": "diffuse", "albedo": [0.2, 0.4, 0.6]}},
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]
  })");
  RenderOptions opt;
  opt.featureBuffers = true;
  FilmImage img = RenderOnCpu(scene, opt).image;
  ASSERT_EQ(img.albedo.size(), 16u * 16u * 3u);
  size_t centre = 8 * 16 + 8;
  EXPECT_NEAR(img.albedo[3 * centre + 0], 0.2f, 1e-6f);
  EXPECT_NEAR(img.albedo[3 * centre + 2], 0.6f, 1e-6f);
  vec3 n(img.normal[3 * centre], img.normal[3 * centre + 1], img.normal[3 * centre + 2]);
  EXPECT_NEAR(glm::length(n), 1.0f, 0.02f);  // averaged over 4 nearby normals
  EXPECT_GT(n.z, 0.98f);
  EXPECT_NEAR(img.depth[centre], 4.0f, 0.02f);  // the sphere's front at z = 1
  EXPECT_EQ(img.depth[0], 0.0f);                 // the corner sees only the background
  EXPECT_EQ(img.albedo[0], 0.0f);
}

}  // namespace
}  // namespace pt::test
