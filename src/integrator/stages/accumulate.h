// Stage 7, accumulate: each pixel adds its finished samples of this wave to the film, in
// sample order. Non-finite samples are counted and dropped (the non-finite firewall). With a
// firefly clamp, a sample brighter than the clamp luminance is scaled down to it (hue kept):
// biased, but it tames rare very bright paths. With the half films it also keeps each sample
// less the emission its camera ray saw (film.h, FilmView::residualMean).
#pragma once

#include "src/integrator/film.h"
#include "src/integrator/path_state.h"
#include "src/integrator/wave.h"

namespace pt {

// kHalves: the film keeps the half films (film.evenSum), a compile-time choice so that a
// render without them runs none of their code (their residual statistics cost ~25% of the
// stage when tested at run time).
template <bool kHalves>
PT_HDI void AccumulatePixel(const WaveInfo& wave, PathState ps, FilmView film,
                            uint32_t localPixel, Counter* counters,
                            float clampLuminance = 0.0f) {
  uint32_t pixel = wave.FilmPixelOf(localPixel);
  uint32_t n = film.sampleCount[pixel];
  float lumMean = film.lumMean[pixel], lumM2 = film.lumM2[pixel];
  vec3 mean = film.mean ? film.mean[pixel] : vec3(0.0f);
  vec3 m2 = film.mean ? film.m2[pixel] : vec3(0.0f);
  glm::dvec3 meanD = film.meanDouble ? film.meanDouble[pixel] : glm::dvec3(0.0);
  glm::dvec3 m2D = film.meanDouble ? film.m2Double[pixel] : glm::dvec3(0.0);
  vec3 evenSum = kHalves ? film.evenSum[pixel] : vec3(0.0f);
  uint32_t evenCount = kHalves ? film.evenCount[pixel] : 0u;
  vec3 residualMean = kHalves ? film.residualMean[pixel] : vec3(0.0f);
  vec3 residualM2 = kHalves ? film.residualM2[pixel] : vec3(0.0f);
  vec3 evenEmission = kHalves ? film.evenEmissionSum[pixel] : vec3(0.0f);
  uint32_t nonfinite = 0;
  for (uint32_t s = 0; s < wave.samplesInWave; ++s) {
    uint32_t id = s * wave.pixelCount + localPixel;
    vec3 l = ps.radiance[id];
    // The emission its camera ray saw (the half films' residual is l less it).
    vec3 e = kHalves && film.albedoSum ? ps.featureEmission[id] : vec3(0.0f);
    if (!IsFinite(l)) {
      ++nonfinite;
      l = e = vec3(0.0f);
    }
    if (!IsFinite(e)) e = vec3(0.0f);
    float y = Luminance(l);
    if (clampLuminance > 0.0f && y > clampLuminance) {
      l *= clampLuminance / y;
      e *= clampLuminance / y;
    }
    ++n;
    if (film.meanDouble) WelfordAdd(meanD, m2D, glm::dvec3(l), double(n));
    else WelfordAdd(mean, m2, l, float(n));
    WelfordAdd(lumMean, lumM2, Luminance(l), float(n));
    // The half film of even sample indices (global ones: chunks and resumes agree).
    if constexpr (kHalves) {
      WelfordAdd(residualMean, residualM2, l - e, float(n));
      if (((wave.sampleStart + s) & 1u) == 0u) {
        evenSum += l;
        evenEmission += e;
        ++evenCount;
      }
    }
    if (film.albedoSum) {
      film.albedoSum[pixel] += ps.featureAlbedo[id];
      film.normalSum[pixel] += ps.featureNormal[id];
      film.depthSum[pixel] += fabsf(ps.featureDepth[id]);  // negative: pending (shade.h)
    }
  }
  if (film.meanDouble) {
    film.meanDouble[pixel] = meanD;
    film.m2Double[pixel] = m2D;
  } else {
    film.mean[pixel] = mean;
    film.m2[pixel] = m2;
  }
  film.lumMean[pixel] = lumMean;
  film.lumM2[pixel] = lumM2;
  film.sampleCount[pixel] = n;
  if constexpr (kHalves) {
    film.evenSum[pixel] = evenSum;
    film.evenCount[pixel] = evenCount;
    film.residualMean[pixel] = residualMean;
    film.residualM2[pixel] = residualM2;
    film.evenEmissionSum[pixel] = evenEmission;
  }
  if (nonfinite && counters) AddToCounter(&counters[kCounterNonfinite], nonfinite);
}

}  // namespace pt
