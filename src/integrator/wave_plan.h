// How a render is cut into waves of paths that fit in memory at once.
#pragma once

#include <vector>

#include "src/integrator/render_api.h"
#include "src/integrator/wave.h"

namespace pt {

struct WavePlan {
  uint32_t cropX0 = 0, cropY0 = 0, cropWidth = 0, cropHeight = 0, cropPixels = 0;
  uint32_t spp = 0;
  uint32_t pathCapacity = 0;  // slots to allocate: the largest wave
  std::vector<WaveInfo> waves;
};

// Samples go in increasing order for every pixel: wave after wave, a pixel receives sample s
// before s + 1, which keeps the film sums in sample order.
WavePlan MakeWavePlan(const RenderSettings& render, const CropWindow& crop,
                      size_t defaultPathsInFlight, size_t requestedPathsInFlight);

FilmImage ResolveFilmImage(uint32_t width, uint32_t height, const std::vector<vec3>& sum,
                           const std::vector<vec3>& sumSquares,
                           const std::vector<uint32_t>& count);

}  // namespace pt
