// Density grids made without files: test data and the tools/make_vdb writer's sources. Each
// fits the cube [-0.5, 0.5]^3 (resolution voxels along each axis) unless said otherwise.
#pragma once

#include <cstdint>

#include "src/media/media_desc.h"

namespace pt {

// Every voxel of [0, n) set to `density`, placed by indexToWorld. Inside the index box
// [0, n - 1] trilinear interpolation gives exactly `density` (it ramps to 0 one voxel out).
SparseGrid MakeConstantGrid(glm::ivec3 n, float density, const glm::dmat4& indexToWorld);

// A cumulus-like cloud: a few overlapping spheres eroded by fractal value noise, densities in
// [0, 1].
SparseGrid MakeNoiseCloud(int resolution, uint32_t seed);

// A sphere of smoke: density 1 near the centre falling to 0 at the radius, its edge made
// turbulent by noise, thinning upwards like a rising plume.
SparseGrid MakeSmokeSphere(int resolution, uint32_t seed);

}  // namespace pt
