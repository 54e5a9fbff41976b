// How bright a textured emitter is on average, for its light power (host only).
#pragma once

#include "src/scene/scene_view.h"

namespace pt {

// Mean of a glTF emissive texture (linear RGB) over primitive `prim`; (1, 1, 1) where the
// material has none. A triangle with texture coordinates averages the texels whose centres
// its UV triangle covers, at the finest mip level where its UV bounding box spans at most
// kEmissionTexelBudget texels (a coarser level's texel is the box-filtered mean of the finer
// ones, so the mean holds at any level); one that covers no texel centre there reads the
// texture bilinearly at its centroid. A triangle whose texels are all black therefore gets 0,
// and is no light: next-event estimation never chooses it (its emission, if filtering bleeds
// some in at its edges, is still found by BSDF sampling at full weight, so nothing is lost).
// Other primitives average 16 stratified lookups. Alpha is not counted (it only lowers power).
vec3 MeanEmissiveTexture(const SceneView& view, const PrimRef& prim);

constexpr int kEmissionTexelBudget = 256;

}  // namespace pt
