#include "src/integrator/shade_order.h"

#include <algorithm>

namespace pt {

ShadeKeys MakeShadeKeys(const Scene& scene) {
  const std::vector<Material>& materials = scene.desc.materials;
  uint32_t count = uint32_t(materials.size());
  ShadeKeys k;
  k.materialKey.resize(count);
  // Rank by (queue, index): a stable counting sort of the materials by queue.
  std::array<uint32_t, kShadeQueueCount + 1> perQueue{};
  for (const Material& m : materials) ++perQueue[ShadeQueueOf(m)];
  uint32_t next = 0;
  for (uint32_t q = 0; q < kShadeQueueCount; ++q) {
    k.firstKey[q] = next;
    next += perQueue[q];
  }
  k.escapedKey = count;
  k.firstKey[kEscapedQueue] = count;
  k.finishedKey = k.firstKey[kShadeQueueCount] = count + 1;
  k.keyCount = count + 2;
  std::array<uint32_t, kShadeQueueCount> cursor{};
  for (uint32_t m = 0; m < count; ++m) {
    uint32_t q = ShadeQueueOf(materials[m]);
    k.materialKey[m] = k.firstKey[q] + cursor[q]++;
  }
  while ((1u << k.keyBits) < k.keyCount) ++k.keyBits;
  std::vector<bool> used(count, false);
  for (const PrimRef& prim : scene.prims)
    if (prim.material < count) used[prim.material] = true;
  for (const InstanceDesc& instance : scene.desc.instances)  // overrides shade with their own
    if (instance.material >= 0 && uint32_t(instance.material) < count) used[instance.material] = true;
  for (uint32_t m = 0; m < count; ++m)
    if (used[m]) k.queuesUsed |= 1u << ShadeQueueOf(materials[m]);
  k.queuesUsed |= 1u << kEscapedQueue;
  return k;
}

SortMethod ResolveSortMethod(SortMethod asked, uint32_t keyCount) {
  bool countingFits = keyCount <= kCountingSortMaxKeys;
  if (asked == SortMethod::kAuto) return countingFits ? SortMethod::kCounting : SortMethod::kRadix;
  if (asked == SortMethod::kCounting && !countingFits) return SortMethod::kRadix;
  return asked;
}

uint32_t SurfaceQueuesUsed(const ShadeKeys& keys) {
  uint32_t n = 0;
  for (uint32_t q = 0; q < kEscapedQueue; ++q) n += keys.Uses(q) ? 1u : 0u;
  return n;
}

bool CostlyQueue(uint32_t q) {
  if (q >= kEscapedQueue) return false;
  MaterialType t = QueueMaterialType(q);
  return QueueTextured(q) || t == MaterialType::kPlastic || t == MaterialType::kGltfPbr;
}

// Most surface queues for which auto launches a kernel per queue.
constexpr uint32_t kMaxQueuesForQueueMode = 3;

SortChoice ChooseSortMode(SortMode asked, const ShadeKeys& keys, FeatureClass featureClass,
                          bool lockstep) {
  if (asked != SortMode::kAuto) return SortChoice{asked, "asked for"};
  // A CPU thread shades its paths one after the other: no divergence to remove, and the
  // queue kernels' extra passes cost (measured 0.8x on the material zoo).
  if (!lockstep) return SortChoice{SortMode::kOff, "no lockstep lanes on this backend"};
  uint32_t queues = SurfaceQueuesUsed(keys);
  bool costly = false;
  for (uint32_t q = 0; q < kEscapedQueue; ++q) costly = costly || (keys.Uses(q) && CostlyQueue(q));
  // Ordering costs a pass over the keys per bounce and the queue kernels' launches; it pays
  // where neighbouring threads would otherwise run different, costly material code, and where
  // a costly queue's own kernel (compiled for its material type alone, fewer registers) beats
  // the general one: one textured glTF queue measured 1.23x on DamagedHelmet (H100). Cheap
  // materials (the diffuse and smooth variants) diverge little (issue 11: sorting lost 0.61x
  // and 0.77x on the Cornell box and the bunny).
  if (!IsGeneralClass(featureClass) || !costly)
    return SortChoice{SortMode::kOff, "no costly material (textured, plastic or glTF)"};
  if (queues < 2)
    return SortChoice{SortMode::kQueues, "one costly shade queue: its own kernel"};
  // Past a few queues, one launch per queue per bounce (each over few paths) costs more than
  // the registers the specialised kernels save: the material zoo's 7 queues ran 0.94x of one
  // ordered kernel, while 2 and 3 queues tied or won (H100, benchmarks/RESULTS.md).
  if (queues > kMaxQueuesForQueueMode)
    return SortChoice{SortMode::kMaterial, std::to_string(queues) +
                                               " shade queues: one ordered kernel beats a launch each"};
  return SortChoice{SortMode::kQueues, std::to_string(queues) +
                                           " shade queues, costly materials among them"};
}

const char* SortModeName(SortMode mode) {
  switch (mode) {
    case SortMode::kOff: return "off";
    case SortMode::kMaterial: return "material";
    case SortMode::kQueues: return "queues";
    default: return "auto";
  }
}

const char* SortMethodName(SortMethod method) {
  switch (method) {
    case SortMethod::kCounting: return "counting";
    case SortMethod::kRadix: return "radix";
    case SortMethod::kRadixFullWidth: return "radix32";
    default: return "auto";
  }
}

const char* ShadeQueueName(uint32_t q) {
  static const char* kNames[kShadeQueueCount] = {
      "diffuse",    "diffuse_textured",    "emissive", "emissive_textured",
      "conductor",  "conductor_textured",  "dielectric", "dielectric_textured",
      "plastic",    "plastic_textured",    "gltf_pbr", "gltf_pbr_textured", "escaped"};
  static_assert(kShadeQueueCount == 13, "a name per shade queue");
  return q < kShadeQueueCount ? kNames[q] : "any";
}

}  // namespace pt
