// Stage 7, accumulate: each pixel adds its finished samples of this wave to the film, in
// sample order. Non-finite samples are counted and dropped (the non-finite firewall).
#pragma once

#include "src/integrator/film.h"
#include "src/integrator/path_state.h"
#include "src/integrator/wave.h"

namespace pt {

PT_HDI void AccumulatePixel(const WaveInfo& wave, PathState ps, FilmView film,
                            uint32_t localPixel, Counter* counters) {
  uint32_t filmPixel = wave.pixelStart + localPixel;
  vec3 sum = film.sum[filmPixel];
  vec3 sumSquares = film.sumSquares[filmPixel];
  uint32_t nonfinite = 0;
  for (uint32_t s = 0; s < wave.samplesInWave; ++s) {
    vec3 l = ps.radiance[s * wave.pixelCount + localPixel];
    if (!IsFinite(l)) {
      ++nonfinite;
      l = vec3(0.0f);
    }
    sum += l;
    sumSquares += l * l;
  }
  film.sum[filmPixel] = sum;
  film.sumSquares[filmPixel] = sumSquares;
  film.sampleCount[filmPixel] += wave.samplesInWave;
  if (nonfinite && counters) AddToCounter(&counters[kCounterNonfinite], nonfinite);
}

}  // namespace pt
