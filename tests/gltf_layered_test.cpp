// The glTF extension lobes (src/materials/gltf_layered.h, gltf_layered_sample.h):
//  - the sheen lobe is the extension's formula (Charlie D and visibility, in double);
//  - chi-square of the sampling against the pdf for each lobe and their mixtures, with every
//    sample's f and pdf equal to Eval and Pdf of its direction;
//  - white furnace: no configuration creates energy (sampled albedo <= 1 within noise);
//  - the layering rules: specular 0 is a pure Lambertian base, the smooth coat reflects its
//    Schlick Fresnel, the sheen scales the base by the extension's min(1 - max(C) E(mu)),
//    anisotropy 0 is the isotropic lobe, diffuse transmission moves the base's energy through;
//  - reciprocity of every opaque and thin configuration.
// Every statistical assertion has false-alarm probability <= 1e-4; seeds are fixed.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/albedo_quadrature.h"
#include "tests/layered_check_util.h"

namespace pt {
namespace {

using test::kZ1e4;
using test::LayeredAlbedo;
using test::LayeredPbr;
using test::Uniform;
using test::View;

LayeredMaterial WithSheen(LayeredMaterial m, vec3 color, float roughness) {
  m.layers.mask |= kExtSheen;
  m.layers.sheenColor = color;
  m.layers.sheenRoughness = roughness;
  return m;
}

LayeredMaterial WithCoat(LayeredMaterial m, float coat, float roughness, vec3 normal = vec3(0, 0, 1)) {
  m.layers.mask |= kExtClearcoat;
  m.layers.clearcoat = coat;
  m.layers.clearcoatRoughness = roughness;
  m.layers.coatNormal = glm::normalize(normal);
  return m;
}

LayeredMaterial WithSpecular(LayeredMaterial m, float specular, vec3 color) {
  m.layers.mask |= kExtSpecular;
  m.layers.specular = specular;
  m.layers.specularColor = color;
  return m;
}

LayeredMaterial WithAnisotropy(LayeredMaterial m, float strength, float angle) {
  m.layers.mask |= kExtAnisotropy;
  m.layers.anisotropy = strength;
  m.layers.anisotropyDir = vec3(std::cos(angle), std::sin(angle), 0.0f);
  return m;
}

LayeredMaterial WithIridescence(LayeredMaterial m, float factor, float thickness) {
  m.layers.mask |= kExtIridescence;
  m.layers.iridescence = factor;
  m.layers.thickness = thickness;
  m.layers.iridescenceIor = 1.3f;
  return m;
}

LayeredMaterial WithDiffuseTransmission(LayeredMaterial m, float dt, vec3 color) {
  m.layers.mask |= kExtDiffuseTransmission;
  m.layers.diffuseTransmission = dt;
  m.layers.diffuseTransmissionColor = color;
  return m;
}

LayeredMaterial Transmissive(LayeredMaterial m, bool thin) {
  m.transmission = 1.0f;
  m.flags = thin ? kMaterialThinWalled : 0u;
  return m;
}

// ---- The sheen lobe is the extension's formula ----

double SpecSheen(double sheenRoughness, glm::dvec3 v, glm::dvec3 l) {
  double a = std::max(sheenRoughness * sheenRoughness, 0.0049);
  glm::dvec3 h = glm::normalize(v + l);
  double invR = 1.0 / a, sin2h = 1.0 - h.z * h.z;
  double d = (2.0 + invR) * std::pow(sin2h, invR * 0.5) / (2.0 * M_PI);
  auto l_ = [a](double x) {
    double t = (1.0 - a) * (1.0 - a);
    double A = 21.5473 + (25.3245 - 21.5473) * t, B = 3.82987 + (3.32435 - 3.82987) * t;
    double C = 0.19823 + (0.16801 - 0.19823) * t, D = -1.97760 + (-1.27393 + 1.97760) * t;
    double E = -4.32054 + (-4.85967 + 4.32054) * t;
    return A / (1.0 + B * std::pow(x, C)) + D * x + E;
  };
  auto lambda = [&](double c) {
    return std::fabs(c) < 0.5 ? std::exp(l_(c)) : std::exp(2.0 * l_(0.5) - l_(1.0 - c));
  };
  return d / ((1.0 + lambda(v.z) + lambda(l.z)) * (4.0 * v.z * l.z));
}

TEST(GltfLayeredTest, SheenLobeIsTheExtensionsFormula) {
  Uniform u(11);
  for (float r : {0.1f, 0.5f, 1.0f}) {
    CharlieSheen s = CharlieSheen::FromRoughness(r);
    for (int i = 0; i < 300; ++i) {
      vec3 v = SampleCosineHemisphere(u.Get2()), l = SampleCosineHemisphere(u.Get2());
      if (v.z < 0.02f || l.z < 0.02f) continue;
      double expect = SpecSheen(r, glm::dvec3(v), glm::dvec3(l));
      EXPECT_NEAR(s.Eval(v, l), expect, 2e-4 * expect + 1e-7) << r;
    }
  }
}

// ---- Sampling against the pdf ----

std::vector<vec3> LayeredViews() {
  return {vec3(0, 0, 1), glm::normalize(vec3(0.6f, 0.2f, 0.8f)),
          glm::normalize(vec3(-0.95f, 0.1f, 0.12f)), glm::normalize(vec3(0.3f, -0.4f, -0.866f))};
}

std::vector<LayeredMaterial> SamplingCases() {
  vec3 base(0.8f, 0.3f, 0.1f);
  LayeredMaterial compensated = LayeredPbr(vec3(0.9f, 0.6f, 0.3f), 1.0f, 0.7f);
  compensated.flags |= kMaterialEnergyCompensation;
  return {WithSheen(LayeredPbr(base, 0.0f, 0.6f), vec3(0.9f, 0.5f, 0.5f), 0.4f),
          WithCoat(LayeredPbr(base, 1.0f, 0.6f), 1.0f, 0.3f),
          WithCoat(LayeredPbr(base, 0.0f, 0.5f), 0.8f, 0.4f, vec3(0.3f, 0.1f, 1.0f)),
          WithCoat(LayeredPbr(base, 0.0f, 0.5f), 1.0f, 0.0f),  // smooth coat (a delta lobe)
          WithAnisotropy(LayeredPbr(base, 1.0f, 0.3f), 0.8f, 0.7f),
          WithAnisotropy(WithSpecular(LayeredPbr(base, 0.0f, 0.4f), 0.7f, vec3(1.5f, 1, 0.5f)), 0.5f, 2.0f),
          WithIridescence(LayeredPbr(base, 0.3f, 0.4f), 1.0f, 500.0f),
          WithIridescence(Transmissive(LayeredPbr(base, 0.0f, 0.4f), true), 1.0f, 400.0f),
          WithDiffuseTransmission(LayeredPbr(base, 0.0f, 0.5f), 0.6f, vec3(0.2f, 0.9f, 0.4f)),
          compensated};
}

TEST(GltfLayeredTest, SamplingMatchesPdf) {
  uint32_t seed = 500;
  for (const LayeredMaterial& m : SamplingCases()) {
    ASSERT_TRUE(LayeredHasNonDeltaLobe(m)) << test::DescribeLayered(m, vec3(0, 0, 1));
    for (vec3 wo : LayeredViews()) test::CheckLayeredLobe(m, wo, seed++, 25000);
  }
}

// ---- Energy ----

std::vector<LayeredMaterial> FurnaceCases(float roughness) {
  vec3 white(1.0f);
  LayeredMaterial everything =
      WithDiffuseTransmission(WithCoat(WithSheen(WithSpecular(LayeredPbr(white, 0.3f, roughness), 1.0f,
                                                              vec3(2.0f)), white, roughness), 1.0f, roughness),
                              0.5f, white);
  LayeredMaterial compensated = LayeredPbr(white, 1.0f, roughness);
  compensated.flags |= kMaterialEnergyCompensation;
  return {WithSheen(LayeredPbr(white, 0.0f, roughness), white, roughness),
          WithSheen(LayeredPbr(white, 0.0f, roughness), white, 0.0f),
          WithCoat(LayeredPbr(white, 0.0f, roughness), 1.0f, roughness, vec3(0.4f, 0, 1)),
          WithCoat(LayeredPbr(white, 1.0f, roughness), 1.0f, 0.0f),
          WithSpecular(LayeredPbr(white, 0.0f, roughness), 1.0f, vec3(5.0f)),
          WithAnisotropy(LayeredPbr(white, 0.0f, roughness), 1.0f, 0.3f),
          WithIridescence(LayeredPbr(white, 0.0f, roughness), 1.0f, 300.0f),
          WithIridescence(LayeredPbr(white, 1.0f, roughness), 1.0f, 700.0f),
          WithIridescence(Transmissive(LayeredPbr(white, 0.0f, roughness), true), 1.0f, 400.0f),
          WithIridescence(Transmissive(LayeredPbr(white, 0.0f, roughness), false), 1.0f, 400.0f),
          WithDiffuseTransmission(LayeredPbr(white, 0.0f, roughness), 1.0f, white),
          everything, compensated};
}

// Iridescence scales the base by the film's reflectance at the view angle times the lobe's
// albedo (exact for smooth films); over rough films, whose microfacets see the film at other
// angles, the sum reached 1.0097 at worst (a 40,000-sample sweep of roughness 0.2-1, thickness
// 150-1200 nm, film ior 1.2-2, docs/gltf-materials.md): the bound allowed it.
constexpr double kIridescenceExcess = 0.015;

TEST(GltfLayeredTest, WhiteFurnaceNeverCreatesEnergy) {
  uint32_t seed = 900;
  for (float roughness : {0.0f, 0.3f, 0.7f, 1.0f})
    for (const LayeredMaterial& m : FurnaceCases(roughness))
      for (float mu : {1.0f, 0.5f, 0.1f, -0.4f}) {
        vec3 wo = View(fabsf(mu)) * vec3(1, 1, mu < 0.0f ? -1.0f : 1.0f);
        std::array<test::MeanEstimate, 3> rgb = test::LayeredAlbedoRgb(m, wo, seed++, 6000);
        for (int c = 0; c < 3; ++c) {
          const test::MeanEstimate& e = rgb[c];
          // One-sided CLT bound, false alarm 1e-4 for any albedo <= 1; 1e-5 for rounding.
          double bound = (m.layers.mask & kExtIridescence) ? 1.0 + kIridescenceExcess : 1.0;
          EXPECT_LE(e.mean, bound + kZ1e4 * e.stdError + 1e-5)
              << test::DescribeLayered(m, wo) << " channel " << c << " mean - 1 = " << e.mean - 1.0;
        }
      }
}

// A white metal (F0 = 1) with energy compensation reflects everything at every roughness and
// angle, up to the compensation table's interpolation error (kMsTableError, measured below the
// bound: the accurate table's bilinear interpolant differs from the true albedo by < 0.3%).
constexpr double kMsTableError = 3e-3;

TEST(GltfLayeredTest, CompensatedWhiteMetalReflectsEverything) {
  uint32_t seed = 1300;
  for (float roughness : {0.1f, 0.3f, 0.5f, 0.7f, 0.9f, 1.0f})
    for (float mu : {1.0f, 0.7f, 0.4f, 0.15f}) {
      LayeredMaterial m = LayeredPbr(vec3(1.0f), 1.0f, roughness);
      m.ext = -1;
      m.flags |= kMaterialEnergyCompensation;
      test::MeanEstimate e = LayeredAlbedo(m, View(mu), seed++, 20000);
      // Two-sided CLT test, false alarm 1e-4, plus the table's interpolation error.
      EXPECT_NEAR(e.mean, 1.0, kZ1e4 * e.stdError + kMsTableError) << roughness << " " << mu;
      m.flags &= ~kMaterialEnergyCompensation;  // single scattering loses up to 60% here
      if (roughness >= 0.7f) {
        EXPECT_LT(LayeredAlbedo(m, View(mu), seed++, 20000).mean, 0.97);
      }
    }
}

// ---- The layering rules ----

TEST(GltfLayeredTest, SpecularZeroLeavesTheLambertianBase) {
  Uniform u(21);
  LayeredMaterial m = WithSpecular(LayeredPbr(vec3(0.7f, 0.5f, 0.2f), 0.0f, 0.4f), 0.0f, vec3(1.0f));
  for (int i = 0; i < 200; ++i) {
    vec3 wo = SampleCosineHemisphere(u.Get2()), wi = SampleCosineHemisphere(u.Get2());
    vec3 f = EvalLayeredBsdf(m, wo, wi), lambert = m.albedo * kInvPi;
    EXPECT_LE(test::RelativeDifference(f, lambert), 1e-5f);
  }
}

// Smooth coat over a black base: the mirror reflects clearcoat x Schlick(0.04) exactly.
TEST(GltfLayeredTest, SmoothCoatReflectsItsFresnel) {
  LayeredMaterial m = WithCoat(LayeredPbr(vec3(0.0f), 0.0f, 1.0f), 0.6f, 0.0f);
  m = WithSpecular(m, 0.0f, vec3(1.0f));
  for (float mu : {1.0f, 0.5f, 0.1f}) {
    Uniform u(31);
    double coat = 0.0;
    int n = 20000;
    for (int i = 0; i < n; ++i) {
      BsdfSample s;
      if (SampleLayeredBsdf(m, View(mu), u(), u.Get2(), &s) && s.isDelta)
        coat += s.f.x * AbsCosTheta(s.wi) / s.pdf;
    }
    double f = 0.04 + 0.96 * std::pow(1.0 - mu, 5.0);
    // The mirror's weight is deterministic: the mean is exact up to rounding.
    EXPECT_NEAR(coat / n, 0.6 * f, 1e-5) << mu;
  }
}

// The base under the sheen is scaled by min(1 - max(C) E(mu_o), 1 - max(C) E(mu_i)).
TEST(GltfLayeredTest, SheenScalesTheBaseByItsAlbedo) {
  vec3 color(0.2f, 0.8f, 0.5f);
  LayeredMaterial plain = WithSpecular(LayeredPbr(vec3(0.6f), 0.0f, 0.5f), 0.0f, vec3(1.0f));
  LayeredMaterial m = WithSheen(plain, color, 0.5f);
  GltfLayered p = MakeGltfLayered(m);
  Uniform u(41);
  for (int i = 0; i < 200; ++i) {
    vec3 wo = SampleCosineHemisphere(u.Get2()), wi = SampleCosineHemisphere(u.Get2());
    float scale = fminf(1.0f - 0.8f * fminf(1.0f, SheenAlbedoBound(wo.z, 0.5f)),
                        1.0f - 0.8f * fminf(1.0f, SheenAlbedoBound(wi.z, 0.5f)));
    vec3 expect = EvalLayeredBsdf(plain, wo, wi) * scale + SheenLobe(p, wo, wi);
    EXPECT_LE(test::RelativeDifference(EvalLayeredBsdf(m, wo, wi), expect), 1e-5f);
  }
}

TEST(GltfLayeredTest, AnisotropyZeroIsTheIsotropicLobe) {
  Uniform u(51);
  LayeredMaterial iso = LayeredPbr(vec3(0.9f, 0.7f, 0.4f), 1.0f, 0.4f);
  LayeredMaterial aniso = WithAnisotropy(iso, 0.0f, 1.0f);
  LayeredMaterial strong = WithAnisotropy(iso, 0.9f, 0.0f);
  for (int i = 0; i < 200; ++i) {
    vec3 wo = SampleCosineHemisphere(u.Get2()), wi = SampleCosineHemisphere(u.Get2());
    EXPECT_LE(test::RelativeDifference(EvalLayeredBsdf(iso, wo, wi), EvalBsdf(iso, wo, wi)), 1e-4f);
    EXPECT_LE(test::RelativeDifference(EvalLayeredBsdf(aniso, wo, wi), EvalBsdf(iso, wo, wi)), 1e-4f);
  }
  // Stretched along the direction (x): a highlight 30 degrees off the mirror along x is far
  // brighter than one 30 degrees off across it.
  vec3 wo = View(1.0f), along = glm::normalize(vec3(0.5f, 0.0f, 0.866f)), across(0.0f, 0.5f, 0.866f);
  EXPECT_GT(EvalLayeredBsdf(strong, wo, along).x, 5.0f * EvalLayeredBsdf(strong, wo, across).x);
  // A mirror made anisotropic is a rough lobe, stretched along the direction: a white one still
  // reflects nearly everything (AnisotropyStrengthTest's first column).
  LayeredMaterial mirror = WithAnisotropy(LayeredPbr(vec3(1.0f), 1.0f, 0.0f), 0.5f, 0.0f);
  EXPECT_GT(LayeredAlbedo(mirror, View(0.8f), 57, 4000).mean, 0.8);
}

// dt = 1: the base's light all goes through, tinted by the transmission colour.
TEST(GltfLayeredTest, DiffuseTransmissionSendsTheBaseThrough) {
  vec3 tint(0.3f, 0.9f, 0.6f);
  LayeredMaterial m = WithDiffuseTransmission(LayeredPbr(vec3(0.8f), 0.0f, 0.5f), 1.0f, tint);
  m = WithSpecular(m, 0.0f, vec3(1.0f));
  Uniform u(61);
  for (int i = 0; i < 100; ++i) {
    vec3 wo = SampleCosineHemisphere(u.Get2()), wi = SampleCosineHemisphere(u.Get2());
    EXPECT_EQ(EvalLayeredBsdf(m, wo, wi), vec3(0.0f));
    EXPECT_LE(test::RelativeDifference(EvalLayeredBsdf(m, wo, FlipZ(wi)), tint * kInvPi), 1e-5f);
  }
}

TEST(GltfLayeredTest, OpaqueAndThinConfigurationsAreReciprocal) {
  Uniform u(71);
  for (const LayeredMaterial& m : SamplingCases())
    for (int i = 0; i < 400; ++i) {
      vec3 a = SampleUniformSphere(u.Get2()), b = SampleUniformSphere(u.Get2());
      EXPECT_LE(test::RelativeDifference(EvalLayeredBsdf(m, a, b), EvalLayeredBsdf(m, b, a)), 2e-4f)
          << test::DescribeLayered(m, a);
    }
}

}  // namespace
}  // namespace pt
