// The material at a surface point: a copy of the material's constants with its textures and
// vertex colours applied, and, for a glTF normal texture, the shading normal perturbed.
#pragma once

#include "src/geometry/interaction.h"
#include "src/materials/surface_attributes.h"

namespace pt {

// Below this cosine to the geometric normal a normal-mapped shading normal is bent back up: a
// normal at or past the horizon has no consistent hemisphere (GeometricallyConsistent in the
// shade stage still guards every direction).
constexpr float kMinNormalMapCosine = 0.01f;

// Tangent-space normal texel (RGB in [0, 1], XY scaled by `scale`) to a unit normal around ns.
PT_HDI vec3 PerturbNormal(const SceneView& s, PrimRef ref, const SurfaceInteraction& si,
                          uint32_t set, vec3 texel, float scale) {
  vec3 t, b;
  if (!TangentFrameAt(s, ref, si.uv, set, si.ns, &t, &b)) return si.ns;
  vec3 c = 2.0f * texel - vec3(1.0f);
  vec3 n = (c.x * scale) * t + (c.y * scale) * b + c.z * si.ns;
  float len2 = glm::dot(n, n);
  if (!(len2 > 0.0f && len2 < kInfinity)) return si.ns;
  n /= sqrtf(len2);
  float cosG = glm::dot(n, si.ng);
  if (cosG < kMinNormalMapCosine) n = glm::normalize(n + (kMinNormalMapCosine - cosG) * si.ng);
  return n;
}

// glTF: baseColor = factor x texture x COLOR_0; metallic and roughness x texture B and G;
// emission x texture; transmission x texture R; the normal texture moves si->ns.
PT_HDI void ResolveGltfTextures(const SceneView& s, PrimRef ref, SurfaceInteraction* si,
                                Material* m) {
  m->albedo *= vec3(VertexColorAt(s, ref, si->uv));
  bool textured = m->baseColorTexture >= 0 || m->metallicRoughnessTexture >= 0 ||
                  m->emissiveTexture >= 0 || m->transmissionTexture >= 0 || m->normalTexture >= 0;
  if (!textured) return;  // no coordinates needed
  TexCoords tc = TexCoordsAt(s, ref, si->uv, FootprintWidth(s.camera, si->p, si->ng));
  if (m->baseColorTexture >= 0) m->albedo *= vec3(SampleTextureRef(s, m->baseColorTexture, tc));
  if (m->metallicRoughnessTexture >= 0) {
    vec4 mr = SampleTextureRef(s, m->metallicRoughnessTexture, tc);
    m->roughness *= mr.y;
    m->metallic *= mr.z;
  }
  if (m->emissiveTexture >= 0) m->radiance *= vec3(SampleTextureRef(s, m->emissiveTexture, tc));
  if (m->transmissionTexture >= 0)
    m->transmission *= SampleTextureRef(s, m->transmissionTexture, tc).x;
  if (m->normalTexture >= 0) {
    vec3 texel(SampleTextureRef(s, m->normalTexture, tc));
    si->ns = PerturbNormal(s, ref, *si, s.textureRefs[m->normalTexture].texCoord, texel,
                           m->normalScale);
  }
}

// The material of primitive ref at si, textures applied. kType and kMayHaveTextures are what
// a shade kernel of one queue knows at compile time (its type; whether its materials have
// textures); the defaults read both from the material.
template <MaterialType kType = MaterialType::kCount, bool kMayHaveTextures = true>
PT_HDI Material ResolveMaterial(const SceneView& s, PrimRef ref, SurfaceInteraction* si) {
  Material m = s.materials[si->material];
  if (TypeOf<kType>(m) == MaterialType::kGltfPbr) {
    if constexpr (kMayHaveTextures) ResolveGltfTextures(s, ref, si, &m);
    else m.albedo *= vec3(VertexColorAt(s, ref, si->uv));  // all that applies without textures
  } else if (kMayHaveTextures && m.baseColorTexture >= 0) {
    TexCoords tc = TexCoordsAt(s, ref, si->uv, FootprintWidth(s.camera, si->p, si->ng));
    m.albedo *= vec3(SampleTextureRef(s, m.baseColorTexture, tc));
  }
  return m;
}

}  // namespace pt
