#include <stdexcept>
#include <string>

#include "src/integrator/render_api.h"

namespace pt {

// mean((x - r)^2 / (r^2 + 1e-2)) over pixels and channels; the 1e-2 keeps black pixels of the
// reference from dominating. Accumulated in double: images reach millions of terms.
double RelMse(const std::vector<float>& image, const std::vector<float>& reference) {
  if (image.size() != reference.size()) {
    throw std::invalid_argument("RelMse: image has " + std::to_string(image.size()) +
                                " values, reference " + std::to_string(reference.size()));
  }
  if (image.empty()) return 0.0;
  double sum = 0.0;
  for (size_t i = 0; i < image.size(); ++i) {
    double r = reference[i];
    double d = double(image[i]) - r;
    sum += d * d / (r * r + 1e-2);
  }
  return sum / double(image.size());
}

}  // namespace pt
