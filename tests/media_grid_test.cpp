// Grid media and the estimators below the renderer: the brick layout against a direct reading
// of the voxels, majorants that bound every density, the DDA's stretches, transmittance
// estimators (ratio and delta tracking) against quadrature of the density, and the
// Henyey-Greenstein phase function (normalisation, chi-square of its sampling).
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <tuple>

#include "src/media/grid_layout.h"
#include "src/media/procedural_volume.h"
#include "src/media/tracking.h"
#include "tests/stat_test_util.h"

namespace pt {
namespace {

using test::kZ1e4;

// A straightforward trilinear reading of a SparseGrid (the layout's reference).
struct VoxelReference {
  std::map<std::tuple<int, int, int>, const std::vector<float>*> bricks;
  explicit VoxelReference(const SparseGrid& g) {
    for (const SparseGrid::Brick& b : g.bricks)
      bricks[{b.origin.x >> 3, b.origin.y >> 3, b.origin.z >> 3}] = &b.values;
  }
  double Voxel(glm::ivec3 v) const {
    auto it = bricks.find({v.x >> 3, v.y >> 3, v.z >> 3});
    if (it == bricks.end()) return 0.0;
    return (*it->second)[((v.z & 7) * 8 + (v.y & 7)) * 8 + (v.x & 7)];
  }
  double Density(glm::dvec3 q) const {
    glm::dvec3 f = glm::floor(q), t = q - f;
    glm::ivec3 i(f);
    double sum = 0.0;
    for (int c = 0; c < 8; ++c) {
      int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
      sum += (dx ? t.x : 1 - t.x) * (dy ? t.y : 1 - t.y) * (dz ? t.z : 1 - t.z) *
             Voxel(i + glm::ivec3(dx, dy, dz));
    }
    return sum;
  }
};

struct GridFixture {
  SparseGrid grid;
  MediaDesc media;
  MediaView view;
  explicit GridFixture(SparseGrid g, vec3 sigmaA = vec3(0.5f), vec3 sigmaS = vec3(2.0f))
      : grid(std::move(g)) {
    Medium m;
    m.type = MediumType::kGrid;
    m.sigmaA = sigmaA;
    m.sigmaS = sigmaS;
    glm::dmat4 place(1.0);
    place[3] = glm::dvec4(0.25, -0.1, 0.3, 1.0);  // placed off the origin, scaled up
    place[0][0] = place[1][1] = place[2][2] = 1.5;
    m.grid = AddGridLayout(grid, place, &media);
    media.media.push_back(m);
    view.media = media.media.data();
    view.grids = media.grids.data();
    view.cells = media.cells.data();
    view.voxels = media.voxels.data();
    view.mediumCount = 1;
  }
  const GridMedium& Grid() const { return media.grids[0]; }
  // World point -> index space, as the layout's reference sees it.
  glm::dvec3 ToIndex(vec3 p) const { return glm::dvec3(GridToIndex(Grid(), p)); }
};

TEST(MediaGrid, LayoutReadsTheVoxelsOfTheSparseGrid) {
  GridFixture f(MakeNoiseCloud(40, 3));
  VoxelReference ref(f.grid);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int nonZero = 0;
  for (int i = 0; i < 20000; ++i) {
    vec3 p(u(rng), u(rng), u(rng));
    double expected = ref.Density(f.ToIndex(p));
    float got = GridDensity(f.view, f.Grid(), p);
    ASSERT_NEAR(got, expected, 1e-5) << "at " << p.x << " " << p.y << " " << p.z;
    nonZero += expected > 0.0;
  }
  EXPECT_GT(nonZero, 1000);  // the test looked inside the cloud
}

TEST(MediaGrid, MajorantsBoundTheDensityAlongEveryStretch) {
  GridFixture f(MakeSmokeSphere(48, 5));
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int stretches = 0;
  for (int r = 0; r < 300; ++r) {
    Ray ray{vec3(-2.0f, u(rng) - 0.5f, u(rng) - 0.3f),
            glm::normalize(vec3(1.0f, u(rng) - 0.5f, u(rng) - 0.5f))};
    GridMajorantWalk walk(f.view, f.Grid(), ray, 0.0f, kInfinity);
    MajorantSegment seg;
    float last = -1.0f;
    while (walk.Next(&seg)) {
      ++stretches;
      ASSERT_LE(seg.t0, seg.t1);
      if (last >= 0.0f) {
        ASSERT_EQ(seg.t0, last) << "stretches must be contiguous";
      }
      last = seg.t1;
      for (int k = 0; k <= 16; ++k) {
        float t = seg.t0 + (seg.t1 - seg.t0) * (k / 16.0f);
        ASSERT_LE(GridDensity(f.view, f.Grid(), ray.o + t * ray.d), seg.majorant * 1.0001f + 1e-6f);
      }
    }
  }
  EXPECT_GT(stretches, 1000);
}

// exp(-sigma_t * integral of the density) along the ray by fine midpoint quadrature.
vec3 QuadratureTransmittance(const GridFixture& f, const Ray& ray, float tMax) {
  const int steps = 20000;
  double sum = 0.0, dt = tMax / steps;
  for (int i = 0; i < steps; ++i)
    sum += GridDensity(f.view, f.Grid(), ray.o + float((i + 0.5) * dt) * ray.d) * dt;
  vec3 sigmaT = f.media.media[0].sigmaA + f.media.media[0].sigmaS;
  return vec3(std::exp(-sigmaT.x * sum), std::exp(-sigmaT.y * sum), std::exp(-sigmaT.z * sum));
}

// Each estimator, with the hero channel drawn per sample as the renderer draws it (spectral
// MIS is unbiased over that choice), averages to the quadrature's transmittance per channel.
TEST(MediaGrid, TransmittanceEstimatorsMatchQuadrature) {
  GridFixture f(MakeNoiseCloud(32, 7), vec3(0.3f, 0.8f, 1.2f), vec3(1.0f, 2.0f, 0.5f));
  const Ray rays[] = {{vec3(-1.2f, 0.0f, 0.3f), glm::normalize(vec3(1.0f, 0.1f, 0.05f))},
                      {vec3(0.2f, -1.0f, 0.2f), glm::normalize(vec3(0.1f, 1.0f, 0.2f))}};
  for (const Ray& ray : rays) {
    vec3 expected = QuadratureTransmittance(f, ray, 2.5f);
    ASSERT_LT(expected.z, 0.9f);  // the ray crosses some cloud
    for (TransmittanceEstimator e :
         {TransmittanceEstimator::kRatio, TransmittanceEstimator::kDelta}) {
      f.view.estimator = e;
      test::MeanAccumulator acc[3];
      for (uint32_t s = 0; s < 60000; ++s) {
        RngKey key{s, 1u, 11u};
        MediumRng rng(key, 0, kStreamShadow);
        ShadowTransmittance st;
        EstimateTransmittance(f.view, 0, ray, 2.5f, HeroChannel(key), vec3(1.0f), rng, &st);
        for (int c = 0; c < 3; ++c) acc[c].Add(st.tr[c]);
      }
      for (int c = 0; c < 3; ++c) {
        test::MeanEstimate m = acc[c].Result();
        EXPECT_NEAR(m.mean, expected[c], kZ1e4 * m.stdError + 1e-4)
            << (e == TransmittanceEstimator::kRatio ? "ratio" : "delta") << " channel " << c;
      }
    }
  }
}

TEST(MediaGrid, HenyeyGreensteinIsNormalisedAndSampledByItsPdf) {
  const vec3 dir = glm::normalize(vec3(0.3f, -0.5f, 0.8f));
  for (float g : {-0.7f, 0.0f, 0.3f, 0.9f}) {
    // Normalisation: integral over cos theta in [-1, 1] of 2 pi p.
    double integral = 0.0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
      double mu = -1.0 + (i + 0.5) * 2.0 / n;
      integral += 2.0 * M_PI * HenyeyGreenstein(float(mu), g) * (2.0 / n);
    }
    EXPECT_NEAR(integral, 1.0, 2e-3) << "g " << g;
    test::Uniform u(17);
    auto sample = [&](vec3* w) {
      float pdf;
      *w = SampleHenyeyGreenstein(dir, g, u.Get2(), &pdf);
      float expected = HenyeyGreenstein(glm::dot(dir, *w), g);
      return std::fabs(pdf - expected) <= 1e-3f * expected;
    };
    auto pdf = [&](vec3 w) { return double(HenyeyGreenstein(glm::dot(dir, w), g)); };
    test::ChiSquareOptions o;
    o.thetaBins = 24;
    o.phiBins = 48;
    test::ChiSquareResult r = test::ChiSquareDirections(sample, pdf, 500000, o);
    EXPECT_GT(r.pValue, test::kChiSquareAlpha) << "g " << g << ": " << r.message;
  }
}

}  // namespace
}  // namespace pt
