// Shading normals that keep their energy without leaking it: the "fold" of the BSDF about the
// geometric surface, used by the shade stage wherever the shading normal differs from the
// geometric one (flat shading never reaches this code).
//
// A lobe samples and evaluates in the shading frame, but a ray must leave on the side of the
// geometric surface the lobe means: reflection on the viewer's side, transmission across. A
// direction the two surfaces disagree about (it lies in the wedge between them) cannot be
// traced as it is; ending the path there loses that wedge's energy (up to a quarter of a
// diffuse surface's light for a 60 degree tilt). Instead each such direction is replaced by its
// mirror image across the geometric surface's plane, which lies on the side the lobe means.
// The mirror is its own inverse and keeps solid angle, so the folded BSDF
//   f~(d) |cos~(d)| = [d agreed] f(d) |cos d| + [M d disputed] f(M d) |cos M d|
// (M d: d mirrored; cosines to the shading normal) has the density
//   p~(d) = [d agreed] p(d) + [M d disputed] p(M d)
// under "sample the lobe, then mirror a disputed sample", and reflects exactly the energy the
// lobe reflects in its own frame: a white Lambertian surface under a uniform sky stays white
// however its normals tilt. Next-event estimation evaluates f~ and p~ and BSDF sampling draws
// from p~, so the two combine by MIS as before. Nothing crosses the geometric surface unless
// a transmission lobe sent it, so a closed opaque mesh cannot leak light.
#pragma once

#include "src/core/math.h"
#include "src/geometry/interaction.h"
#include "src/integrator/stages/bsdf_variant.h"

namespace pt {

// Exact comparison: flat shading copies ng into ns, so only curved shading differs.
PT_HDI bool ShadingNormalIsGeometric(const SurfaceInteraction& si) {
  return si.ns.x == si.ng.x && si.ns.y == si.ng.y && si.ns.z == si.ng.z;
}

// w mirrored across the geometric surface's plane.
PT_HDI vec3 MirrorAcrossSurface(vec3 w, vec3 ng) { return w - (2.0f * glm::dot(w, ng)) * ng; }

// Whether the geometric surface puts wi where the shading frame does: on wo's side for a pair
// on the same shading side, across otherwise.
PT_HDI bool SidesAgree(float woDotNg, float wiDotNg, float woLocalZ, float wiLocalZ) {
  return (woDotNg * wiDotNg > 0.0f) == (woLocalZ * wiLocalZ > 0.0f);
}

// The folded f~ |cos~| and p~ at a world direction wi (wiLocal in the shading frame), for
// next-event estimation. pdf may be null when the caller needs no density.
template <FeatureClass C, uint32_t Q>
PT_HDI vec3 FoldedEvalCos(const HitMaterial<C>& m, const SurfaceInteraction& si, const Frame& frame,
                          vec3 woLocal, float woDotNg, vec3 wi, vec3 wiLocal, float* pdf) {
  vec3 f(0.0f);
  float p = 0.0f;
  if (SidesAgree(woDotNg, glm::dot(wi, si.ng), woLocal.z, wiLocal.z)) {
    f = EvalBsdfFor<C, Q>(m, woLocal, wiLocal) * fabsf(wiLocal.z);
    if (pdf) p = PdfBsdfFor<C, Q>(m, woLocal, wiLocal);
  }
  vec3 mirrored = MirrorAcrossSurface(wi, si.ng);
  vec3 mLocal = frame.ToLocal(mirrored);
  if (!SidesAgree(woDotNg, glm::dot(mirrored, si.ng), woLocal.z, mLocal.z)) {
    f += EvalBsdfFor<C, Q>(m, woLocal, mLocal) * fabsf(mLocal.z);
    if (pdf) p += PdfBsdfFor<C, Q>(m, woLocal, mLocal);
  }
  if (pdf) *pdf = p;
  return f;
}

// A sampled direction bs (wi: it in world space) folded: wi becomes the member of {wi, M wi}
// on the side the lobe means, and the path weight f~ |cos~| / p~ goes to *weight, p~ to *pdf.
// A delta lobe's sample is mirrored with its weight unchanged (no density to fold).
template <FeatureClass C, uint32_t Q>
PT_HDI void FoldSample(const HitMaterial<C>& m, const SurfaceInteraction& si, const Frame& frame,
                       vec3 woLocal, float woDotNg, const BsdfSample& bs, vec3* wi,
                       vec3* weight, float* pdf) {
  vec3 mirrored = MirrorAcrossSurface(*wi, si.ng);
  bool agreed = SidesAgree(woDotNg, glm::dot(*wi, si.ng), woLocal.z, bs.wi.z);
  vec3 fCos = bs.f * fabsf(bs.wi.z);
  *pdf = bs.pdf;
  if (!bs.isDelta) {
    // The pair's other member adds to f~ and p~ when the lobe could have drawn it as well
    // (it lies on the same shading side): see the derivation above.
    vec3 mLocal = frame.ToLocal(mirrored);
    if (mLocal.z * bs.wi.z > 0.0f) {
      fCos += EvalBsdfFor<C, Q>(m, woLocal, mLocal) * fabsf(mLocal.z);
      *pdf += PdfBsdfFor<C, Q>(m, woLocal, mLocal);
    }
  }
  *weight = fCos / *pdf;
  if (!agreed) *wi = mirrored;
}

}  // namespace pt
