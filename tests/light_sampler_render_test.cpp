// The light samplers in whole renders: uniform, power and bvh estimate the same image (Welch's
// t per 8x8 block over independent seeds) in a room lit by many lights of every kind, with
// glossy, glass and two-sided surfaces and a camera that sees the emitters (MIS at every hit
// uses the receiver normal carried in path state); auto picks the tree for many lights; and an
// emissive texture's black texels make no lights.
#include <gtest/gtest.h>

#include <string>

#include "src/lights/light_bvh_build.h"
#include "tests/gltf_writer.h"
#include "tests/light_bvh_test_util.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"
#include "tests/welch.h"

namespace pt::test {
namespace {

FilmImage RenderWith(LightSampler sampler, int seed) {
  Scene scene = SceneFromJson(ManyLightRoom(seed));
  RenderOptions o;
  o.lightSampler = sampler;
  RenderResult r = RenderOnCpu(scene, o);
  EXPECT_EQ(r.stats.lightSampler, LightSamplerName(sampler));
  EXPECT_EQ(r.stats.nonfiniteSamples, 0u);
  return r.image;
}

// Under agreement each block fails at the 1% level with probability 0.01; the count allowed
// is exceeded with probability 1e-3.
void ExpectSamplersAgree(LightSampler a, LightSampler b) {
  const int kSeeds = 6;
  const double kBlockAlpha = 0.01;
  std::vector<std::vector<double>> x, y;
  for (int k = 0; k < kSeeds; ++k) {
    x.push_back(BlockLuminance(RenderWith(a, 100 + k)));
    y.push_back(BlockLuminance(RenderWith(b, 200 + k)));
  }
  int blocks = int(x[0].size()), failing = FailingBlocks(x, y, kBlockAlpha);
  EXPECT_LE(failing, BinomialUpperBound(blocks, kBlockAlpha, 1e-3))
      << LightSamplerName(a) << " vs " << LightSamplerName(b) << ": " << failing << " of "
      << blocks << " blocks differ at the 1% level";
}

TEST(LightSamplerRender, BvhAndPowerEstimateTheSameImage) {
  ExpectSamplersAgree(LightSampler::kBvh, LightSampler::kPower);
}

TEST(LightSamplerRender, UniformAndPowerEstimateTheSameImage) {
  ExpectSamplersAgree(LightSampler::kUniform, LightSampler::kPower);
}

TEST(LightSamplerRender, AutoChoosesTheTreeForManyLights) {
  RenderOptions o;  // kAuto
  Scene many = SceneFromJson(ManyLightRoom(1));
  ASSERT_GE(many.lightTree.nodeCount, 2 * kAutoBvhMinLights);
  EXPECT_EQ(ChooseLightSampler(LightSampler::kAuto, many), LightSampler::kBvh);
  Scene few = SceneFromJson(ManyLightRoom(1, 2));  // 4 lamps, 3 balls, point, spot
  EXPECT_EQ(ChooseLightSampler(LightSampler::kAuto, few), LightSampler::kPower);
  RenderResult r = RenderOnCpu(few, o);
  EXPECT_EQ(r.stats.lightSampler, "power");
}

// Emissive texture: black on the left half (x < 4 of 8 texels), white on the right.
TEST(LightSamplerRender, BlackEmissiveTexelsMakeNoLights) {
  std::string dir = TempDir();
  RgbaImage img(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      uint8_t v = x < 4 ? 0 : 255;
      img.Set(x, y, v, v, v, 255);
    }
  GltfWriter w("half_black");
  int tex = w.AddTexture(img);
  w.AddMaterial(R"({"emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": )" +
                std::to_string(tex) + "}}");
  GltfPrimitive p;
  p.material = 0;
  // Triangles at z = 0 (area 0.5 each) with UVs: in the black half, in the white half, across
  // both, and one so small it covers no texel centre (inside white texel (6, 2)).
  const vec2 uvs[4][3] = {{{0.05f, 0.1f}, {0.45f, 0.1f}, {0.05f, 0.9f}},
                          {{0.55f, 0.1f}, {0.95f, 0.1f}, {0.55f, 0.9f}},
                          {{0.05f, 0.05f}, {0.95f, 0.2f}, {0.3f, 0.95f}},
                          {{0.76f, 0.26f}, {0.79f, 0.26f}, {0.76f, 0.29f}}};
  for (int t = 0; t < 4; ++t) {
    vec3 o(2.0f * t, 0.0f, 0.0f);
    for (vec3 v : {o, o + vec3(1, 0, 0), o + vec3(0, 1, 0)}) p.positions.push_back(v);
    for (int k = 0; k < 3; ++k) p.uvs.push_back(uvs[t][k]);
  }
  p.normals.assign(12, vec3(0, 0, 1));
  w.AddPrimitive(p);
  std::string json = R"({"render": {"width": 8, "height": 8, "spp": 1, "max_depth": 2},
      "camera": {"position": [3, 0.5, 5], "look_at": [3, 0.5, 0], "fov_y": 60}, "materials": {},
      "objects": [{"type": "mesh", "file": ")" + w.Write(dir) + "\"}]}";
  Scene scene = BuildScene(LoadSceneFromString(json, "t.json", dir));
  // The triangles' lights by their position along x.
  std::vector<int32_t> light(4, -2);
  for (const PrimRef& prim : scene.prims) {
    int t = int(std::round(scene.desc.triangles[prim.Index()].p0.x / 2.0f));
    light[t] = prim.light;
  }
  EXPECT_EQ(light[0], -1) << "black texels: no light";
  ASSERT_GE(light[1], 0);
  ASSERT_GE(light[2], 0);
  ASSERT_GE(light[3], 0) << "no texel centre inside: its centroid's texel";
  EXPECT_EQ(scene.lights.size(), 3u);
  // Powers relative to the all-white triangle: the share of white texel centres covered.
  int white = 0, covered = 0;
  const vec2* t2 = uvs[2];
  auto side = [](vec2 a, vec2 b, vec2 c) {
    return double(b.x - a.x) * (c.y - a.y) - double(b.y - a.y) * (c.x - a.x);
  };
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      vec2 c((x + 0.5f) / 8.0f, (y + 0.5f) / 8.0f);
      if (side(t2[0], t2[1], c) < 0 || side(t2[1], t2[2], c) < 0 || side(t2[2], t2[0], c) < 0)
        continue;
      ++covered;
      white += x >= 4 ? 1 : 0;
    }
  ASSERT_GT(covered, 10);
  double full = scene.lightPower[size_t(light[1])];
  EXPECT_NEAR(scene.lightPower[size_t(light[2])] / full, double(white) / covered, 1e-6);
  EXPECT_NEAR(scene.lightPower[size_t(light[3])] / full, 1.0, 1e-6);
  // Every sampler chooses among those three only.
  for (LightSampler s : {LightSampler::kUniform, LightSampler::kPower, LightSampler::kBvh}) {
    RenderOptions o;
    o.lightSampler = s;
    EXPECT_EQ(RenderOnCpu(scene, o).stats.nonfiniteSamples, 0u);
  }
}

}  // namespace
}  // namespace pt::test
