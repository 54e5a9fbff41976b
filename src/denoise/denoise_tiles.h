// The CPU's order of the denoiser's per-offset passes (src/denoise/denoise_runner.h): a band
// of rows at a time, tile by tile, every group of offsets over a tile before the next tile,
// so that a tile's planes stay in its core's caches and no pass waits for the others. The
// bodies are nlm_stages.h's, as on the GPU; only the loop order differs. Host code.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "src/denoise/nlm_stages.h"

namespace pt {

// One band's work: image rows [r0, r1), every padded column, tileColumns at a time, in groups
// of at most maxGroup offsets (DenoiseOffsets::Group). The planes' distance pointers are the
// task's own (DenoiseRunner::Tiles).
struct DenoiseBand {
  DenoisePlanes d;
  DenoiseBandwidths k;
  uint32_t r0, r1, tileColumns;
  int radius, maxGroup;
};

// One group of offsets (kGroup = its count) over the columns [c0, c1) of a band.
using DenoiseGroupFn = void (*)(const DenoiseBand&, const DenoiseOffsets&, size_t, size_t);
using DenoiseGroupFns = std::array<DenoiseGroupFn, kDenoiseWideGroup + 1>;  // by group size

// How the CPU backend runs the per-offset passes: tiles of rows x columns padded pixels (0:
// the whole image), and per patch radius (0..3) the largest group and the group functions of
// the sizes it makes. The backend picks the functions (cpu_backend/denoise_cpu.cpp: compiled
// for the host's vector ISA).
struct DenoiseTiling {
  uint32_t rows = 0, columns = 0;
  std::array<int, 4> maxGroup{};
  std::array<DenoiseGroupFns, 4> groups{};
};

// body(p) for p in [begin, end): items the compiler may take as independent, so that it
// vectorises the body over them. (A 32-bit counter: GCC 12 vectorises none of these loops
// over a size_t one.)
template <typename F>
inline void DenoiseForPixels(size_t begin, size_t end, const F& body) {
  F local = body;
  uint32_t n = uint32_t(end - begin);
#if !defined(__CUDACC__)  // (host code: nvcc compiles it in the CUDA runner without using it)
#pragma GCC ivdep
#endif
  for (uint32_t i = 0; i < n; ++i) local(begin + size_t(i));
}

// One group of offsets over a tile (columns [c0, c1)): the distances over the tile widened by
// the patch radius, then the weights and sums over the tile. kGroup is o.count.
template <int kPatch, int kGroup>
inline void DenoiseTileGroup(const DenoiseBand& band, const DenoiseOffsets& o, size_t c0,
                             size_t c1) {
  const DenoisePlanes d = band.d;
  const DenoiseBandwidths k = band.k;
  for (uint32_t y = band.r0 + d.padY - kPatch; y < band.r1 + d.padY + kPatch; ++y) {
    size_t row = size_t(y) * d.stride;
    DenoiseForPixels(row + c0 - kPatch, row + c1 + kPatch,
                     [=](size_t p) { DenoiseDistancePixel<kGroup>(d, o, p); });
  }
  for (uint32_t y = band.r0 + d.padY; y < band.r1 + d.padY; ++y) {
    size_t row = size_t(y) * d.stride;
    DenoiseForPixels(row + c0, row + c1, [=](size_t p) {
      DenoiseAccumulatePixel<kPatch, kGroup>(d, k, o, p);
    });
  }
}

// Each tile of the band: every group of offsets in the GPU's order.
inline void DenoiseBandPasses(const DenoiseBand& band, const DenoiseGroupFns& groups) {
  const uint32_t stride = band.d.stride;
  int radius = band.radius;
  for (uint32_t c0 = 0; c0 < stride; c0 += band.tileColumns) {
    size_t c1 = std::min(stride, c0 + band.tileColumns);
    for (int dy = -radius; dy <= radius; ++dy) {
      for (int dx = -radius; dx <= radius;) {
        const DenoiseOffsets o = DenoiseOffsets::Group(dy, dx, radius, stride, band.maxGroup);
        groups[size_t(o.count)](band, o, c0, c1);
        dx += o.count;
      }
    }
  }
}

// The selection on the CPU, image row y: each candidate's error summed over the window into
// acc (kDenoiseCandidates x width floats, those past count left as they are) with the pixel
// loop innermost, so that it vectorises; each pixel's sum takes the same values in the same
// order as DenoiseFinishPixel's. Then each pixel's choice (DenoiseChoosePixel).
inline void DenoiseSelectRow(const DenoisePlanes& d, int count, int radius, float* out,
                             uint32_t y, float* acc) {
  const size_t row = d.Padded(0, y), width = d.width;
  const ptrdiff_t stride = ptrdiff_t(d.stride);
  for (int k = 0; k < count; ++k) {
    float* a = acc + size_t(k) * width;
    DenoiseForPixels(0, width, [=](size_t x) { a[x] = 0.0f; });
    for (int dy = -radius; dy <= radius; ++dy) {
      for (int dx = -radius; dx <= radius; ++dx) {
        const float* e = d.error[k] + (ptrdiff_t(row) + dy * stride + dx);
        DenoiseForPixels(0, width, [=](size_t x) { a[x] += e[x]; });
      }
    }
  }
  float* rgb = out + 3 * size_t(y) * width;
  DenoiseForPixels(0, width, [=](size_t x) {
    float e[kDenoiseCandidates];
    PT_DENOISE_UNROLL
    for (int k = 0; k < kDenoiseCandidates; ++k) e[k] = acc[size_t(k) * width + x];
    DenoiseChoosePixel(d, count, e, row + x, rgb + 3 * x);
  });
}

}  // namespace pt
