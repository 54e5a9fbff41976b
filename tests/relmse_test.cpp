// relMSE as cli.md defines it: mean((x - r)^2 / (r^2 + 1e-2)) over pixels and channels.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "src/integrator/render_api.h"

namespace pt {
namespace {

TEST(RelMse, ZeroForIdenticalImages) {
  std::vector<float> image = {0.0f, 0.5f, 2.0f, 10.0f, 0.25f, 1.0f};
  EXPECT_EQ(RelMse(image, image), 0.0);
  EXPECT_EQ(RelMse({}, {}), 0.0);
}

TEST(RelMse, MatchesTheDefinition) {
  // (1 - 0)^2 / (0 + 0.01) = 100; (2 - 1)^2 / (1 + 0.01); (0.5 - 0.5)^2 = 0.
  std::vector<float> image = {1.0f, 2.0f, 0.5f};
  std::vector<float> reference = {0.0f, 1.0f, 0.5f};
  EXPECT_NEAR(RelMse(image, reference), (100.0 + 1.0 / 1.01) / 3.0, 1e-9);
}

TEST(RelMse, IsRelativeToTheReference) {
  // The same relative error weighs (nearly) the same on bright and dim references.
  double bright = RelMse({110.0f}, {100.0f});
  double dim = RelMse({11.0f}, {10.0f});
  EXPECT_NEAR(bright, 0.01, 1e-5);
  EXPECT_NEAR(dim, 0.01, 1e-4);
}

TEST(RelMse, SizeMismatchThrows) {
  EXPECT_THROW(RelMse({1.0f, 2.0f, 3.0f}, {1.0f}), std::invalid_argument);
}

}  // namespace
}  // namespace pt
