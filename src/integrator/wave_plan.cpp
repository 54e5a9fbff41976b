#include "src/integrator/wave_plan.h"

#include <algorithm>

namespace pt {

WavePlan MakeWavePlan(const RenderSettings& render, const CropWindow& crop,
                      size_t defaultPathsInFlight, size_t requestedPathsInFlight) {
  WavePlan plan;
  CropWindow c = crop.Empty() ? CropWindow{0, 0, render.width, render.height} : crop;
  plan.cropX0 = uint32_t(c.x0);
  plan.cropY0 = uint32_t(c.y0);
  plan.cropWidth = uint32_t(c.x1 - c.x0);
  plan.cropHeight = uint32_t(c.y1 - c.y0);
  plan.cropPixels = plan.cropWidth * plan.cropHeight;
  plan.spp = uint32_t(render.spp);

  size_t maxPaths = requestedPathsInFlight ? requestedPathsInFlight : defaultPathsInFlight;
  maxPaths = std::max<size_t>(maxPaths, 1);
  uint32_t tile = uint32_t(std::min<size_t>(plan.cropPixels, maxPaths));
  uint32_t samplesPerWave = 1;
  if (tile == plan.cropPixels)
    samplesPerWave = uint32_t(std::clamp<size_t>(maxPaths / plan.cropPixels, 1, plan.spp));

  WaveInfo base{};
  base.cropX0 = plan.cropX0;
  base.cropY0 = plan.cropY0;
  base.cropWidth = plan.cropWidth;
  base.imageWidth = uint32_t(render.width);
  base.imageHeight = uint32_t(render.height);
  base.seed = render.seed;
  for (uint32_t s = 0; s < plan.spp; s += samplesPerWave) {
    for (uint32_t p = 0; p < plan.cropPixels; p += tile) {
      WaveInfo w = base;
      w.pixelStart = p;
      w.pixelCount = std::min(tile, plan.cropPixels - p);
      w.sampleStart = s;
      w.samplesInWave = std::min(samplesPerWave, plan.spp - s);
      plan.pathCapacity = std::max(plan.pathCapacity, w.PathCount());
      plan.waves.push_back(w);
    }
  }
  return plan;
}

FilmImage ResolveFilmImage(uint32_t width, uint32_t height, const std::vector<vec3>& sum,
                           const std::vector<vec3>& sumSquares,
                           const std::vector<uint32_t>& count) {
  FilmImage img;
  img.width = int(width);
  img.height = int(height);
  size_t n = size_t(width) * height;
  img.rgb.assign(3 * n, 0.0f);
  img.variance.assign(3 * n, 0.0f);
  img.samples = count;
  for (size_t i = 0; i < n; ++i) {
    if (count[i] == 0) continue;
    double k = count[i];
    for (int c = 0; c < 3; ++c) {
      double mean = sum[i][c] / k;
      img.rgb[3 * i + c] = float(mean);
      // Unbiased sample variance of the pixel's samples.
      double var = k > 1 ? (sumSquares[i][c] - k * mean * mean) / (k - 1) : 0.0;
      img.variance[3 * i + c] = float(std::max(0.0, var));
    }
  }
  return img;
}

}  // namespace pt
