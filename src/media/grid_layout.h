// Lays a sparse grid out as the GPU reads it (src/media/medium.h, docs/media.md): its bricks
// appended to the scene's voxel array, a dense table over the brick cells of the grid's
// bounds, and each cell's majorant.
#pragma once

#include <stdexcept>
#include <string>

#include "src/media/media_desc.h"

namespace pt {

// Brick cells one grid may span (its table is dense over its bounds): 2^27 cells are 1 GiB.
constexpr uint64_t kMaxGridCells = uint64_t(1) << 27;

// A grid the layout cannot take; the message says what (the loader names file and field).
struct GridLayoutError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Appends grid (placed in the world by toWorld after its own index -> world map) to media's
// arrays; returns its index in media->grids. Throws GridLayoutError on an empty grid, a value
// that is negative or not finite, or one too large for the table.
int32_t AddGridLayout(const SparseGrid& grid, const glm::dmat4& toWorld, MediaDesc* media);

// The world-space box outside of which the grid's density is 0 (its voxels' reach).
void GridWorldBounds(const SparseGrid& grid, const glm::dmat4& toWorld, vec3* lo, vec3* hi);

}  // namespace pt
