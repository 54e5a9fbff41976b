#include "src/media/media_tables.h"

namespace pt {
namespace {

uint32_t ShapeInterface(const MediaDesc& md, const PrimRef& ref) {
  const std::vector<uint32_t>* table = nullptr;
  switch (ref.Type()) {
    case ShapeType::kTriangle: table = &md.triangleInterfaces; break;
    case ShapeType::kQuad: table = &md.quadInterfaces; break;
    default: table = &md.sphereInterfaces; break;
  }
  return ref.Index() < table->size() ? (*table)[ref.Index()] : 0u;
}

}  // namespace

std::vector<uint32_t> BuildPrimMedia(const Scene& scene, uint32_t* invisible) {
  const MediaDesc& md = scene.desc.media;
  *invisible = 0;
  if (!md.HasInterfaces()) return {};
  std::vector<uint32_t> out(scene.prims.size(), 0u);
  const uint32_t outsideShift = kMediumFieldBits;
  for (size_t i = 0; i < scene.prims.size(); ++i) {
    uint32_t iface = ShapeInterface(md, scene.prims[i]);
    if (((iface >> outsideShift) & kMediumFieldMask) == kOutsideIsCamera) {
      iface &= ~(kMediumFieldMask << outsideShift);
      iface |= uint32_t(md.cameraMedium + 1) << outsideShift;
    }
    if (IsInvisible(iface)) ++*invisible;
    out[i] = iface;
  }
  return out;
}

void ApplyFog(float sigmaS, SceneDesc* desc) {
  MediaDesc& md = desc->media;
  Medium fog;
  fog.type = MediumType::kHomogeneous;
  fog.sigmaS = vec3(sigmaS);
  md.media.push_back(fog);
  md.names.push_back("--fog");
  md.boundsLo.push_back(vec3(-kInfinity));
  md.boundsHi.push_back(vec3(kInfinity));
  md.cameraMedium = int32_t(md.media.size() - 1);
}

}  // namespace pt
