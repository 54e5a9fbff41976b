// The glTF extension parameters at a surface point (layered_material.h): factors times their
// textures (each through the channel the extension names), the clearcoat normal (its own
// normal texture about the interpolated normal, or that normal: glTF applies the base normal
// texture to the base only) and the anisotropy direction in the tangent frame. An unlit
// material shows its base colour: it becomes its radiance.
#pragma once

#include "src/materials/layered_material.h"
#include "src/materials/resolve.h"

namespace pt {

// Direction (world) of the anisotropy at the point: the tangent-space direction (+X, or the
// texture's RG in [-1, 1]) rotated by `rotation`, in the tangent frame of UV set `set` about
// the shading normal. False without a tangent frame.
PT_HDI bool AnisotropyDirection(const SceneView& s, PrimRef ref, const SurfaceInteraction& si,
                                uint32_t set, vec2 dir, float rotation, vec3* out) {
  vec3 t, b;
  if (!TangentFrameAt(s, ref, si.uv, set, si.ns, &t, &b)) return false;
  float c = cosf(rotation), sn = sinf(rotation);
  vec2 r(c * dir.x - sn * dir.y, sn * dir.x + c * dir.y);
  vec3 d = r.x * t + r.y * b;
  float len2 = glm::dot(d, d);
  if (!(len2 > 0.0f)) return false;
  *out = d / sqrtf(len2);
  return true;
}

PT_HDI bool HasExtensionTextures(const GltfMaterialExtension& e) {
  return e.specularTexture >= 0 || e.specularColorTexture >= 0 || e.clearcoatTexture >= 0 ||
         e.clearcoatRoughnessTexture >= 0 || e.clearcoatNormalTexture >= 0 ||
         e.sheenColorTexture >= 0 || e.sheenRoughnessTexture >= 0 || e.iridescenceTexture >= 0 ||
         e.iridescenceThicknessTexture >= 0 || e.anisotropyTexture >= 0 ||
         e.diffuseTransmissionTexture >= 0 || e.diffuseTransmissionColorTexture >= 0;
}

// Reads texture slot t (-1: none) at tc.
struct LayerTextures {
  const SceneView& s;
  TexCoords tc;
  PT_HDI vec4 At(int32_t t) const { return t >= 0 ? SampleTextureRef(s, t, tc) : vec4(1.0f); }
};

PT_HDI void ResolveClearcoat(const LayerTextures& tex, const GltfMaterialExtension& e, PrimRef ref,
                             const SurfaceInteraction& si, vec3 nsBase, GltfLayers* x) {
  x->clearcoat = e.clearcoat * tex.At(e.clearcoatTexture).x;
  x->clearcoatRoughness = e.clearcoatRoughness * tex.At(e.clearcoatRoughnessTexture).y;
  x->coatNormal = nsBase;
  if (e.clearcoatNormalTexture >= 0) {
    SurfaceInteraction base = si;
    base.ns = nsBase;
    x->coatNormal = PerturbNormal(tex.s, ref, base, tex.s.textureRefs[e.clearcoatNormalTexture].texCoord,
                                  vec3(tex.At(e.clearcoatNormalTexture)), e.clearcoatNormalScale);
  }
}

PT_HDI void ResolveAnisotropy(const LayerTextures& tex, const GltfMaterialExtension& e, PrimRef ref,
                              const SurfaceInteraction& si, GltfLayers* x) {
  vec2 dir(1.0f, 0.0f);
  x->anisotropy = e.anisotropy;
  uint32_t set = 0;
  if (e.anisotropyTexture >= 0) {
    vec4 a = tex.At(e.anisotropyTexture);
    dir = vec2(2.0f * a.x - 1.0f, 2.0f * a.y - 1.0f);
    x->anisotropy *= a.z;
    set = tex.s.textureRefs[e.anisotropyTexture].texCoord;
  }
  if (!AnisotropyDirection(tex.s, ref, si, set, dir, e.anisotropyRotation, &x->anisotropyDir))
    x->anisotropy = 0.0f;  // no tangent frame (no UVs, no TANGENT): isotropic
}

// Fills m->layers from the material's extension entry; nsBase is the shading normal before the
// base normal texture moved it.
PT_HDI void ResolveGltfLayers(const SceneView& s, PrimRef ref, const SurfaceInteraction& si,
                              vec3 nsBase, LayeredMaterial* m) {
  if (m->flags & kMaterialUnlit) m->radiance = m->albedo;
  if (m->ext < 0) return;
  const GltfMaterialExtension& e = s.materialExts[m->ext];
  GltfLayers& x = m->layers;
  x.mask = e.mask;
  LayerTextures tex{s, TexCoords{}};
  if (HasExtensionTextures(e))
    tex.tc = TexCoordsAt(s, ref, si.uv, FootprintWidth(s.camera, si.p, si.ng));
  if (e.mask & kExtSpecular) {
    x.specular = e.specular * tex.At(e.specularTexture).w;
    x.specularColor = e.specularColor * vec3(tex.At(e.specularColorTexture));
  }
  if (e.mask & kExtClearcoat) ResolveClearcoat(tex, e, ref, si, nsBase, &x);
  if (e.mask & kExtSheen) {
    x.sheenColor = e.sheenColor * vec3(tex.At(e.sheenColorTexture));
    x.sheenRoughness = e.sheenRoughness * tex.At(e.sheenRoughnessTexture).w;
  }
  if (e.mask & kExtIridescence) {
    x.iridescence = e.iridescence * tex.At(e.iridescenceTexture).x;
    x.iridescenceIor = e.iridescenceIor;
    x.thickness = e.iridescenceThicknessTexture >= 0
                      ? e.thicknessMin + (e.thicknessMax - e.thicknessMin) *
                                             tex.At(e.iridescenceThicknessTexture).y
                      : e.thicknessMax;
  }
  if (e.mask & kExtAnisotropy) ResolveAnisotropy(tex, e, ref, si, &x);
  if (e.mask & kExtDiffuseTransmission) {
    x.diffuseTransmission = e.diffuseTransmission * tex.At(e.diffuseTransmissionTexture).w;
    x.diffuseTransmissionColor =
        e.diffuseTransmissionColor * vec3(tex.At(e.diffuseTransmissionColorTexture));
  }
}

}  // namespace pt
