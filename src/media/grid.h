// Grid media on host and device: the density at a point (trilinear over the bricks) and the
// walk of a ray through the brick cells, each a stretch of constant majorant (a 3D DDA,
// Amanatides and Woo 1987). Layout: src/media/medium.h, docs/media.md.
#pragma once

#include "src/core/ray.h"
#include "src/media/medium.h"

namespace pt {

PT_HDI vec3 GridToIndex(const GridMedium& g, vec3 p) {
  vec4 h(p, 1.0f);
  return vec3(glm::dot(g.worldToIndex[0], h), glm::dot(g.worldToIndex[1], h),
              glm::dot(g.worldToIndex[2], h));
}

PT_HDI vec3 GridDirectionToIndex(const GridMedium& g, vec3 d) {
  return vec3(glm::dot(vec3(g.worldToIndex[0]), d), glm::dot(vec3(g.worldToIndex[1]), d),
              glm::dot(vec3(g.worldToIndex[2]), d));
}

PT_HDI uint32_t GridCellIndex(const GridMedium& g, glm::ivec3 c) {
  return g.tableOffset + (uint32_t(c.z) * g.dims.y + uint32_t(c.y)) * g.dims.x + uint32_t(c.x);
}

// The voxel at v, counted from the grid's cell origin; 0 outside the grid and in empty bricks.
PT_HDI float GridVoxel(const MediaView& mv, const GridMedium& g, glm::ivec3 v) {
  const int n = int(kBrickSize);
  if (v.x < 0 || v.y < 0 || v.z < 0 || v.x >= int(g.dims.x) * n || v.y >= int(g.dims.y) * n ||
      v.z >= int(g.dims.z) * n)
    return 0.0f;
  uint32_t brick = mv.cells[GridCellIndex(g, v / n)].brick;
  if (brick == kEmptyBrick) return 0.0f;
  uint32_t local = (uint32_t(v.z % n) * kBrickSize + uint32_t(v.y % n)) * kBrickSize +
                   uint32_t(v.x % n);
  return mv.voxels[size_t(brick) * kBrickVoxels + local];
}

// Density at world point p: trilinear between the eight voxels around it (OpenVDB's box
// sampler).
PT_HDI float GridDensity(const MediaView& mv, const GridMedium& g, vec3 p) {
  vec3 q = GridToIndex(g, p) - g.cellOrigin;
  vec3 f = glm::floor(q);
  if (!(f.x > -2.0f && f.y > -2.0f && f.z > -2.0f)) return 0.0f;  // also NaN
  vec3 limit = vec3(g.dims) * float(kBrickSize);
  if (!(f.x < limit.x && f.y < limit.y && f.z < limit.z)) return 0.0f;
  glm::ivec3 i(f);
  vec3 t = q - f;
  float c[2][2][2];
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx)
        c[dz][dy][dx] = GridVoxel(mv, g, i + glm::ivec3(dx, dy, dz));
  auto lerp = [](float a, float b, float s) { return a + s * (b - a); };
  float y0 = lerp(lerp(c[0][0][0], c[0][0][1], t.x), lerp(c[0][1][0], c[0][1][1], t.x), t.y);
  float y1 = lerp(lerp(c[1][0][0], c[1][0][1], t.x), lerp(c[1][1][0], c[1][1][1], t.x), t.y);
  return fmaxf(lerp(y0, y1, t.z), 0.0f);
}

// A stretch [t0, t1) of a ray over which the density never exceeds `majorant`.
struct MajorantSegment {
  float t0, t1, majorant;
};

// The walk of ray (o + t d, world space, t in [tMin, tMax)) through the grid's cells, in
// units of cells of index space (affine maps keep t).
class GridMajorantWalk {
 public:
  PT_HDI GridMajorantWalk(const MediaView& mv, const GridMedium& g, const Ray& ray, float tMin,
                          float tMax)
      : cells_(mv.cells), grid_(g) {
    const float perCell = 1.0f / float(kBrickSize);
    vec3 o = (GridToIndex(g, ray.o) - g.cellOrigin) * perCell;
    vec3 d = GridDirectionToIndex(g, ray.d) * perCell;
    vec3 hi = vec3(g.dims);
    float t0 = tMin, t1 = tMax;
    for (int a = 0; a < 3; ++a) {  // slab test against [0, dims]
      if (d[a] == 0.0f) {
        if (!(o[a] >= 0.0f && o[a] < hi[a])) t1 = -1.0f;
        continue;
      }
      float invD = 1.0f / d[a];
      float tn = (0.0f - o[a]) * invD, tf = (hi[a] - o[a]) * invD;
      if (tn > tf) { float s = tn; tn = tf; tf = s; }
      t0 = fmaxf(t0, tn);
      t1 = fminf(t1, tf);
    }
    t_ = t0;
    tEnd_ = t1;
    if (!(t0 < t1)) return;
    vec3 p = o + t0 * d;
    for (int a = 0; a < 3; ++a) {
      int c = int(floorf(p[a]));
      cell_[a] = c < 0 ? 0 : (c >= int(g.dims[a]) ? int(g.dims[a]) - 1 : c);
      if (d[a] == 0.0f) {
        next_[a] = kInfinity;
        delta_[a] = kInfinity;
        step_[a] = 0;
      } else if (d[a] > 0.0f) {
        next_[a] = t0 + (float(cell_[a] + 1) - p[a]) / d[a];
        delta_[a] = 1.0f / d[a];
        step_[a] = 1;
      } else {
        next_[a] = t0 + (float(cell_[a]) - p[a]) / d[a];
        delta_[a] = -1.0f / d[a];
        step_[a] = -1;
      }
    }
  }

  // The next stretch, or false when the ray has left the grid (or reached tMax).
  PT_HDI bool Next(MajorantSegment* seg) {
    if (!(t_ < tEnd_)) return false;
    int a = next_[0] < next_[1] ? (next_[0] < next_[2] ? 0 : 2) : (next_[1] < next_[2] ? 1 : 2);
    float t1 = fminf(fmaxf(next_[a], t_), tEnd_);
    seg->t0 = t_;
    seg->t1 = t1;
    seg->majorant = cells_[GridCellIndex(grid_, cell_)].majorant;
    t_ = t1;
    cell_[a] += step_[a];
    next_[a] += delta_[a];
    if (cell_[a] < 0 || cell_[a] >= int(grid_.dims[a])) t_ = tEnd_;
    return true;
  }

 private:
  const GridCell* cells_;
  GridMedium grid_;
  float t_, tEnd_;
  glm::ivec3 cell_ = glm::ivec3(0), step_ = glm::ivec3(0);
  vec3 next_ = vec3(0.0f), delta_ = vec3(0.0f);
};

}  // namespace pt
