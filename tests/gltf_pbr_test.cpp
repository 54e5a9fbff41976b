// The glTF metallic-roughness BSDF (src/materials/gltf_pbr.h):
//  - the metal lobe is the specification's conductor_fresnel(baseColor, specular_brdf) in
//    closed form, and metallic 1 / an untinted full-transmission volume equal the plain
//    conductor / dielectric they are mapped to;
//  - the coat-albedo table bounds the albedo from above at points between its nodes, and its
//    averages are the integrals of its interpolant (so the diffuse base's normalisation holds);
//  - white furnace: energy is never created, opaque (quadrature of EvalBsdf and the mean of
//    SampleBsdf's weights agree) and transmissive (sampled). What is lost: a metal loses the
//    single-scattering GGX loss of tests/white_furnace_test.cpp (up to 69% at roughness 1,
//    normal incidence); the coated diffuse loses only the table's upper-bound margin, because
//    the base receives whatever the coat's single scattering does not reflect (its albedo
//    1 - E includes what the coat's microfacets shadow). White base colour, metallic 0,
//    ior 1.5, by quadrature:
//      roughness      0 (smooth)   0.3       0.6       1.0
//      E(mu = 1)      1.00000      0.99955   0.99995   1.00000
//      E(mu = 0.5)    1.00000      0.99919   0.99993   0.99999
//      E(mu = 0.1)    1.00000      0.99890   0.99962   0.99985
//  - chi-square of its sampling against its pdf on both sides, every sample's f and pdf equal
//    to EvalBsdf and PdfBsdf of its direction; reciprocity of the opaque and thin-walled lobes.
//
// Every statistical assertion has false-alarm probability <= 1e-4 (stated at each); seeds are
// fixed, so a run is reproducible.
#include <gtest/gtest.h>

#include <sstream>

#include "src/materials/bsdf.h"
#include "tests/albedo_quadrature.h"
#include "tests/bsdf_check_util.h"
#include "tests/stat_test_util.h"

namespace pt {
namespace {

using test::kZ1e4;
using test::SampledAlbedo;
using test::View;
using test::Uniform;

Material Pbr(vec3 base, float metallic, float roughness, float ior = 1.5f,
             float transmission = 0.0f, bool thin = true) {
  Material m;
  m.type = MaterialType::kGltfPbr;
  m.albedo = base;
  m.metallic = metallic;
  m.roughness = roughness;
  m.ior = ior;
  m.transmission = transmission;
  m.flags = thin ? kMaterialThinWalled : 0u;
  return m;
}

std::string Describe(const Material& m, vec3 wo) {
  std::ostringstream s;
  s << "metallic " << m.metallic << " roughness " << m.roughness << " ior " << m.ior
    << " transmission " << m.transmission << (m.flags & kMaterialThinWalled ? " thin" : " volume")
    << " wo (" << wo.x << ", " << wo.y << ", " << wo.z << ")";
  return s.str();
}

// ---- The specification's metal lobe, and the exact plain mappings ----

// conductor_fresnel(f0 = baseColor, specular_brdf(alpha)) of appendix B in double:
// (f0 + (1 - f0)(1 - |V.H|)^5) D V with D the Trowbridge-Reitz distribution and V the
// height-correlated Smith visibility G2 / (4 |N.L| |N.V|).
glm::dvec3 SpecMetal(glm::dvec3 c, double alpha, glm::dvec3 v, glm::dvec3 l) {
  glm::dvec3 h = glm::normalize(v + l);
  double a2 = alpha * alpha, nh = h.z, nv = v.z, nl = l.z;
  double d = a2 / (M_PI * std::pow(nh * nh * (a2 - 1.0) + 1.0, 2));
  double lv = std::sqrt(nl * nl * (1 - a2) + a2), ll = std::sqrt(nv * nv * (1 - a2) + a2);
  double vis = 0.5 / (nl * ll + nv * lv);  // Heitz's height-correlated form, as the spec
  return (c + (glm::dvec3(1.0) - c) * std::pow(1.0 - std::fabs(glm::dot(v, h)), 5)) * d * vis;
}

TEST(GltfPbrTest, MetalLobeIsTheSpecificationsFormula) {
  Uniform u(3);
  glm::dvec3 c(0.95, 0.64, 0.54);
  for (float roughness : {0.2f, 0.5f, 1.0f}) {
    Material m = Pbr(vec3(c), 1.0f, roughness);
    for (int i = 0; i < 200; ++i) {
      vec3 wo = SampleCosineHemisphere(u.Get2()), wi = SampleCosineHemisphere(u.Get2());
      if (wo.z < 0.05f || wi.z < 0.05f) continue;
      glm::dvec3 want = SpecMetal(c, GgxAlpha(roughness), glm::dvec3(wo), glm::dvec3(wi));
      vec3 got = EvalBsdf(m, wo, wi);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 1e-4 * want[k] + 1e-7);
    }
  }
}

TEST(GltfPbrTest, ExactMappingsEqualThePlainMaterials) {
  Uniform u(4);
  Material metal = Pbr(vec3(0.9f, 0.6f, 0.3f), 1.0f, 0.4f), conductor = metal;
  conductor.type = MaterialType::kConductor;
  Material clear = Pbr(vec3(1.0f), 0.0f, 0.4f, 1.5f, 1.0f, false), glass = clear;
  glass.type = MaterialType::kDielectric;
  for (int i = 0; i < 500; ++i) {
    vec3 wo = SampleUniformSphere(u.Get2()), wi = SampleUniformSphere(u.Get2());
    for (auto [a, b] : {std::pair{metal, conductor}, {clear, glass}}) {
      EXPECT_LE(test::RelativeDifference(EvalBsdf(a, wo, wi), EvalBsdf(b, wo, wi)), 1e-5f);
      float pa = PdfBsdf(a, wo, wi), pb = PdfBsdf(b, wo, wi);
      EXPECT_NEAR(pa, pb, 1e-5f * std::max(pa, pb));
    }
  }
}

// ---- The coat albedo table ----

// At points between the table's nodes, the interpolated albedo is at least the albedo of a
// Schlick-F0 GGX lobe by quadrature (a conductor of albedo F0 is exactly that lobe), and not
// more than 0.02 above it.
TEST(GltfPbrTest, CoatAlbedoTableBoundsTheAlbedoFromAbove) {
  for (float roughness : {0.11f, 0.23f, 0.5f, 0.77f, 1.0f})
    for (float f0 : {0.0f, 0.04f, 0.2f, 1.0f})
      for (float mu : {0.03f, 0.13f, 0.4f, 0.71f, 0.97f}) {
        Material lobe;
        lobe.type = MaterialType::kConductor;
        lobe.albedo = vec3(f0);
        lobe.roughness = roughness;
        test::Albedo q = test::QuadratureAlbedo(lobe, View(mu), GgxAlpha(roughness));
        float table = CoatAlbedo{f0, roughness, false}.At(mu);
        EXPECT_GE(table, q.value - q.error - 1e-6) << roughness << " " << f0 << " " << mu;
        EXPECT_LE(table, q.value + 0.02) << roughness << " " << f0 << " " << mu;
      }
}

// Average() is 2 * integral of At(mu) mu: Simpson's rule with 2^16 intervals (the interpolant
// is piecewise linear in mu, so only the kinks at nodes limit it, far below the tolerance).
TEST(GltfPbrTest, CoatAlbedoAverageIsTheInterpolantsIntegral) {
  for (float roughness : {0.0f, 0.2f, 0.45f, 0.8f, 1.0f})
    for (float f0 : {0.0f, 0.04f, 0.5f, 1.0f})
      for (bool smooth : {false, true}) {
        CoatAlbedo coat{f0, roughness, smooth};
        const int n = 1 << 16;
        double sum = 0.0;
        for (int i = 0; i <= n; ++i) {
          double mu = double(i) / n;
          sum += (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2)) * coat.At(float(mu)) * mu;
        }
        EXPECT_NEAR(2.0 * sum / (3.0 * n), coat.Average(), 2e-6) << roughness << " " << f0;
      }
}

// ---- White furnace ----

TEST(GltfPbrTest, OpaqueWhiteFurnaceNeverCreatesEnergy) {
  uint32_t seed = 10;
  for (float metallic : {0.0f, 0.5f, 1.0f})
    for (float roughness : {0.0f, 0.3f, 0.6f, 1.0f})
      for (float ior : {1.5f, 2.0f})
        for (float mu : {1.0f, 0.5f, 0.1f}) {
          Material m = Pbr(vec3(1.0f), metallic, roughness, ior);
          bool smooth = IsSmooth(m);
          // Smooth: the delta lobe reflects Schlick's F(mu) exactly; quadrature sees the rest.
          double delta = smooth ? GltfSpecularFresnel(MakeGltfPbr(m), mu).x : 0.0;
          test::Albedo q = test::QuadratureAlbedo(m, View(mu), smooth ? 1.0 : GgxAlpha(roughness));
          double total = delta + q.value;
          std::string what = Describe(m, View(mu));
          EXPECT_LT(q.error, 1e-4) << what;
          // + 1e-6: float rounding of weights that are exactly 1 in real arithmetic.
          EXPECT_LE(total, 1.0 + q.error + 1e-6) << what << " total - 1 = " << total - 1.0;
          if (smooth && metallic == 0.0f) {
            EXPECT_NEAR(total, 1.0, 2e-5 + q.error) << what;  // F + (1 - F), exactly
          }
          for (float side : {1.0f, -1.0f}) {  // two-sided: the back mirrors the front
            test::MeanEstimate e = SampledAlbedo(m, View(mu) * vec3(1, 1, side), seed++, 20000);
            // Two-sided CLT test of the sampled weights against the quadrature: 1e-4.
            EXPECT_NEAR(e.mean, total, kZ1e4 * e.stdError + q.error) << what << " side " << side;
          }
        }
}

// The diffuse base alone (the full lobe minus its coat, a conductor of albedo F0) reflects
// exactly base (1 - E(mu)), E the table's coat albedo: the normalisation by 1 - E_avg holds.
TEST(GltfPbrTest, DiffuseBaseReflectsWhatTheCoatLeaves) {
  for (float roughness : {0.3f, 0.7f}) {
    Material m = Pbr(vec3(1.0f), 0.0f, roughness);
    Material coat;
    coat.type = MaterialType::kConductor;
    coat.albedo = vec3(0.04f);
    coat.roughness = roughness;
    for (float mu : {0.9f, 0.5f, 0.2f}) {
      test::Albedo all = test::QuadratureAlbedo(m, View(mu), GgxAlpha(roughness));
      test::Albedo spec = test::QuadratureAlbedo(coat, View(mu), GgxAlpha(roughness));
      double expected = 1.0 - CoatAlbedo{0.04f, roughness, false}.At(mu);
      EXPECT_NEAR(all.value - spec.value, expected, 1e-4 + all.error + spec.error)
          << roughness << " " << mu;
    }
  }
}

TEST(GltfPbrTest, TransmissiveWhiteFurnaceNeverCreatesEnergy) {
  uint32_t seed = 100;
  for (bool thin : {true, false})
    for (float roughness : {0.0f, 0.3f, 0.7f})
      for (float transmission : {0.5f, 1.0f})
        for (float mu : {1.0f, 0.6f, 0.15f, -0.9f, -0.3f}) {  // outside, then inside
          Material m = Pbr(vec3(1.0f), 0.2f, roughness, 1.5f, transmission, thin);
          vec3 wo = View(fabsf(mu)) * vec3(1, 1, mu < 0.0f ? -1.0f : 1.0f);
          test::MeanEstimate e = SampledAlbedo(m, wo, seed++, 20000);
          // One-sided CLT bound: P(mean > E + z sigma / sqrt(n)) < 1e-4 for any E <= 1; + 1e-6
          // for float rounding of weights that are exactly 1 in real arithmetic (smooth glass).
          EXPECT_LE(e.mean, 1.0 + kZ1e4 * e.stdError + 1e-6)
              << Describe(m, wo) << " mean - 1 = " << e.mean - 1.0;
        }
}

// ---- Sampling against the pdf ----

std::vector<vec3> PbrViews() {
  return {vec3(0, 0, 1), glm::normalize(vec3(0.6f, 0.0f, 0.8f)),
          glm::normalize(vec3(-0.95f, 0.1f, 0.1f)), glm::normalize(vec3(0.3f, -0.4f, -0.866f))};
}

TEST(GltfPbrTest, SamplingMatchesPdf) {
  vec3 base(0.8f, 0.3f, 0.1f);
  const Material cases[] = {
      Pbr(base, 0.0f, 0.3f),       Pbr(base, 0.0f, 0.8f),  Pbr(base, 0.4f, 0.5f),
      Pbr(base, 0.0f, 0.0f),       // smooth coat (a delta lobe) over the diffuse base
      Pbr(base, 0.0f, 0.5f, 1.5f, 1.0f, true),  Pbr(base, 0.2f, 0.3f, 1.33f, 0.5f, true),
      Pbr(base, 0.0f, 0.4f, 1.5f, 0.6f, false), Pbr(base, 0.0f, 0.6f, 2.0f, 1.0f, false)};
  uint32_t seed = 300;
  for (const Material& m : cases) {
    ASSERT_TRUE(HasNonDeltaLobe(m));
    for (vec3 wo : PbrViews()) test::CheckLobe(m, wo, seed++, 100000);
  }
}

// Reciprocity f(wo, wi) = f(wi, wo) holds for the opaque lobes and thin walls; a volume's
// refraction is not symmetric (radiance scales by 1 / eta^2 entering the denser side).
TEST(GltfPbrTest, OpaqueAndThinLobesAreReciprocal) {
  Uniform u(7);
  for (const Material& m : {Pbr(vec3(0.9f, 0.6f, 0.3f), 0.3f, 0.5f),
                            Pbr(vec3(0.9f, 0.6f, 0.3f), 0.0f, 0.4f, 1.5f, 0.7f, true)}) {
    for (int i = 0; i < 2000; ++i) {
      vec3 a = SampleUniformSphere(u.Get2()), b = SampleUniformSphere(u.Get2());
      EXPECT_LE(test::RelativeDifference(EvalBsdf(m, a, b), EvalBsdf(m, b, a)), 1e-4f)
          << Describe(m, a);
    }
  }
}

}  // namespace
}  // namespace pt
