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
  size_t maxPaths = 0;
  WaveInfo base{};            // what every wave shares (crop, image size, seed, sampler)
};

// Samples go in increasing order for every pixel: wave after wave, a pixel receives sample s
// before s + 1, which keeps the film sums in sample order.
WavePlan MakeWavePlan(const RenderSettings& render, const CropWindow& crop,
                      size_t defaultPathsInFlight, size_t requestedPathsInFlight);

// Waves giving `sampleCount` samples from `sampleStart` on to `pixelCount` pixels (the first
// pixelCount entries of pixelList, or a contiguous range from 0 when it is null), at most
// maxPaths paths each, every pixel's samples in increasing order.
void AppendWaves(const WaveInfo& base, const uint32_t* pixelList, uint32_t pixelCount,
                 uint32_t sampleStart, uint32_t sampleCount, size_t maxPaths,
                 std::vector<WaveInfo>& waves);

// The film as an image. Feature sums may be empty (not requested).
FilmImage ResolveFilmImage(const FilmState& film);

}  // namespace pt
