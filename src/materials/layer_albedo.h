// Lookups in the albedo tables the layered glTF BSDF scales its layers by: the GGX tables of
// ggx_albedo_table.h (upper bounds, F = 1 and F = (1 - cos)^5) and layer_tables.h (the accurate
// GGX albedo for energy compensation, the Charlie sheen albedo). All share one grid: nodes
// mu = (i / 31)^2 and roughness r = j / 31, bilinear between nodes (linear in mu).
#pragma once

#include "src/materials/ggx_albedo_table.h"
#include "src/materials/layer_tables.h"
#include "src/core/math.h"

namespace pt {

// Where (mu, r) falls on the grid: the cell's corner index and the weights along each axis.
struct AlbedoCell {
  int i, j;
  float fx, fy;
};

PT_HDI AlbedoCell AlbedoCellAt(float mu, float r) {
  mu = Clamp01(mu);
  float x = sqrtf(mu) * float(kGgxAlbedoMu - 1);
  float y = Clamp01(r) * float(kGgxAlbedoRoughness - 1);
  int i = int(fminf(x, float(kGgxAlbedoMu - 2))), j = int(fminf(y, float(kGgxAlbedoRoughness - 2)));
  float mu0 = Sqr(float(i) / float(kGgxAlbedoMu - 1)), mu1 = Sqr(float(i + 1) / float(kGgxAlbedoMu - 1));
  return AlbedoCell{i, j, Clamp01((mu - mu0) / (mu1 - mu0)), y - float(j)};
}

// The bilinear interpolant of a 32 x 32 table at `base` read through entry(index).
template <typename Entry>
PT_HDI float AlbedoLerp(Entry entry, int base, const AlbedoCell& c) {
  int a = base + c.j * kGgxAlbedoMu + c.i, b = a + kGgxAlbedoMu;
  float lo = (1.0f - c.fx) * entry(a) + c.fx * entry(a + 1);
  float hi = (1.0f - c.fx) * entry(b) + c.fx * entry(b + 1);
  return (1.0f - c.fy) * lo + c.fy * hi;
}

// A row average (32 entries at `base`) at roughness r.
template <typename Entry>
PT_HDI float AlbedoRowLerp(Entry entry, int base, float r) {
  float y = Clamp01(r) * float(kGgxAlbedoRoughness - 1);
  int j = int(fminf(y, float(kGgxAlbedoRoughness - 2)));
  float fy = y - float(j);
  return (1.0f - fy) * entry(base + j) + fy * entry(base + j + 1);
}

struct GgxTableReader {
  PT_HDI float operator()(int i) const { return GgxAlbedoEntry(i); }
};
struct LayerTableReader {
  PT_HDI float operator()(int i) const { return LayerTableEntry(i); }
};

// Upper bounds of GGX reflection albedo with F = 1 (x) and with F = (1 - cos)^5 (y): with Schlick
// from F0 to F90 >= F0 the albedo is at most F0 x + (F90 - F0) y. A mirror: (1, (1 - mu)^5).
PT_HDI vec2 GgxAlbedoBounds(float mu, float r, bool smooth) {
  if (smooth) {
    float m = Clamp01(1.0f - mu);
    return vec2(1.0f, (m * m) * (m * m) * m);
  }
  AlbedoCell c = AlbedoCellAt(mu, r);
  return vec2(AlbedoLerp(GgxTableReader{}, kGgxAlbedoE1, c), AlbedoLerp(GgxTableReader{}, kGgxAlbedoE5, c));
}

// Their hemispherical averages (2 * integral of the interpolant times mu).
PT_HDI vec2 GgxAlbedoBoundAverages(float r, bool smooth) {
  if (smooth) return vec2(1.0f, 1.0f / 21.0f);
  return vec2(AlbedoRowLerp(GgxTableReader{}, kGgxAlbedoAvg1, r),
              AlbedoRowLerp(GgxTableReader{}, kGgxAlbedoAvg5, r));
}

// Accurate GGX albedo with F = 1 and its average (energy compensation).
PT_HDI float GgxAlbedoExact(float mu, float r) {
  return AlbedoLerp(LayerTableReader{}, kLayerMsE, AlbedoCellAt(mu, r));
}
PT_HDI float GgxAlbedoExactAverage(float r) { return AlbedoRowLerp(LayerTableReader{}, kLayerMsAvg, r); }

// Upper bound of the Charlie sheen albedo (white), possibly above 1 (see charlie_sheen.h).
PT_HDI float SheenAlbedoBound(float mu, float sheenRoughness) {
  return AlbedoLerp(LayerTableReader{}, kLayerSheenE, AlbedoCellAt(mu, sheenRoughness));
}

}  // namespace pt
