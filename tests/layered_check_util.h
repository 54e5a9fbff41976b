// Checks of the layered glTF BSDF (src/materials/gltf_layered_sample.h) with the harness of
// tests/bsdf_check_util.h: chi-square of SampleLayeredBsdf against PdfLayeredBsdf with every
// sample's f and pdf equal to the mixture's Eval and Pdf of its direction, and the sampled
// albedo (the mean path weight, delta lobes included).
#pragma once

#include <array>
#include <sstream>
#include <string>

#include "src/materials/gltf_layered_sample.h"
#include "tests/bsdf_check_util.h"

namespace pt::test {

inline LayeredMaterial LayeredPbr(vec3 base, float metallic, float roughness) {
  LayeredMaterial m;
  m.type = MaterialType::kGltfPbr;
  m.albedo = base;
  m.metallic = metallic;
  m.roughness = roughness;
  m.flags = kMaterialThinWalled;
  m.ext = 0;  // any entry: the layers are given directly
  return m;
}

inline std::string DescribeLayered(const LayeredMaterial& m, vec3 wo) {
  const GltfLayers& x = m.layers;
  std::ostringstream s;
  s << "metallic " << m.metallic << " roughness " << m.roughness << " mask " << x.mask
    << " specular " << x.specular << " coat " << x.clearcoat << "/" << x.clearcoatRoughness
    << " sheen " << x.sheenColor.x << "/" << x.sheenRoughness << " irid " << x.iridescence
    << " aniso " << x.anisotropy << " dt " << x.diffuseTransmission << " flags " << m.flags
    << " wo (" << wo.x << ", " << wo.y << ", " << wo.z << ")";
  return s.str();
}

inline void CheckLayeredLobe(const LayeredMaterial& m, vec3 wo, uint32_t seed, int64_t n,
                             const ChiSquareGrid& grid = ChiSquareGrid{}) {
  Uniform u(seed);
  int samples = 0, mismatches = 0;
  float worst = 0.0f;
  auto sample = [&](vec3* w) {
    BsdfSample s;
    if (!SampleLayeredBsdf(m, wo, u(), u.Get2(), &s) || s.isDelta) return false;
    EXPECT_EQ(s.isTransmission, s.wi.z * wo.z < 0.0f);
    vec3 f = EvalLayeredBsdf(m, wo, s.wi);
    float pdf = PdfLayeredBsdf(m, wo, s.wi);
    vec3 weight = s.f * (AbsCosTheta(s.wi) / s.pdf);
    vec3 expect = pdf > 0.0f ? f * (AbsCosTheta(s.wi) / pdf) : vec3(-1.0f);
    float d = RelativeDifference(weight, expect);
    worst = std::max(worst, d);
    ++samples;
    if (d > kWeightConsistency) ++mismatches;
    *w = s.wi;
    return true;
  };
  auto pdf = [&](vec3 w) { return double(PdfLayeredBsdf(m, wo, w)); };
  ChiSquareResult r = ChiSquareAccurate(sample, pdf, n, grid);
  std::string what = DescribeLayered(m, wo);
  EXPECT_GT(r.pValue, kChiSquareAlpha) << what << ": " << r.message;  // false alarm 1e-4
  EXPECT_EQ(mismatches, 0) << what << ": worst relative weight difference " << worst;
  EXPECT_GT(samples, 0) << what;
}

// Mean path weight f |cos| / pdf per channel (delta lobes included; refraction's 1 / eta^2
// undone, so the mean is the energy reflected and transmitted).
inline std::array<MeanEstimate, 3> LayeredAlbedoRgb(const LayeredMaterial& m, vec3 wo,
                                                    uint32_t seed, int n) {
  Uniform u(seed);
  MeanAccumulator acc[3];
  for (int i = 0; i < n; ++i) {
    BsdfSample s;
    vec3 w(0.0f);
    if (SampleLayeredBsdf(m, wo, u(), u.Get2(), &s)) {
      w = s.f * (AbsCosTheta(s.wi) / s.pdf);
      if (s.isTransmission) w *= s.eta * s.eta;
    }
    for (int c = 0; c < 3; ++c) acc[c].Add(w[c]);
  }
  return {acc[0].Result(), acc[1].Result(), acc[2].Result()};
}

inline MeanEstimate LayeredAlbedo(const LayeredMaterial& m, vec3 wo, uint32_t seed, int n) {
  return LayeredAlbedoRgb(m, wo, seed, n)[0];
}

}  // namespace pt::test
