// The glTF material features rendered end to end on the CPU, against analytic values: normal
// maps tilt the lit side by the factor the BSDF gives the tilted normal, emissive textures
// light only their texels and every integrator sees the same light, an alpha cutoff and back-
// face culling let shadow rays through, BLEND at alpha 0.5 passes half the light, transmission
// keeps its tint (thin walls and volumes, with Beer-Lambert absorption), COLOR_0 multiplies
// the base colour, and a distant high-frequency texture is filtered instead of aliased.
#include <gtest/gtest.h>

#include <cstring>

#include "src/integrator/stages/generate.h"
#include "src/materials/bsdf.h"
#include "src/materials/texture.h"
#include "src/scene/effects.h"
#include "tests/gltf_material_scenes.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

// The image position of pixel (x, y)'s centre on the plane z = 0 under FarCamera(half).
vec3 PlanePoint(int x, int y, int size, double half) {
  return vec3(float((2.0 * (x + 0.5) / size - 1.0) * half),
              float((1.0 - 2.0 * (y + 0.5) / size) * half), 0.0f);
}

// Radiance towards the camera of the normal-mapped square at p under NormalMapScene's light,
// computed from the BSDF with the shading normal n: f(wo, wi) |cos wi| E.
double LitRadiance(const Material& m, vec3 n, vec3 p) {
  vec3 light = 600.0f * vec3(std::sqrt(0.5f), 0.0f, std::sqrt(0.5f));
  vec3 wi = glm::normalize(light - p), wo = glm::normalize(vec3(0, 0, 60) - p);
  float irradiance = 360000.0f / glm::dot(light - p, light - p);
  Frame f = Frame::FromZ(n);
  vec3 wiL = f.ToLocal(wi);
  return EvalBsdf(m, f.ToLocal(wo), wiL).x * fabsf(wiL.z) * irradiance;
}

// The renderer's decoding of a tangent-space normal texel (x, y scaled) in the square's frame
// (tangent +x, bitangent +y, normal +z).
vec3 DecodedNormal(const uint8_t code[4], float scale) {
  vec3 c = 2.0f * vec3(code[0], code[1], code[2]) / 255.0f - vec3(1.0f);
  return glm::normalize(vec3(c.x * scale, c.y * scale, c.z));
}

TEST(GltfMaterialRender, NormalMapTiltsTheLitSideByTheBsdfsFactor) {
  std::string dir = TempDir();
  SceneSpec spec;
  for (int variant : {0, 1, 2}) {  // tangents from UVs, from TANGENT, normalTexture.scale 0.5
    Scene scene = NormalMapScene(dir, variant, spec);
    ASSERT_EQ(scene.desc.triangleTangents.empty(), variant != 1);
    const Material& m = scene.desc.materials.back();  // after the scene's floor
    FilmImage img = RenderOnCpu(scene).image;
    // Columns 2-12 read the tilted texels only, 19-29 the flat ones (bilinear blends between).
    double got[2] = {0, 0}, want[2] = {0, 0};
    float scale = variant == 2 ? 0.5f : 1.0f;
    vec3 normals[2] = {DecodedNormal(kTiltedNormal, scale), DecodedNormal(kFlatNormal, scale)};
    for (int y = 4; y < 28; ++y)
      for (int k = 0; k < 2; ++k)
        for (int x = k ? 19 : 2; x < (k ? 30 : 13); ++x) {
          got[k] += img.rgb[3 * (size_t(y) * spec.size + x)];
          want[k] += LitRadiance(m, normals[k], PlanePoint(x, y, spec.size, 1.0));
        }
    // Point light, direct light only: each sample is f |cos| E at its jittered point, so the
    // window sums differ from the pixel-centre sums only by the variation within pixels.
    EXPECT_NEAR(got[0] / want[0], 1.0, 2e-3) << "variant " << variant;
    EXPECT_NEAR(got[1] / want[1], 1.0, 2e-3) << "variant " << variant;
    EXPECT_GT(want[0], 1.1 * want[1]);  // tilted towards the light: brighter
  }
}

TEST(GltfMaterialRender, EmissiveTextureLightsOnlyItsTexels) {
  std::string dir = TempDir();
  SceneSpec spec;
  Scene scene = EmissiveTextureScene(dir, false, spec);
  FilmImage img = RenderOnCpu(scene).image;
  for (int y = 2; y < 30; ++y) {
    for (int x = 2; x < 13; ++x) ASSERT_EQ(img.rgb[3 * (size_t(y) * spec.size + x)], 0.0f) << x << " " << y;
    for (int x = 19; x < 30; ++x)
      for (int c = 0; c < 3; ++c)  // factor 1 x texel 1 x strength 3; nothing else is lit
        ASSERT_NEAR(img.rgb[3 * (size_t(y) * spec.size + x) + c], 3.0f, 1e-5f) << x << " " << y;
  }
}

// The floor lit by the half-textured emitter: light sampling (which reads the texture at the
// sampled point) and BSDF sampling (which finds it by hitting the emitter) estimate the same
// irradiance, and MIS combines them into the same mean. Each window and pair is a z-test on the
// difference of means with the films' variances (Bonferroni over all of them).
TEST(GltfMaterialRender, EmissiveTextureLightIsTheSameForEveryIntegrator) {
  std::string dir = TempDir();
  SceneSpec spec;
  spec.size = 24;
  spec.spp = 256;
  spec.maxDepth = 1;
  // Also cut by MASK and halved by BLEND: light sampling must count only what a ray would meet.
  for (const char* alpha : {"", "MASK", "BLEND"}) {
    Scene scene = EmissiveTextureScene(dir, true, spec, alpha);
    // The right triangle covers white texel centres; the left one only black ones (filtering
    // bleeds a little light onto its edge, which BSDF sampling alone finds): no light.
    EXPECT_EQ(scene.lights.size(), 1u);
    FilmImage img[3];
    const IntegratorMode modes[3] = {IntegratorMode::kMis, IntegratorMode::kBsdf,
                                     IntegratorMode::kNee};
    for (int i = 0; i < 3; ++i) {
      RenderOptions o;
      o.integrator = modes[i];
      img[i] = RenderOnCpu(scene, o).image;
    }
    // 3 alpha modes x 2 windows x 3 pairs share the false-alarm budget of 1e-4.
    double z = TwoSidedNormalQuantile(1e-4 / 18);
    const int windows[2][4] = {{3, 16, 11, 22}, {13, 16, 21, 22}};  // floor, left and right
    for (const auto& w : windows) {
      WindowMean m[3];
      for (int i = 0; i < 3; ++i) m[i] = MeanOverWindow(img[i], 0, w[0], w[1], w[2], w[3]);
      EXPECT_GT(m[0].mean, 0.005) << alpha;
      for (auto [a, b] : {std::pair{0, 1}, {0, 2}, {1, 2}})
        EXPECT_NEAR(m[a].mean, m[b].mean, z * std::sqrt(m[a].varianceOfMean + m[b].varianceOfMean))
            << "alpha " << alpha << " integrators " << a << " and " << b << " window x " << w[0];
    }
  }
}

// Where pixel (x, y)'s centre ray meets the floor y = 0 (far away when it misses).
vec3 FloorPoint(const Scene& scene, int x, int y, int size) {
  Ray r = CameraRay(scene.camera, x + 0.5f, y + 0.5f, float(size), float(size), vec2(0.5f));
  float t = r.d.y < 0.0f ? -r.o.y / r.d.y : 1e9f;
  return r.o + t * r.d;
}

// Pixels whose floor point lies in x0 < x < x1, |z| < zMax (a margin of a pixel's footprint
// inside the shadow's outline).
std::vector<size_t> FloorPixels(const Scene& scene, int size, float x0, float x1, float zMax) {
  std::vector<size_t> out;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      vec3 p = FloorPoint(scene, x, y, size);
      if (p.x > x0 && p.x < x1 && fabsf(p.z) < zMax) out.push_back(size_t(y) * size + x);
    }
  return out;
}

// Shadows under a point light are deterministic per sample (the same seed jitters the same
// camera rays), so an unoccluded pixel equals the scene without the occluder exactly.
TEST(GltfMaterialRender, AlphaCutoffAndCullingLetShadowRaysThrough) {
  std::string dir = TempDir();
  SceneSpec spec;
  Scene noneScene = AlphaShadowScene(dir, "none", spec);
  FilmImage none = RenderOnCpu(noneScene).image;
  FilmImage mask = RenderOnCpu(AlphaShadowScene(dir, "mask", spec)).image;
  FilmImage up = RenderOnCpu(AlphaShadowScene(dir, "up", spec)).image;
  FilmImage down = RenderOnCpu(AlphaShadowScene(dir, "down", spec)).image;
  // Under the masked-out half (floor x in (-1.2, -0.15)) and the kept half (0.15, 1.2).
  std::vector<size_t> open = FloorPixels(noneScene, spec.size, -1.2f, -0.15f, 1.1f);
  std::vector<size_t> kept = FloorPixels(noneScene, spec.size, 0.15f, 1.2f, 1.1f);
  ASSERT_GT(open.size(), 10u);
  ASSERT_GT(kept.size(), 10u);
  for (size_t i : open) {
    ASSERT_GT(none.rgb[3 * i], 0.0f);
    ASSERT_EQ(mask.rgb[3 * i], none.rgb[3 * i]) << i;
  }
  for (size_t i : kept) {
    ASSERT_EQ(mask.rgb[3 * i], 0.0f) << i;
    ASSERT_EQ(down.rgb[3 * i], 0.0f) << i;  // single-sided, facing down: its front blocks
  }
  // Single-sided and facing up: shadow rays meet its back face, which is culled.
  EXPECT_EQ(std::memcmp(up.rgb.data(), none.rgb.data(), up.rgb.size() * sizeof(float)), 0);
}

// The same through an instance (identity placement: bit for bit the flat scene's image), so the
// instanced traversal runs the hit test when a material asks for it and culls back faces.
TEST(GltfMaterialRender, AlphaCutoffAndCullingHoldForInstancedMeshes) {
  std::string dir = TempDir();
  SceneSpec spec;
  for (const char* mode : {"mask", "up", "down"}) {
    Scene instanced = AlphaShadowScene(dir, mode, spec, true);
    ASSERT_TRUE(instanced.HasInstances()) << mode;
    FilmImage flat = RenderOnCpu(AlphaShadowScene(dir, mode, spec)).image;
    EXPECT_TRUE(SameImage(flat, RenderOnCpu(instanced).image)) << mode;
  }
}

TEST(GltfMaterialRender, BlendAtHalfAlphaPassesHalfTheLight) {
  std::string dir = TempDir();
  SceneSpec spec;
  spec.spp = 64;
  Scene noneScene = AlphaShadowScene(dir, "none", spec);
  FilmImage none = RenderOnCpu(noneScene).image;
  Scene blend = AlphaShadowScene(dir, "blend", spec);
  FilmImage half = RenderOnCpu(blend).image;
  // Under the occluder each shadow ray passes with probability 1/2, independently per ray: a
  // pixel's mean is its unoccluded value times a binomial fraction. z-test on the sums with the
  // film's own variances (pixels independent), false-alarm probability 1e-4.
  double sumHalf = 0, sumNone = 0, var = 0;
  for (size_t i : FloorPixels(noneScene, spec.size, -1.1f, 1.1f, 1.1f)) {
    sumHalf += half.rgb[3 * i];
    sumNone += none.rgb[3 * i];
    var += half.variance[3 * i] / half.samples[i] + 0.25 * none.variance[3 * i] / none.samples[i];
  }
  EXPECT_GT(var, 0.0);
  EXPECT_NEAR(sumHalf, 0.5 * sumNone, kZ1e4 * std::sqrt(var));
  // Stochastic, yet bit-identical across threads, compaction and sort (the coin hashes the ray).
  RenderOptions o;
  o.threads = 1;
  o.compact = Toggle::kOn;
  o.sort = SortMode::kMaterial;
  FilmImage again = RenderOnCpu(blend, o).image;
  EXPECT_EQ(std::memcmp(again.rgb.data(), half.rgb.data(), half.rgb.size() * sizeof(float)), 0);
}

// Head-on through smooth glass of ior 1.5 (Fresnel reflectance F = 0.04 exactly) in a white
// environment: a thin wall reflects F and transmits (1 - F) tint; a non-absorbing tinted cube
// sends everything that enters out again through two crossings (tint sqrt(c) each), so it
// shows F + (1 - F) c too; with absorption T = exp(-sigma 2) per traversal the internal
// reflections sum to F + (1 - F)^2 c T / (1 - F T).
TEST(GltfMaterialRender, TransmissionKeepsItsTintAndAbsorbs) {
  std::string dir = TempDir();
  SceneSpec spec;
  spec.size = 16;
  spec.spp = 16;
  spec.maxDepth = 12;
  const vec3 tint(1.0f, 0.2f, 0.5f);
  const double f = 0.04;
  struct Case {
    bool volume;
    float attenuation;
  };
  for (Case c : {Case{false, 1.0f}, Case{true, 1.0f}, Case{true, 0.5f}}) {
    Scene scene = TransmissionScene(dir, c.volume, tint, c.attenuation, spec);
    EXPECT_EQ(scene.desc.materials.back().type, MaterialType::kGltfPbr);  // tinted: not plain glass
    FilmImage img = RenderOnCpu(scene).image;
    double t = c.attenuation;  // attenuationColor at attenuationDistance 2 = the cube's depth
    for (int ch = 0; ch < 3; ++ch) {
      double want = c.attenuation < 1.0f ? f + (1 - f) * (1 - f) * tint[ch] * t / (1 - f * t)
                                         : f + (1 - f) * tint[ch];
      WindowMean w = MeanOverWindow(img, ch, 2, 2, 14, 14);
      // A z-test at 1e-4 per channel and case (the estimate is a mixture of lobe choices),
      // plus 1e-5 for the angles' spread around normal incidence.
      EXPECT_NEAR(w.mean, want, kZ1e4 * std::sqrt(w.varianceOfMean) + 1e-5)
          << (c.volume ? "volume" : "thin") << " attenuation " << c.attenuation << " channel " << ch;
    }
  }
}

// Smooth coat over a diffuse base of COLOR_0 c in a white environment, seen head-on: the coat
// reflects F = 0.04, the base (1 - F) c.
TEST(GltfMaterialRender, VertexColourMultipliesTheBaseColour) {
  std::string dir = TempDir();
  SceneSpec spec;
  spec.size = 16;
  spec.spp = 64;
  spec.maxDepth = 2;
  const vec4 color(0.5f, 0.25f, 1.0f, 1.0f);
  FilmImage img = RenderOnCpu(VertexColorScene(dir, color, spec)).image;
  for (int ch = 0; ch < 3; ++ch) {
    WindowMean w = MeanOverWindow(img, ch, 1, 1, 15, 15);
    double want = 0.04 + 0.96 * color[ch];
    // z-test, false-alarm probability 1e-4 per channel.
    EXPECT_NEAR(w.mean, want, kZ1e4 * std::sqrt(w.varianceOfMean) + 1e-5) << "channel " << ch;
  }
}

// 16 texels of a one-texel checker under each pixel: with one sample per pixel a bilinear
// lookup would read black or white; the mip level its footprint picks holds their mean (linear
// 0.5, stored as the sRGB code 188: 0.5029).
TEST(GltfMaterialRender, DistantCheckerIsFilteredNotAliased) {
  std::string dir = TempDir();
  SceneSpec spec;
  spec.size = 16;
  spec.spp = 1;
  Scene scene = DistantCheckerScene(dir, spec);
  EXPECT_EQ(scene.desc.textures[0].levels, 9u);
  FilmImage img = RenderOnCpu(scene).image;
  for (int y = 1; y < 15; ++y)
    for (int x = 1; x < 15; ++x)
      EXPECT_NEAR(img.rgb[3 * (size_t(y) * spec.size + x)], 0.5029f, 0.01f) << x << " " << y;
}

// The effect analysis names each feature, and only the general shade variant runs them; a glTF
// metal mapped to the plain conductor keeps its scene in the specialised variant.
TEST(GltfMaterialRender, EffectsNameTheFeaturesAndChooseTheVariant) {
  std::string dir = TempDir();
  SceneSpec spec;
  auto has = [](const Scene& s, const char* name) {
    std::vector<std::string> n = EffectNames(AnalyzeEffects(s));
    return std::find(n.begin(), n.end(), name) != n.end();
  };
  Scene normal = NormalMapScene(dir, 0, spec);
  for (const char* e : {"gltf_pbr", "normal_maps", "textures", "backface_culling"}) EXPECT_TRUE(has(normal, e)) << e;
  EXPECT_FALSE(has(normal, "alpha"));
  EXPECT_EQ(ChooseFeatureClass(AnalyzeEffects(normal)), FeatureClass::kGeneral);
  EXPECT_TRUE(has(EmissiveTextureScene(dir, false, spec), "emissive_textures"));
  EXPECT_TRUE(has(AlphaShadowScene(dir, "mask", spec), "alpha"));
  EXPECT_TRUE(has(AlphaShadowScene(dir, "blend", spec), "alpha"));
  Scene cube = TransmissionScene(dir, true, vec3(1, 0.5f, 0.5f), 0.5f, spec);  // tinted
  EXPECT_TRUE(has(cube, "transmission"));
  EXPECT_TRUE(has(cube, "absorption"));
  Scene mesh = BuildScene(LoadScene(SourcePath("scenes/mesh_scene.json")));  // a smooth gold glTF
  EXPECT_FALSE(has(mesh, "gltf_pbr"));
  EXPECT_NE(ChooseFeatureClass(AnalyzeEffects(mesh)), FeatureClass::kGeneral);
}

}  // namespace
}  // namespace pt::test
