#include "src/media/procedural_volume.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "src/core/rng.h"

namespace pt {
namespace {

// Value noise in [-1, 1]: hashed lattice values, smoothly interpolated.
float LatticeValue(int x, int y, int z, uint32_t seed) {
  glm::uvec4 h = Pcg4d(glm::uvec4(uint32_t(x), uint32_t(y), uint32_t(z), seed));
  return float(h.x >> 8) * 0x1p-23f - 1.0f;
}

float ValueNoise(glm::dvec3 p, uint32_t seed) {
  glm::dvec3 f = glm::floor(p);
  glm::ivec3 i(f);
  glm::dvec3 t = p - f;
  t = t * t * (3.0 - 2.0 * t);
  double v = 0.0;
  for (int c = 0; c < 8; ++c) {
    int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
    double w = (dx ? t.x : 1.0 - t.x) * (dy ? t.y : 1.0 - t.y) * (dz ? t.z : 1.0 - t.z);
    v += w * LatticeValue(i.x + dx, i.y + dy, i.z + dz, seed);
  }
  return float(v);
}

float Fbm(glm::dvec3 p, uint32_t seed, int octaves) {
  float sum = 0.0f, amplitude = 0.5f;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * ValueNoise(p, seed + uint32_t(o) * 7919u);
    p *= 2.03;
    amplitude *= 0.5f;
  }
  return sum;
}

// The grid of a density function over [-0.5, 0.5]^3, keeping only bricks with some density.
SparseGrid Sample(int n, const std::function<float(glm::dvec3)>& density) {
  SparseGrid grid;
  double voxel = 1.0 / n;
  grid.indexToWorld = glm::dmat4(voxel);
  grid.indexToWorld[3] = glm::dvec4(glm::dvec3(-0.5 + 0.5 * voxel), 1.0);
  for (int bz = 0; bz < n; bz += 8)
    for (int by = 0; by < n; by += 8)
      for (int bx = 0; bx < n; bx += 8) {
        SparseGrid::Brick b{glm::ivec3(bx, by, bz), std::vector<float>(kBrickVoxels, 0.0f)};
        bool any = false;
        for (int z = 0; z < 8; ++z)
          for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
              glm::ivec3 v = b.origin + glm::ivec3(x, y, z);
              if (v.x >= n || v.y >= n || v.z >= n) continue;
              glm::dvec3 p = glm::dvec3(grid.indexToWorld * glm::dvec4(glm::dvec3(v), 1.0));
              float d = std::clamp(density(p), 0.0f, 1.0f);
              b.values[(z * 8 + y) * 8 + x] = d;
              any = any || d > 0.0f;
            }
        if (any) grid.bricks.push_back(std::move(b));
      }
  return grid;
}

}  // namespace

SparseGrid MakeConstantGrid(glm::ivec3 n, float density, const glm::dmat4& indexToWorld) {
  SparseGrid grid;
  grid.indexToWorld = indexToWorld;
  for (int bz = 0; bz < n.z; bz += 8)
    for (int by = 0; by < n.y; by += 8)
      for (int bx = 0; bx < n.x; bx += 8) {
        SparseGrid::Brick b{glm::ivec3(bx, by, bz), std::vector<float>(kBrickVoxels, 0.0f)};
        for (int z = 0; z < 8; ++z)
          for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x)
              if (bx + x < n.x && by + y < n.y && bz + z < n.z)
                b.values[(z * 8 + y) * 8 + x] = density;
        grid.bricks.push_back(std::move(b));
      }
  return grid;
}

SparseGrid MakeNoiseCloud(int resolution, uint32_t seed) {
  // Lobes of a cumulus: a wide base and three puffs above it (centre, radius).
  const glm::dvec4 lobes[] = {{0.0, -0.1, 0.0, 0.32}, {-0.15, 0.05, 0.05, 0.22},
                              {0.12, 0.08, -0.05, 0.24}, {0.0, 0.2, 0.0, 0.18}};
  return Sample(resolution, [&](glm::dvec3 p) {
    double shape = -1.0;
    for (const glm::dvec4& l : lobes)
      shape = std::max(shape, 1.0 - glm::length(p - glm::dvec3(l)) / l.w);
    if (p.y < -0.25) shape -= (-0.25 - p.y) * 8.0;  // a flat bottom
    float erosion = Fbm(p * 9.0, seed, 5);
    return float(shape * 2.5) + 1.6f * erosion;
  });
}

SparseGrid MakeSmokeSphere(int resolution, uint32_t seed) {
  return Sample(resolution, [&](glm::dvec3 p) {
    double r = glm::length(p) / 0.45;
    float turbulence = Fbm(p * 7.0 + glm::dvec3(0.0, -p.y * 3.0, 0.0), seed, 4);
    double falloff = 1.0 - r + 0.35 * turbulence;
    double thinning = 1.0 - 0.6 * std::clamp(p.y / 0.45 + 0.5, 0.0, 1.0);
    return float(std::clamp(falloff * 3.0, 0.0, 1.0) * thinning);
  });
}

}  // namespace pt
