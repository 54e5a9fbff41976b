#include "src/media/grid_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "src/media/grid.h"

namespace pt {
namespace {

glm::ivec3 FloorDiv8(glm::ivec3 v) {
  return glm::ivec3(v.x >> 3, v.y >> 3, v.z >> 3);  // arithmetic shift: floor for negatives
}

std::string VoxelText(glm::ivec3 v) {
  return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

// Checks every value, and returns the bricks' cell range (the one below the lowest included:
// trilinear interpolation reaches one voxel past the data).
void CellRange(const SparseGrid& grid, glm::ivec3* lo, glm::ivec3* hi) {
  if (grid.bricks.empty()) throw GridLayoutError("the grid has no voxels");
  *lo = glm::ivec3(std::numeric_limits<int>::max());
  *hi = glm::ivec3(std::numeric_limits<int>::min());
  for (const SparseGrid::Brick& b : grid.bricks) {
    if (b.values.size() != kBrickVoxels || (b.origin.x & 7) || (b.origin.y & 7) || (b.origin.z & 7))
      throw GridLayoutError("a brick is not 8^3 voxels at a multiple of 8");
    for (uint32_t i = 0; i < kBrickVoxels; ++i) {
      float v = b.values[i];
      if (std::isfinite(v) && v >= 0.0f) continue;
      glm::ivec3 at = b.origin + glm::ivec3(i % 8, (i / 8) % 8, i / 64);
      throw GridLayoutError("voxel " + VoxelText(at) + " holds " + std::to_string(v) +
                            " (densities must be finite and >= 0)");
    }
    glm::ivec3 c = FloorDiv8(b.origin);
    *lo = glm::min(*lo, c);
    *hi = glm::max(*hi, c);
  }
  *lo -= glm::ivec3(1);
}

// The largest density trilinear interpolation reaches in each cell: voxels 8c .. 8c + 8.
void FillMajorants(MediaDesc* out, const GridMedium& g) {
  const MediaDesc& media = *out;
  MediaView mv;
  mv.cells = media.cells.data();
  mv.voxels = media.voxels.data();
  std::vector<float> majorant(size_t(g.dims.x) * g.dims.y * g.dims.z, 0.0f);
  for (uint32_t z = 0; z < g.dims.z; ++z)
    for (uint32_t y = 0; y < g.dims.y; ++y)
      for (uint32_t x = 0; x < g.dims.x; ++x) {
        glm::ivec3 base = glm::ivec3(x, y, z) * 8;
        float m = 0.0f;
        // Only cells next to a brick can be non-zero.
        bool any = false;
        for (int dz = -1; dz <= 1 && !any; ++dz)
          for (int dy = -1; dy <= 1 && !any; ++dy)
            for (int dx = -1; dx <= 1 && !any; ++dx) {
              glm::ivec3 c = glm::ivec3(x, y, z) + glm::ivec3(dx, dy, dz);
              if (glm::any(glm::lessThan(c, glm::ivec3(0))) ||
                  glm::any(glm::greaterThanEqual(c, glm::ivec3(g.dims))))
                continue;
              any = media.cells[GridCellIndex(g, c)].brick != kEmptyBrick;
            }
        if (!any) continue;
        for (int k = 0; k <= 8; ++k)
          for (int j = 0; j <= 8; ++j)
            for (int i = 0; i <= 8; ++i)
              m = std::max(m, GridVoxel(mv, g, base + glm::ivec3(i, j, k)));
        majorant[GridCellIndex(g, glm::ivec3(x, y, z)) - g.tableOffset] = m;
      }
  for (size_t i = 0; i < majorant.size(); ++i) out->cells[g.tableOffset + i].majorant = majorant[i];
}

}  // namespace

int32_t AddGridLayout(const SparseGrid& grid, const glm::dmat4& toWorld, MediaDesc* media) {
  glm::ivec3 lo, hi;
  CellRange(grid, &lo, &hi);
  glm::ivec3 dims = hi - lo + glm::ivec3(1);
  uint64_t cellCount = uint64_t(dims.x) * uint64_t(dims.y) * uint64_t(dims.z);
  if (cellCount > kMaxGridCells)
    throw GridLayoutError("the grid spans " + std::to_string(cellCount) +
                          " bricks of 8^3 voxels; at most " + std::to_string(kMaxGridCells) +
                          " fit its table");
  glm::dmat4 indexToWorld = toWorld * grid.indexToWorld;
  double det = glm::determinant(glm::dmat3(indexToWorld));
  if (!(std::fabs(det) > 0.0) || !std::isfinite(det))
    throw GridLayoutError("the grid's transform is singular or not finite");
  glm::dmat4 worldToIndex = glm::inverse(indexToWorld);
  GridMedium g{};
  for (int r = 0; r < 3; ++r)
    g.worldToIndex[r] = vec4(float(worldToIndex[0][r]), float(worldToIndex[1][r]),
                             float(worldToIndex[2][r]), float(worldToIndex[3][r]));
  g.brickOrigin = lo;
  g.cellOrigin = vec3(lo * 8);
  g.dims = glm::uvec3(dims);
  g.tableOffset = uint32_t(media->cells.size());
  media->cells.resize(media->cells.size() + cellCount, GridCell{kEmptyBrick, 0.0f});
  float maxDensity = 0.0f;
  for (const SparseGrid::Brick& b : grid.bricks) {
    float bmax = *std::max_element(b.values.begin(), b.values.end());
    if (!(bmax > 0.0f)) continue;  // all zero: an empty cell
    maxDensity = std::max(maxDensity, bmax);
    GridCell& cell = media->cells[GridCellIndex(g, FloorDiv8(b.origin) - lo)];
    if (cell.brick != kEmptyBrick) throw GridLayoutError("two bricks at the same place");
    cell.brick = uint32_t(media->voxels.size() / kBrickVoxels);
    media->voxels.insert(media->voxels.end(), b.values.begin(), b.values.end());
  }
  if (media->voxels.size() / kBrickVoxels >= kEmptyBrick)
    throw GridLayoutError("too many bricks in the scene's grids");
  g.maxDensity = maxDensity;
  FillMajorants(media, g);
  media->grids.push_back(g);
  return int32_t(media->grids.size() - 1);
}

void GridWorldBounds(const SparseGrid& grid, const glm::dmat4& toWorld, vec3* lo, vec3* hi) {
  glm::dvec3 vlo(std::numeric_limits<double>::max()), vhi(-std::numeric_limits<double>::max());
  for (const SparseGrid::Brick& b : grid.bricks) {
    vlo = glm::min(vlo, glm::dvec3(b.origin) - 1.0);
    vhi = glm::max(vhi, glm::dvec3(b.origin) + 8.0);
  }
  glm::dmat4 m = toWorld * grid.indexToWorld;
  glm::dvec3 wlo(std::numeric_limits<double>::max()), whi(-std::numeric_limits<double>::max());
  for (int c = 0; c < 8; ++c) {
    glm::dvec3 p((c & 1) ? vhi.x : vlo.x, (c & 2) ? vhi.y : vlo.y, (c & 4) ? vhi.z : vlo.z);
    glm::dvec3 w = glm::dvec3(m * glm::dvec4(p, 1.0));
    wlo = glm::min(wlo, w);
    whi = glm::max(whi, w);
  }
  *lo = vec3(wlo);
  *hi = vec3(whi);
}

}  // namespace pt
