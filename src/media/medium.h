// Participating media as the stages see them: a closed set of medium types (a tag and one
// switch, no virtual functions), the medium interfaces of primitives, and the view of every
// media array a media kernel reads. Scenes without media never include this in a kernel.
#pragma once

#include "src/core/math.h"

namespace pt {

enum class MediumType : uint32_t { kHomogeneous = 0, kGrid = 1 };

// One medium. Coefficients are per unit length in world units, the scene's "scale" already
// applied; a grid medium's are those of density 1, multiplied by the grid's density.
// Emission: radiance `emission` where the medium absorbs (the source term sigma_a Le), times
// the value of emissionGrid (a grid of its own, e.g. a temperature) where it has one.
struct Medium {
  MediumType type = MediumType::kHomogeneous;
  int32_t grid = -1;     // kGrid: index into MediaView::grids
  float g = 0.0f;        // Henyey-Greenstein asymmetry, in (-1, 1)
  int32_t emissionGrid = -1;  // index into MediaView::grids, or -1: `emission` everywhere
  vec3 sigmaA = vec3(0.0f);
  vec3 sigmaS = vec3(0.0f);
  vec3 emission = vec3(0.0f);

  PT_HDI bool Emits() const {
    return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f;
  }
};

// A grid medium laid out for the GPU (docs/media.md): density on the voxels of a sparse grid
// stored as bricks of 8^3 voxels, found through a dense table over the brick cells, which also
// holds each cell's majorant (the largest density trilinear interpolation can reach in it).
// Index space: voxel (i, j, k) sits at the integer point (i, j, k), OpenVDB's convention.
struct GridMedium {
  vec4 worldToIndex[3];   // rows of the affine map from world to index space
  vec3 cellOrigin;        // index-space corner of cell (0, 0, 0): 8 * its brick coordinates
  uint32_t tableOffset;   // into MediaView::cells
  glm::ivec3 brickOrigin;  // brick coordinates of cell (0, 0, 0)
  uint32_t pad0;
  glm::uvec3 dims;         // cells per axis
  float maxDensity;        // over the whole grid
};

// A brick cell: its brick (or kEmptyBrick: every voxel 0) and the majorant density of the
// index-space cube [8c, 8c + 8) it covers.
struct GridCell {
  uint32_t brick;
  float majorant;
};
constexpr uint32_t kEmptyBrick = 0xffffffffu;
constexpr uint32_t kBrickSize = 8;  // voxels per brick edge (OpenVDB's leaf size)
constexpr uint32_t kBrickVoxels = kBrickSize * kBrickSize * kBrickSize;

// A primitive's medium interface packed in 32 bits: the medium inside (behind its geometric
// normal) and outside, each as index + 1 (0: vacuum), whether it is an interface (no surface:
// rays pass straight through) and whether it has an interface at all (else the ray keeps its
// medium).
constexpr uint32_t kMediumFieldBits = 15;
constexpr uint32_t kMediumFieldMask = (1u << kMediumFieldBits) - 1u;
constexpr uint32_t kMaxMedia = kMediumFieldMask - 1;   // the last value is kOutsideIsCamera
constexpr uint32_t kOutsideIsCamera = kMediumFieldMask;  // host only: "the camera's medium"
constexpr uint32_t kInterfaceInvisible = 1u << 30;
constexpr uint32_t kInterfaceTransition = 1u << 31;

PT_HDI uint32_t PackMediumInterface(int32_t inside, int32_t outside, bool invisible) {
  return kInterfaceTransition | (invisible ? kInterfaceInvisible : 0u) |
         uint32_t(inside + 1) | (uint32_t(outside + 1) << kMediumFieldBits);
}
PT_HDI bool IsTransition(uint32_t iface) { return (iface & kInterfaceTransition) != 0; }
PT_HDI bool IsInvisible(uint32_t iface) { return (iface & kInterfaceInvisible) != 0; }
PT_HDI int32_t InsideMedium(uint32_t iface) { return int32_t(iface & kMediumFieldMask) - 1; }
PT_HDI int32_t OutsideMedium(uint32_t iface) {
  return int32_t((iface >> kMediumFieldBits) & kMediumFieldMask) - 1;
}
// The medium a ray leaving the surface along w enters: inside when w goes against the
// geometric normal ng, else outside; `current` where the surface has no interface.
PT_HDI int32_t MediumAfter(uint32_t iface, vec3 ng, vec3 w, int32_t current) {
  if (!IsTransition(iface)) return current;
  return glm::dot(w, ng) < 0.0f ? InsideMedium(iface) : OutsideMedium(iface);
}

// How shadow rays estimate transmittance through grid media (--transmittance): ratio
// tracking (the default) or delta tracking (a binary estimator, for the accuracy study).
// Homogeneous media use the exact exp(-sigma_t d) with either.
enum class TransmittanceEstimator : uint32_t { kRatio = 0, kDelta = 1 };

// Every media array a media kernel reads (host memory on the CPU, device memory on the GPU).
struct MediaView {
  const Medium* media = nullptr;
  const GridMedium* grids = nullptr;
  const GridCell* cells = nullptr;
  const float* voxels = nullptr;       // kBrickVoxels per brick, x fastest
  const uint32_t* primMedia = nullptr;  // per PrimRef (BVH order); null: no primitive has one
  uint32_t mediumCount = 0;
  int32_t cameraMedium = -1;           // the medium camera rays start in (-1: vacuum)
  uint32_t invisibleCount = 0;         // primitives rays pass through (interface material)
  TransmittanceEstimator estimator = TransmittanceEstimator::kRatio;

  PT_HDI uint32_t InterfaceOf(uint32_t prim) const { return primMedia ? primMedia[prim] : 0u; }
};

// ---- Henyey-Greenstein phase function ----
// cosTheta is the cosine between the direction light travelled before scattering (the ray's
// direction) and after it (towards the next vertex): g > 0 scatters forwards.
PT_HDI float HenyeyGreenstein(float cosTheta, float g) {
  float denom = 1.0f + g * g - 2.0f * g * cosTheta;
  return kInv4Pi * (1.0f - g * g) / (denom * SafeSqrt(denom));
}

// Samples the direction after scattering, given unit rayDir; the pdf equals the phase value.
PT_HDI vec3 SampleHenyeyGreenstein(vec3 rayDir, float g, vec2 u, float* pdf) {
  float cosTheta;
  if (fabsf(g) < 1e-3f) {
    cosTheta = 1.0f - 2.0f * u.x;
  } else {
    float s = (1.0f - g * g) / (1.0f - g + 2.0f * g * u.x);
    cosTheta = (1.0f + g * g - s * s) / (2.0f * g);
  }
  cosTheta = fminf(fmaxf(cosTheta, -1.0f), 1.0f);
  float sinTheta = SafeSqrt(1.0f - cosTheta * cosTheta);
  float phi = 2.0f * kPi * u.y;
  Frame frame = Frame::FromZ(rayDir);
  vec3 wi = frame.FromLocal(vec3(sinTheta * cosf(phi), sinTheta * sinf(phi), cosTheta));
  *pdf = HenyeyGreenstein(cosTheta, g);
  return glm::normalize(wi);
}

}  // namespace pt
