// Null-scattering transport through media (Miller, Georgiev and Jarosz 2019; pbrt-v4's
// volumetric path tracer): collisions are sampled against a majorant, real ones scatter or
// absorb, null ones continue. Chromatic media are sampled with one hero RGB channel per path
// and weighted by spectral MIS over the three channels (balance heuristic), so every channel
// is unbiased whichever is hero.
//
// Bookkeeping (docs/media.md): a path carries its throughput already divided by the average
// of its rescaled channel probabilities r_u, and r_u normalised to average 1 (rHat). Every
// medium event multiplies both by the same per-channel factor v, so only v's ratios matter:
// throughput *= v / avg(rHat v), rHat = rHat v / avg(rHat v). Surface events leave rHat alone.
#pragma once

#include "src/core/ray.h"
#include "src/core/rng.h"
#include "src/media/grid.h"

namespace pt {

// The random dimension group of media in each bounce (rng.h leaves group 3 unused).
constexpr uint32_t kDimMedium = 3;
static_assert(kDimMedium < kDimsPerBounce, "kDimMedium must be a group of its own");

// Random streams of one path vertex: the path's own tracking and each shadow ray's.
enum MediumStream : uint32_t { kStreamPath = 0, kStreamShadow = 1, kStreamHero = 2 };

// An unbounded sequence of uniform numbers for (path, bounce, stream): tracking draws as many
// as its collisions need, each a pure function of the path's key like every other draw.
struct MediumRng {
  glm::uvec4 base;
  uint32_t counter = 0, used = 4;
  vec4 cache = vec4(0.0f);

  PT_HDI MediumRng(const RngKey& key, uint32_t bounce, MediumStream stream)
      : base(key.pixel, key.sample, bounce * kDimsPerBounce + kDimMedium,
             key.seed ^ (uint32_t(stream) << 28)) {}

  PT_HDI float Next() {
    if (used == 4) {
      ++counter;
      glm::uvec4 h = Pcg4d(glm::uvec4(base.x, base.y, base.z, base.w + 0x9e3779b9u * counter));
      cache = vec4(BitsToUnitFloat(h.x), BitsToUnitFloat(h.y), BitsToUnitFloat(h.z),
                   BitsToUnitFloat(h.w));
      used = 0;
    }
    return cache[int(used++)];
  }
};

// The path's hero channel, uniform over R, G, B (to 2^-32).
PT_HDI int HeroChannel(const RngKey& key) {
  glm::uvec4 h = Pcg4d(glm::uvec4(key.pixel, key.sample, kDimMedium,
                                  key.seed ^ (uint32_t(kStreamHero) << 28)));
  return int((uint64_t(h.x) * 3u) >> 32);
}

PT_HDI float Average(vec3 v) { return (v.x + v.y + v.z) * (1.0f / 3.0f); }

// exp(-sigma d) per channel, 1 where sigma is 0 (whatever d, infinite included).
PT_HDI vec3 ExpNeg(vec3 sigma, float d) {
  vec3 r;
  for (int c = 0; c < 3; ++c) r[c] = sigma[c] > 0.0f ? expf(-sigma[c] * d) : 1.0f;
  return r;
}

// Applies a medium event's per-channel factor v to the throughput and rHat (see above).
// False when no channel can carry the path any more.
PT_HDI bool ApplySpectralFactor(vec3 v, vec3* beta, vec3* rHat) {
  if (v.x == v.y && v.y == v.z) return v.x > 0.0f;  // grey: nothing changes, exactly
  vec3 r = *rHat * v;
  float a = Average(r);
  if (!(a > 0.0f) || !(a < kInfinity)) return false;
  *beta *= v / a;
  *rHat = r / a;
  return true;
}

// The medium's coefficients at a collision.
struct MediumSample {
  vec3 sigmaA, sigmaS;
  vec3 le;  // emitted radiance (0 unless the medium emits)
};

// Samples collisions along ray (t in [0, tMax)) with the hero channel's majorant, calling
// f(t, const MediumSample&, vec3 sigmaMaj, vec3 Tmaj) at each (Tmaj: the majorant's
// transmittance since the previous collision); f returns false to stop. Returns the majorant
// transmittance from the last collision to tMax, or vec3(0) when f stopped the walk.
template <typename F>
PT_HDI vec3 SampleCollisions(const MediaView& mv, int32_t m, const Ray& ray, float tMax, int h,
                             MediumRng& rng, F&& f) {
  const Medium& med = mv.media[m];
  vec3 sigmaT = med.sigmaA + med.sigmaS;
  vec3 T(1.0f);
  // One stretch of constant majorant; false when f stopped.
  auto stretch = [&](float t0, float t1, float density, const GridMedium* g) {
    vec3 sigmaMaj = density * sigmaT;
    if (!(sigmaMaj[h] > 0.0f)) {
      T *= ExpNeg(sigmaMaj, t1 - t0);
      return true;
    }
    for (float t = t0;;) {
      float tc = t - log1pf(-rng.Next()) / sigmaMaj[h];
      if (!(tc < t1)) {
        T *= ExpNeg(sigmaMaj, t1 - t);
        return true;
      }
      T *= ExpNeg(sigmaMaj, tc - t);
      vec3 p = ray.o + tc * ray.d;
      float d = g ? GridDensity(mv, *g, p) : 1.0f;
      vec3 le = med.emission;
      if (med.emissionGrid >= 0) le *= GridDensity(mv, mv.grids[med.emissionGrid], p);
      if (!f(tc, MediumSample{d * med.sigmaA, d * med.sigmaS, le}, sigmaMaj, T)) return false;
      T = vec3(1.0f);
      t = tc;
    }
  };
  if (med.type == MediumType::kHomogeneous)
    return stretch(0.0f, tMax, 1.0f, nullptr) ? T : vec3(0.0f);
  const GridMedium& g = mv.grids[med.grid];
  GridMajorantWalk walk(mv, g, ray, 0.0f, tMax);
  MajorantSegment seg;
  while (walk.Next(&seg))
    if (seg.majorant > 0.0f && !stretch(seg.t0, seg.t1, seg.majorant, &g)) return vec3(0.0f);
  return T;
}

// What delta tracking along a path's segment found.
enum class MediumEvent : uint32_t { kNone, kAbsorbed, kScattered };

struct TrackResult {
  MediumEvent event = MediumEvent::kNone;
  float t = 0.0f;  // where it scattered
};

// Delta tracking for a path through medium m over [0, tMax): absorbs, scatters (beta and
// rHat then include the scattering coefficient) or passes (with the stretch's weights). An
// emitting medium adds its emission at every collision to *radiance when `emit` (pbrt-v4's
// estimator: beta sigma_a Le over the collision's majorant density, with spectral MIS).
PT_HDI TrackResult DeltaTrack(const MediaView& mv, int32_t m, const Ray& ray, float tMax, int h,
                              MediumRng& rng, vec3* beta, vec3* rHat, bool emit,
                              vec3* radiance) {
  TrackResult r;
  emit = emit && mv.media[m].Emits();
  vec3 T = SampleCollisions(mv, m, ray, tMax, h, rng,
                            [&](float t, const MediumSample& ms, vec3 sigmaMaj, vec3 Tmaj) {
    if (emit) {
      float a = Average(*rHat * sigmaMaj * Tmaj);
      if (a > 0.0f) *radiance += *beta * Tmaj * ms.sigmaA * ms.le / a;
    }
    float pAbsorb = ms.sigmaA[h] / sigmaMaj[h], pScatter = ms.sigmaS[h] / sigmaMaj[h];
    float u = rng.Next();
    r.t = t;
    if (u < pAbsorb) {
      r.event = MediumEvent::kAbsorbed;
      return false;
    }
    if (u < pAbsorb + pScatter) {
      r.event = ApplySpectralFactor(Tmaj * ms.sigmaS, beta, rHat) ? MediumEvent::kScattered
                                                                  : MediumEvent::kAbsorbed;
      return false;
    }
    vec3 sigmaN = glm::max(sigmaMaj - ms.sigmaA - ms.sigmaS, vec3(0.0f));
    if (ApplySpectralFactor(Tmaj * sigmaN, beta, rHat)) return true;
    r.event = MediumEvent::kAbsorbed;
    return false;
  });
  if (r.event == MediumEvent::kNone && !ApplySpectralFactor(T, beta, rHat))
    r.event = MediumEvent::kAbsorbed;
  return r;
}

// A shadow ray's transmittance estimate so far: tr over the average of rL (the light
// technique's rescaled channel probabilities) times the path's rHat, kept normalised so that
// tr is the estimate itself.
struct ShadowTransmittance {
  vec3 tr = vec3(1.0f);
  vec3 rL = vec3(1.0f);

  PT_HDI bool Apply(vec3 trFactor, vec3 rFactor, vec3 rHat) {
    tr *= trFactor;
    rL *= rFactor;
    float a = Average(rL * rHat);
    if (!(a > 0.0f) || !(a < kInfinity) || IsBlack(tr)) {
      tr = vec3(0.0f);
      return false;
    }
    tr /= a;
    rL /= a;
    return true;
  }
};

// Multiplies in the transmittance of medium m over [0, tMax) along ray: exact for a
// homogeneous medium, else ratio or delta tracking as mv.estimator says. False when it
// reached 0.
PT_HDI bool EstimateTransmittance(const MediaView& mv, int32_t m, const Ray& ray, float tMax,
                                  int h, vec3 rHat, MediumRng& rng, ShadowTransmittance* st) {
  const Medium& med = mv.media[m];
  if (med.type == MediumType::kHomogeneous) {
    st->tr *= ExpNeg(med.sigmaA + med.sigmaS, tMax);
    return !IsBlack(st->tr);
  }
  bool ratio = mv.estimator == TransmittanceEstimator::kRatio;
  vec3 T = SampleCollisions(mv, m, ray, tMax, h, rng,
                            [&](float, const MediumSample& ms, vec3 sigmaMaj, vec3 Tmaj) {
    vec3 sigmaN = glm::max(sigmaMaj - ms.sigmaA - ms.sigmaS, vec3(0.0f));
    if (!ratio) {  // delta tracking: a real collision ends the estimate at 0
      if (!(rng.Next() * sigmaMaj[h] < sigmaN[h])) {
        st->tr = vec3(0.0f);
        return false;
      }
      return st->Apply(Tmaj * sigmaN, Tmaj * sigmaN, rHat);
    }
    if (!st->Apply(Tmaj * sigmaN, Tmaj * sigmaMaj, rHat)) return false;
    if (MaxComponent(st->tr) < 0.05f) {  // Russian roulette on a small estimate (pbrt-v4)
      if (rng.Next() < 0.75f) {
        st->tr = vec3(0.0f);
        return false;
      }
      st->tr /= 0.25f;
    }
    return true;
  });
  if (IsBlack(st->tr)) return false;
  return st->Apply(T, T, rHat);
}

}  // namespace pt
