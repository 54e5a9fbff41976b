#include "src/denoise/denoiser.h"

namespace pt {

std::string DenoiseInputProblem(const FilmImage& image) {
  size_t n = size_t(std::max(image.width, 0)) * size_t(std::max(image.height, 0));
  if (n == 0) return "the image is empty";
  if (image.rgb.size() != 3 * n || image.variance.size() != 3 * n || image.samples.size() != n)
    return "the image lacks its mean, variance or sample counts";
  if (image.albedo.size() != 3 * n || image.normal.size() != 3 * n || image.depth.size() != n)
    return "the image lacks its feature buffers (albedo, normal, depth)";
  if (image.evenRgb.size() != 3 * n || image.evenSamples.size() != n)
    return "the image lacks its half buffers (render with RenderOptions::halfFilms)";
  const size_t residual[] = {image.emission.size(), image.evenEmission.size(),
                             image.residualVariance.size()};
  for (size_t size : residual) {
    if (size != residual[0] || (size != 0 && size != 3 * n))
      return "the image's emission and residual variance planes do not match its size";
  }
  return "";
}

}  // namespace pt
