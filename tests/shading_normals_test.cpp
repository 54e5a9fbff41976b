// Shading normals neither blacken nor leak (src/materials/shading_normal.h bends a normal the
// viewer sees from behind; src/integrator/stages/normal_fold.h folds the BSDF about the
// geometric surface instead of dropping directions the two surfaces disagree about):
// - a closed mesh with smooth or wild vertex normals lets no light through, for every opaque
//   material;
// - a plane whose normals tilt away from the viewer, and a coarse smooth-shaded sphere whose
//   interpolated normals face away at its silhouette, render no black pixel and keep the
//   flat-shaded energy under a uniform environment (a white diffuse surface stays exactly its
//   albedo, a white mirror exactly 1);
// - glTF materials with a wild normal texture reflect at most what arrives (white furnace).
#include <gtest/gtest.h>

#include <random>

#include "src/materials/shading_normal.h"

#include "tests/render_test_util.h"
#include "tests/shading_normal_scenes.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

// The bend (shading_normal.h) on random configurations: a normal whose mirror reflection of
// the view is already high enough is returned bit for bit; a bent one is a unit vector in the
// plane of the normal and the geometric normal, on the near side of the surface, whose
// reflection of the view has exactly the required elevation min(0.9 cos, 0.01) (the smallest
// rotation that makes it valid), and the viewer sees its front.
TEST(ShadingNormals, BentNormalReflectsTheViewJustAboveTheSurface) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const vec3 ng(0.0f, 0.0f, 1.0f);
  int bent = 0;
  for (int i = 0; i < 20000; ++i) {
    vec3 wo = glm::normalize(vec3(u(rng), u(rng), std::fabs(u(rng)) + 1e-3f));
    vec3 ns = glm::normalize(vec3(u(rng), u(rng), std::fabs(u(rng)) + 1e-2f));
    float cosO = glm::dot(wo, ng), threshold = std::min(0.9f * cosO, 0.01f);
    vec3 n = BendForValidReflection(ng, wo, ns);
    vec3 r = 2.0f * glm::dot(n, wo) * n - wo;
    if (glm::dot(2.0f * glm::dot(ns, wo) * ns - wo, ng) >= threshold) {
      ASSERT_TRUE(n == ns) << i;
      continue;
    }
    ++bent;
    ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f) << i;
    ASSERT_NEAR(glm::dot(n, glm::normalize(glm::cross(ns, ng))), 0.0f, 2e-3f) << i;  // in plane
    ASSERT_GT(n.z, 0.0f) << i;
    ASSERT_NEAR(glm::dot(r, ng), threshold, 2e-3f) << i;
    ASSERT_GT(glm::dot(n, wo), 0.0f) << i;
  }
  EXPECT_GT(bent, 2000);  // the configurations exercised the bend
}

// A point light inside a closed sphere: nothing outside may be lit, whatever the normals say
// and whatever the (opaque) material.
TEST(ShadingNormals, NoLightLeaksThroughAClosedMesh) {
  for (uint32_t material : {kNtDiffuse, kNtMirror, kNtRough, kNtPlastic}) {
    for (uint32_t wild : {0u, 7u}) {
      SceneDesc d = NormalTestScene(R"(, "lights": [{"type": "point", "position": [0, 0, 0.7],
                                          "intensity": [100, 100, 100]}])");
      AddNormalTestIcosphere(d, vec3(0.0f), 1.0f, 1, material, true, wild);
      d.render.spp = 16;
      RenderResult r = RenderOnCpu(BuildScene(std::move(d)));
      for (size_t i = 0; i < r.image.rgb.size(); ++i)
        ASSERT_EQ(r.image.rgb[i], 0.0f)
            << "light leaked at pixel " << i / 3 << ", material " << material << " wild " << wild;
    }
  }
}

// Pixel k's mean is `expected` within z standard errors (its own sample variance).
void ExpectPixelNear(const FilmImage& img, size_t k, double expected, double z,
                     const std::string& what) {
  double sigma = std::sqrt(double(img.variance[3 * k]) / img.samples[k]);
  EXPECT_NEAR(img.rgb[3 * k], expected, z * sigma + 1e-5) << what << " pixel " << k;
}

// Under a uniform environment of radiance 1, a flat diffuse square shows its albedo and a
// white mirror shows 1, at every pixel (the camera sees only the square). Normals tilted 40
// degrees away from the viewer must change neither: no pixel black, each within noise of the
// flat value, and the whole square's mean within its standard error.
TEST(ShadingNormals, NormalsTiltedAwayFromTheViewerKeepTheFlatEnergy) {
  for (uint32_t material : {kNtDiffuse, kNtMirror}) {
    double expected = material == kNtDiffuse ? 0.5 : 1.0;
    RenderResult r = RenderOnCpu(BuildScene(TiltedNormalSquare(material, 40.0f)));
    const FilmImage& img = r.image;
    // 32 x 32 pixels, two-sided each, plus the mean: a family false-alarm rate under 1e-4.
    double z = TwoSidedNormalQuantile(1e-4 / 1025);
    double sum = 0.0, varianceOfSum = 0.0;
    for (size_t k = 0; k < img.samples.size(); ++k) {
      ASSERT_GT(img.rgb[3 * k], 0.05f) << "black pixel " << k << ", material " << material;
      ExpectPixelNear(img, k, expected, z, "material " + std::to_string(material));
      sum += img.rgb[3 * k];
      varianceOfSum += double(img.variance[3 * k]) / img.samples[k];
    }
    double n = double(img.samples.size());
    EXPECT_NEAR(sum / n, expected, z * std::sqrt(varianceOfSum) / n + 1e-6) << material;
  }
}

// A coarse sphere (80 faces, normals up to ~20 degrees off the facets) in a uniform
// environment: at the silhouette its interpolated normals face away from the camera. Smooth
// and flat shading see the same geometry, so each pixel (silhouette pixels too) has the same
// expectation, and no pixel on the sphere may be black.
TEST(ShadingNormals, SmoothSphereMatchesTheFlatOneAtEveryPixel) {
  FilmImage img[2];
  for (bool smooth : {false, true}) {
    SceneDesc d = NormalTestScene(R"(, "background": [1, 1, 1])");
    AddNormalTestIcosphere(d, vec3(0.0f), 1.0f, 1, kNtDiffuse, smooth);
    d.render.spp = 128;
    img[smooth] = RenderOnCpu(BuildScene(std::move(d))).image;
  }
  // Every pixel, plus the sum over the sphere's pixels (where a bias of a few percent near the
  // silhouette shows): a family false-alarm rate under 1e-4.
  double z = TwoSidedNormalQuantile(1e-4 / 1025);
  double sum[2] = {0, 0}, varianceOfDifference = 0.0;
  for (size_t k = 0; k < img[0].samples.size(); ++k) {
    ASSERT_GT(img[1].rgb[3 * k], 0.1f) << "black pixel " << k;
    double var = double(img[0].variance[3 * k]) / img[0].samples[k] +
                 double(img[1].variance[3 * k]) / img[1].samples[k];
    EXPECT_NEAR(img[1].rgb[3 * k], img[0].rgb[3 * k], z * std::sqrt(var) + 1e-5) << "pixel " << k;
    if (img[0].rgb[3 * k] == 1.0f) continue;  // background only
    for (int s = 0; s < 2; ++s) sum[s] += img[s].rgb[3 * k];
    varianceOfDifference += var;
  }
  EXPECT_NEAR(sum[1], sum[0], z * std::sqrt(varianceOfDifference)) << "the sphere's total";
}

// A white furnace with a wild normal texture (random texels): glTF materials, diffuse and
// metallic at several roughnesses, reflect at most what arrives at every pixel, and none is
// black.
TEST(ShadingNormals, WildNormalMapsInAWhiteFurnaceReflectAtMostOne) {
  std::string dir = TempDir();
  for (int i = 0; i < 4; ++i) {
    SceneSpec spec;
    spec.spp = 64;
    spec.maxDepth = 8;
    FilmImage img = RenderOnCpu(WildNormalFurnace(dir, i, spec)).image;
    double z = TwoSidedNormalQuantile(1e-4 / (4 * 1024));
    for (size_t k = 0; k < img.samples.size(); ++k) {
      double sigma = std::sqrt(double(img.variance[3 * k]) / img.samples[k]);
      ASSERT_GT(img.rgb[3 * k], 0.02f) << "black pixel " << k << ", material " << i;
      EXPECT_LE(img.rgb[3 * k], 1.0 + z * sigma + 1e-5) << "pixel " << k << ", material " << i;
    }
  }
}

}  // namespace
}  // namespace pt::test
