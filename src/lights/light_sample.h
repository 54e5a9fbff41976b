// Next-event estimation: choosing a light (uniformly, by power, or through the light BVH:
// SceneView::lightTree.sampler), sampling a point or direction on it, and the matching
// solid-angle pdfs for multiple importance sampling when a BSDF-sampled ray hits an emitter.
// Every pdf here includes the probability of choosing the light.
//
// kMap = false compiles the environment map out (stage variants of scenes without one).
#pragma once

#include "src/core/sampling.h"
#include "src/lights/env_map.h"
#include "src/lights/light_bvh.h"
#include "src/materials/emission.h"
#include "src/geometry/instance.h"
#include "src/scene/scene_view.h"

namespace pt {

struct LightLiSample {
  vec3 L = vec3(0.0f);       // radiance arriving at refP along wi (point, spot: intensity / d^2)
  vec3 wi = vec3(0.0f);      // unit direction from refP towards the light
  float pdf = 0.0f;          // solid angle x choice probability; delta: choice probability
  vec3 pLight = vec3(0.0f);  // the sampled point (background: a point beyond the scene)
  vec3 nLight = vec3(0.0f);  // unit geometric normal there (point: 0; background: -wi)
  bool isDelta = false;      // point and spot lights, delta directional: MIS does not apply
  bool isInfinite = false;   // background, directional, map: trace the shadow ray unbounded
  int lightIndex = -1;       // which entry of SceneView::lights was chosen
};

// ---- Shape measures shared with the host light table ----

PT_HDI float QuadArea(const Quad& q) { return glm::length(glm::cross(q.u, q.v)); }
PT_HDI float TriangleArea(const Triangle& t) {
  return 0.5f * glm::length(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
}
PT_HDI float SphereArea(const Sphere& s) { return 4.0f * kPi * s.radius * s.radius; }

// Radiance leaving an emissive surface with geometric normal ng towards wo (world space):
// emission is one-sided unless the material says two_sided. glTF materials pass their
// resolved emission (factor x texture x strength) in m.radiance.
PT_HDI vec3 EmittedRadiance(const Material& m, vec3 ng, vec3 wo) {
  if (m.type != MaterialType::kEmissive && m.type != MaterialType::kGltfPbr) return vec3(0.0f);
  if (!m.twoSided && glm::dot(ng, wo) <= 0.0f) return vec3(0.0f);
  return m.radiance;
}

// An area light's triangle in world space (an instance's is transformed, wound to its front).
PT_HDI Triangle LightTriangle(const SceneView& s, const Light& light, uint32_t index) {
  if (light.instance < 0) return s.triangles[index];
  return TriangleToWorld(s.instances[light.instance], s.triangles[index]);
}

// ---- Light choice ----

// Largest i with lightCdf[i] <= u, so a light of zero probability (an empty cdf interval) is
// never chosen. Returns -1 when there is nothing to choose.
PT_HDI int SampleLightIndex(const SceneView& s, float u) {
  if (s.lightCount == 0) return -1;
  int lo = 0, hi = int(s.lightCount) - 1;
  while (lo < hi) {
    int mid = (lo + hi + 1) / 2;
    if (s.lightCdf[mid] <= u) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

// Probability of choosing light `index` where the choice does not depend on the point: every
// light under the uniform sampler, lights at infinity under the others (the BVH sampler
// chooses them by power beside the tree, as the power sampler does).
PT_HDI float InfiniteLightPmf(const SceneView& s, uint32_t index) {
  if (s.lightTree.sampler == uint32_t(LightSampler::kUniform)) return 1.0f / float(s.lightCount);
  return s.lightPmf[index];
}

// The BVH sampler's probability of choosing the tree at all: the power share of the finite
// lights (the power table's cdf up to them), so the lights at infinity keep their share.
PT_HDI float LightTreeShare(const SceneView& s) { return s.lightCdf[s.lightTree.boundedCount]; }

// Chooses a light for reference r with uChoice (uRefresh: the BVH walk's second number, or
// negative); -1 when there is none. *pmf: the probability, LightChoicePmf's value.
PT_HDI int ChooseLight(const SceneView& s, const LightRef& r, float uChoice, float uRefresh,
                       float* pmf) {
  if (s.lightCount == 0) return -1;
  switch (LightSampler(s.lightTree.sampler)) {
    case LightSampler::kUniform: {
      int index = int(fminf(uChoice * float(s.lightCount), float(s.lightCount - 1)));
      *pmf = 1.0f / float(s.lightCount);
      return index;
    }
    case LightSampler::kBvh: {
      float share = LightTreeShare(s);
      if (uChoice < share) {
        int index;
        float p;
        if (!SampleLightTree(s, r, fminf(uChoice / share, 0x1.fffffep-1f), uRefresh, &index, &p))
          return -1;
        *pmf = share * p;
        return index;
      }
      break;  // a light at infinity, by the power table (its cdf puts it past the tree's share)
    }
    default: break;
  }
  int index = SampleLightIndex(s, uChoice);
  *pmf = s.lightPmf[index];
  return index;
}

// The probability that ChooseLight at r returns light `index`.
PT_HDI float LightChoicePmf(const SceneView& s, const LightRef& r, uint32_t index) {
  if (s.lightTree.sampler == uint32_t(LightSampler::kBvh) && index < s.lightTree.boundedCount)
    return LightTreeShare(s) * LightTreePmf(s, r, index);
  return InfiniteLightPmf(s, index);
}

// ---- Spheres: the cone of directions a sphere subtends from an outside point ----

struct SphereCone {
  float sin2ThetaMax, sinThetaMax, cosThetaMax, oneMinusCosThetaMax;
};

// False when refP is inside the sphere (then it is sampled uniformly by area instead).
// 1 - cos is computed as sin^2 / (1 + cos), exact for tiny or distant spheres where the
// direct difference cancels, so no small-angle approximation (and no bias) is needed.
PT_HDI bool SphereConeFrom(const Sphere& sp, vec3 refP, SphereCone* c) {
  vec3 d = sp.center - refP;
  float dist2 = glm::dot(d, d);
  float r2 = sp.radius * sp.radius;
  if (dist2 <= r2) return false;
  c->sin2ThetaMax = r2 / dist2;
  c->sinThetaMax = sqrtf(c->sin2ThetaMax);
  c->cosThetaMax = SafeSqrt(1.0f - c->sin2ThetaMax);
  c->oneMinusCosThetaMax = c->sin2ThetaMax / (1.0f + c->cosThetaMax);
  return true;
}

PT_HDI float SphereConePdf(const SphereCone& c) {
  return 1.0f / (2.0f * kPi * c.oneMinusCosThetaMax);
}

// Uniform direction in the cone, mapped to the visible point of the sphere it hits (pbrt-v4
// Sphere::Sample): alpha is the angle at the centre between the axis and that point.
PT_HDI void SampleSphereCone(const Sphere& sp, vec3 refP, const SphereCone& c, vec2 u,
                             vec3* p, vec3* n) {
  float omc = u.x * c.oneMinusCosThetaMax;  // 1 - cos(theta), accurate near the axis
  float cosTheta = 1.0f - omc;
  float sin2Theta = omc * (2.0f - omc);
  float cosAlpha = sin2Theta / c.sinThetaMax +
                   cosTheta * SafeSqrt(1.0f - sin2Theta / c.sin2ThetaMax);
  float sinAlpha = SafeSqrt(1.0f - cosAlpha * cosAlpha);
  float phi = u.y * 2.0f * kPi;
  vec3 w = vec3(sinAlpha * cosf(phi), sinAlpha * sinf(phi), cosAlpha);
  Frame frame = Frame::FromZ(glm::normalize(sp.center - refP));
  *n = frame.FromLocal(-w);
  *p = sp.center + sp.radius * (*n);
}

// ---- Area-measure to solid-angle conversion ----

// Solid-angle pdf of picking pLight uniformly on an area from refP, with the one-sided test.
// Returns 0 when the point faces away (and the light is one-sided) or is degenerate.
PT_HDI float AreaToSolidAnglePdf(vec3 refP, vec3 pLight, vec3 nLight, float area,
                                 bool twoSided) {
  vec3 d = pLight - refP;
  float dist2 = glm::dot(d, d);
  if (dist2 == 0.0f || area <= 0.0f) return 0.0f;
  float cosLight = -glm::dot(nLight, d) / sqrtf(dist2);
  if (cosLight == 0.0f || (!twoSided && cosLight < 0.0f)) return 0.0f;
  float pdf = dist2 / (fabsf(cosLight) * area);
  return pdf < kInfinity ? pdf : 0.0f;  // false for inf and NaN
}

// Solid-angle pdf (without the choice probability) of an area light's point as
// SampleAreaLight below would produce it from refP.
PT_HDI float AreaLightPdf(const SceneView& s, const Light& light, vec3 refP, vec3 pLight,
                          vec3 nLight) {
  const PrimRef& prim = s.prims[light.prim];
  bool twoSided = light.twoSided != 0;
  switch (prim.Type()) {
    case ShapeType::kQuad:
      return AreaToSolidAnglePdf(refP, pLight, nLight, QuadArea(s.quads[prim.Index()]), twoSided);
    case ShapeType::kTriangle:
      return AreaToSolidAnglePdf(refP, pLight, nLight,
                                 TriangleArea(LightTriangle(s, light, prim.Index())), twoSided);
    case ShapeType::kSphere: {
      const Sphere& sp = s.spheres[prim.Index()];
      SphereCone cone;
      if (SphereConeFrom(sp, refP, &cone)) return SphereConePdf(cone);
      return AreaToSolidAnglePdf(refP, pLight, nLight, SphereArea(sp), twoSided);
    }
  }
  return 0.0f;
}

// Picks a point on an area light's shape: *p, unit *n (the shape's front), its shape
// parameters *param (triangle (b1, b2), quad (s, t); 0 on spheres) and *solidAnglePdf.
PT_HDI bool SampleAreaLight(const SceneView& s, const Light& light, vec3 refP, vec2 u, vec3* p,
                            vec3* n, vec2* param, float* solidAnglePdf) {
  const PrimRef& prim = s.prims[light.prim];
  *param = vec2(0.0f);
  switch (prim.Type()) {
    case ShapeType::kQuad: {
      const Quad& q = s.quads[prim.Index()];
      *p = q.origin + u.x * q.u + u.y * q.v;
      *n = glm::normalize(glm::cross(q.u, q.v));
      *param = u;
      break;
    }
    case ShapeType::kTriangle: {
      const Triangle t = LightTriangle(s, light, prim.Index());
      vec2 b = SampleUniformTriangle(u);
      *p = b.x * t.p0 + b.y * t.p1 + (1.0f - b.x - b.y) * t.p2;
      *n = glm::normalize(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
      *param = vec2(b.y, 1.0f - b.x - b.y);  // weights of p1 and p2
      break;
    }
    case ShapeType::kSphere: {
      const Sphere& sp = s.spheres[prim.Index()];
      SphereCone cone;
      if (SphereConeFrom(sp, refP, &cone)) {
        SampleSphereCone(sp, refP, cone, u, p, n);
        *solidAnglePdf = SphereConePdf(cone);  // the visible cap faces refP by construction
        return *solidAnglePdf < kInfinity;
      }
      *n = SampleUniformSphere(u);  // refP inside: uniform by area
      *p = sp.center + sp.radius * (*n);
      break;
    }
  }
  *solidAnglePdf = AreaLightPdf(s, light, refP, *p, *n);
  return *solidAnglePdf > 0.0f;
}

// ---- Distant lights ----

// Whether unit w lies in the directional light's cone: |w - axis|^2 = 2 (1 - cos), exact for
// the sun's tiny cone where a dot product near 1 would round the rim away.
PT_HDI bool InDirectionalCone(const Light& light, vec3 w) {
  vec3 d = w - light.direction;
  return glm::dot(d, d) <= 2.0f * light.oneMinusCos;
}

// Solid-angle pdf of the cone's uniform sampling (0 for a delta light).
PT_HDI float DirectionalConePdf(const Light& light) {
  return light.IsDeltaDirection() ? 0.0f : 1.0f / (2.0f * kPi * light.oneMinusCos);
}

// A direction uniform in the cone, from 1 - cos(theta) so that the sun's disk keeps its size.
PT_HDI vec3 SampleDirectionalCone(const Light& light, vec2 u) {
  float omc = u.x * light.oneMinusCos;
  float sinTheta = SafeSqrt(omc * (2.0f - omc));
  float phi = 2.0f * kPi * u.y;
  vec3 local(sinTheta * cosf(phi), sinTheta * sinf(phi), 1.0f - omc);
  return glm::normalize(Frame::FromZ(light.direction).FromLocal(local));
}

// Fills the parts of a sample from a light at infinity along wi.
PT_HDI void SetInfiniteSample(const SceneView& s, vec3 refP, vec3 wi, LightLiSample* out) {
  out->wi = wi;
  // A point surely outside the scene's bounding sphere; shadow rays are still traced
  // unbounded (isInfinite).
  float reach = 2.0f * (s.sceneRadius + glm::length(refP - s.sceneCenter));
  out->pLight = refP + reach * wi;
  out->nLight = -wi;
  out->isInfinite = true;
}

// ---- Entry points ----

// Chooses a light for r with uLight (and uRefresh: ChooseLight) and a point or direction on
// it with u. Returns false when the sample carries no light (back face of a one-sided
// emitter, degenerate geometry, no lights); the caller then skips the shadow ray.
template <bool kMap = true>
PT_HDI bool SampleLightLi(const SceneView& s, const LightRef& r, float uLight, float uRefresh,
                          vec2 u, LightLiSample* out) {
  const vec3 refP = r.p;
  float pmf = 0.0f;
  int index = ChooseLight(s, r, uLight, uRefresh, &pmf);
  if (index < 0 || !(pmf > 0.0f)) return false;
  const Light& light = s.lights[index];
  out->lightIndex = index;
  out->isDelta = false;
  out->isInfinite = false;
  switch (light.type) {
    case LightType::kArea: {
      vec3 p, n;
      vec2 param;
      float pdf;
      if (!SampleAreaLight(s, light, refP, u, &p, &n, &param, &pdf)) return false;
      out->wi = glm::normalize(p - refP);
      out->L = AreaLightRadiance(s, light, param, p, n);
      out->pdf = pmf * pdf;
      out->pLight = p;
      out->nLight = n;
      return true;
    }
    case LightType::kPoint:
    case LightType::kSpot: {
      vec3 d = light.position - refP;
      float dist2 = glm::dot(d, d);
      if (dist2 == 0.0f) return false;
      out->wi = d / sqrtf(dist2);
      vec3 intensity = light.intensity;
      if (light.type == LightType::kSpot) {
        float falloff = light.SpotFalloff(-glm::dot(light.direction, out->wi));
        if (!(falloff > 0.0f)) return false;  // outside the cone: no shadow ray
        intensity *= falloff;
      }
      out->L = intensity / dist2;
      out->pdf = pmf;
      out->pLight = light.position;
      out->nLight = vec3(0.0f);
      out->isDelta = true;
      return true;
    }
    case LightType::kBackground: {
      SetInfiniteSample(s, refP, SampleUniformSphere(u), out);
      out->L = light.radiance;
      out->pdf = pmf * UniformSpherePdf();
      return true;
    }
    case LightType::kDirectional: {
      bool delta = light.IsDeltaDirection();
      SetInfiniteSample(s, refP, delta ? light.direction : SampleDirectionalCone(light, u), out);
      out->L = delta ? light.irradiance : light.radiance;
      out->pdf = delta ? pmf : pmf * DirectionalConePdf(light);
      out->isDelta = delta;
      return true;
    }
    case LightType::kEnvironmentMap: {
      if constexpr (kMap) {
        vec3 wi, L;
        float pdf;
        if (!SampleEnvMap(s, u, &wi, &L, &pdf)) return false;
        SetInfiniteSample(s, refP, wi, out);
        out->L = L;
        out->pdf = pmf * pdf;
        return true;
      }
      return false;
    }
  }
  return false;
}

// The same from a point with no receiver normal (the BVH's importance then ignores the
// orientation there; LightPdf must be given the same reference).
template <bool kMap = true>
PT_HDI bool SampleLightLi(const SceneView& s, vec3 refP, float uLight, vec2 u,
                          LightLiSample* out) {
  LightRef r;
  r.p = refP;
  return SampleLightLi<kMap>(s, r, uLight, -1.0f, u, out);
}

// Solid-angle pdf, with the choice probability, that SampleLightLi from r produces the point
// pLight (unit geometric normal nLight, the shape's front) of light lightIndex. For MIS when a
// BSDF-sampled ray hits an emitter. 0 for delta lights (they cannot be hit). Lights at
// infinity take the direction towards pLight.
template <bool kMap = true>
PT_HDI float LightPdf(const SceneView& s, int lightIndex, const LightRef& r, vec3 pLight,
                      vec3 nLight) {
  if (lightIndex < 0 || uint32_t(lightIndex) >= s.lightCount) return 0.0f;
  const vec3 refP = r.p;
  const Light& light = s.lights[lightIndex];
  float pmf = LightChoicePmf(s, r, uint32_t(lightIndex));
  if (!(pmf > 0.0f)) return 0.0f;
  switch (light.type) {
    case LightType::kArea: return pmf * AreaLightPdf(s, light, refP, pLight, nLight);
    case LightType::kPoint:
    case LightType::kSpot: return 0.0f;
    case LightType::kBackground: return pmf * UniformSpherePdf();
    case LightType::kDirectional: {
      vec3 w = glm::normalize(pLight - refP);
      return InDirectionalCone(light, w) ? pmf * DirectionalConePdf(light) : 0.0f;
    }
    case LightType::kEnvironmentMap:
      if constexpr (kMap) return pmf * EnvMapPdf(s, glm::normalize(pLight - refP));
      return 0.0f;
  }
  return 0.0f;
}

template <bool kMap = true>
PT_HDI float LightPdf(const SceneView& s, int lightIndex, vec3 refP, vec3 pLight, vec3 nLight) {
  LightRef r;
  r.p = refP;
  return LightPdf<kMap>(s, lightIndex, r, pLight, nLight);
}

// Pdf of an escaped ray's direction under the background light's sampling (choice included);
// 0 when the background is black (it is then not a light).
PT_HDI float BackgroundLightPdf(const SceneView& s) {
  if (s.backgroundLight < 0) return 0.0f;
  return InfiniteLightPmf(s, uint32_t(s.backgroundLight)) * UniformSpherePdf();
}

// Radiance of the environment map along an escaped direction w, and the pdf (choice
// included) that next-event estimation samples w; zero when there is no map light.
template <bool kMap>
PT_HDI vec3 EnvMapLightLe(const SceneView& s, vec3 w, float* lightPdf) {
  *lightPdf = 0.0f;
  if constexpr (kMap) {
    if (s.env.light < 0) return vec3(0.0f);
    *lightPdf = InfiniteLightPmf(s, uint32_t(s.env.light)) * EnvMapPdf(s, w);
    return EnvMapLe(s, w);
  }
  return vec3(0.0f);
}

}  // namespace pt
