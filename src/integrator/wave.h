// A wave: the set of paths in flight at once, samplesInWave consecutive samples of a range of
// pixels of the crop window. Path slot id -> (pixel, sample) is pure arithmetic.
#pragma once

#include "src/core/math.h"
#include "src/core/rng.h"

namespace pt {

enum class IntegratorKind : uint32_t { kMis = 0, kBsdf = 1, kNee = 2 };

struct WaveInfo {
  const uint32_t* pixelList;  // adaptive sampling: the wave's pixels; null = contiguous range
  uint32_t pixelStart;      // first pixel of the crop window in this wave (crop-linear index)
  uint32_t pixelCount;      // pixels in this wave
  uint32_t sampleStart;     // sample index of the wave's first sample
  uint32_t samplesInWave;
  uint32_t cropX0, cropY0, cropWidth;
  uint32_t imageWidth, imageHeight;
  uint32_t seed;
  SamplerKind sampler;      // --sampler: what the paths' keys draw

  PT_HDI uint32_t PathCount() const { return pixelCount * samplesInWave; }
  // Neighbouring slots are neighbouring pixels: coherent camera rays in a warp.
  PT_HDI uint32_t FilmPixelOf(uint32_t localPixel) const {
    return pixelList ? pixelList[localPixel] : pixelStart + localPixel;
  }
  PT_HDI uint32_t CropPixelOf(uint32_t id) const { return FilmPixelOf(id % pixelCount); }
  PT_HDI uint32_t SampleOf(uint32_t id) const { return sampleStart + id / pixelCount; }
  PT_HDI uint32_t ImageX(uint32_t cropPixel) const { return cropX0 + cropPixel % cropWidth; }
  PT_HDI uint32_t ImageY(uint32_t cropPixel) const { return cropY0 + cropPixel / cropWidth; }
  // The random stream of a path is keyed on the image pixel, so a crop renders the same
  // pixels as the full image.
  PT_HDI RngKey KeyOf(uint32_t id) const {
    uint32_t p = CropPixelOf(id);
    return RngKey{ImageY(p) * imageWidth + ImageX(p), SampleOf(id), seed, sampler};
  }
};

struct IntegratorParams {
  int maxDepth;
  int rrDepth;
  IntegratorKind kind;
  uint32_t minBounces, maxBounces;  // light paths counted (--light-paths)
  float rayOffsetEpsilon;           // 0: robust error-bound offsets
  uint32_t featureBuffers;          // write first-hit albedo, normal, depth
  float clampLuminance;             // > 0: the firefly clamp of each sample (accumulate)

  // Light that reached the camera after this many bounces is counted.
  PT_HDI bool Counts(uint32_t bounces) const {
    return bounces >= minBounces && bounces <= maxBounces;
  }
};

}  // namespace pt
