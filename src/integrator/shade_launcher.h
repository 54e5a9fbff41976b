// The shade stage's launches in the order --sort asks for: one kernel over the queue as it
// stands (off); one kernel over the queue ordered by material key (material); or the queue
// ordered the same way and one kernel per shade queue the scene uses, each compiled for its
// queue only (queues), as pbrt-v4's wavefront integrator. The queue itself is never
// reordered: the order is a second index list read by shading alone, so intersection, shadow
// rays and compaction keep their pixel-coherent slot order. Each queue's kernel reads its
// range of that list from the device (found there by binary search), so a bounce needs no
// host synchronisation; kernels of empty queues exit at once.
//
// The one-kernel modes run the diffuse and smooth classes with or without environment-map
// code (envMap); the general class and the queue kernels always have it (a scene without a
// map skips it at run time), which keeps the kernel count down.
//
// Launchers are public because nvcc's extended lambdas may not live in private members.
#pragma once

#include <utility>

#include "src/integrator/shade_order.h"
#include "src/integrator/stage_id.h"
#include "src/integrator/stages/intersect.h"
#include "src/integrator/stages/shade.h"

namespace pt {

template <typename Backend>
class ShadeLauncher {
 public:
  template <typename T>
  using Buffer = typename Backend::template Buffer<T>;

  // What every shade kernel reads.
  struct Inputs {
    SceneView scene;
    IntegratorParams params;
    PathState ps;
  };

  explicit ShadeLauncher(Backend& backend) : backend_(backend) {}

  // The scene's material keys (again after every scene change) and the ordering method.
  void SetScene(const Scene& scene, SortMethod method) {
    keys_ = MakeShadeKeys(scene);
    std::copy(keys_.firstKey.begin(), keys_.firstKey.end(), table_.firstKey);
    method_ = ResolveSortMethod(method, keys_.keyCount);
    materialKeys_.Upload(keys_.materialKey);
    ordering_ = false;
  }
  const ShadeKeys& Keys() const { return keys_; }
  SortMethod Method() const { return method_; }

  // The ordering's buffers, the first time a mode orders (paths in flight: capacity).
  void EnsureOrdering(size_t capacity) {
    if (ordering_ && orderedSlots_.Size() == capacity) return;
    ordering_ = true;
    for (Buffer<uint32_t>* b : {&sortKeys_, &orderedKeys_, &orderedSlots_}) b->Resize(capacity);
    ranges_.Resize(kShadeQueueCount + 1);
    scratchBytes_ = backend_.ReserveOrdering(
        OrderShape{method_, keys_.keyBits, keys_.keyCount, uint32_t(capacity)});
  }
  // Bytes per path this launcher holds: sort keys, the ordered list and its keys, scratch.
  size_t BytesPerPath() const {
    size_t n = orderedSlots_.Size();
    return n ? 3 * sizeof(uint32_t) + (scratchBytes_ + n - 1) / n : 0;
  }

  // Where intersect writes each queue position's key: nowhere when mode does not order.
  SortKeyOutput KeyOutput(SortMode mode) {
    if (mode == SortMode::kOff) return SortKeyOutput{nullptr, nullptr};
    return SortKeyOutput{sortKeys_.Data(), materialKeys_.Data()};
  }

  // Shades queue[0, n) after intersect wrote KeyOutput(mode); returns the paths it ordered.
  // flat: the scene has no vertex normals and no light tree (ShadeSurface's kFlat).
  uint32_t Shade(SortMode mode, FeatureClass c, bool envMap, bool flat, const WaveInfo& wave,
                 const Inputs& in, const uint32_t* queue, uint32_t n) {
    if (n == 0) return 0;
    if (mode == SortMode::kOff) {
      ShadeClass(c, envMap, flat, wave, in, queue, n);
      return 0;
    }
    Order(queue, n);
    if (mode == SortMode::kMaterial) {
      ShadeClass(c, envMap, flat, wave, in, orderedSlots_.Data(), n);
    } else {
      FindQueueRanges(n);
      switch (QueueClass(c)) {
        case FeatureClass::kDiffuse: ShadeQueues<FeatureClass::kDiffuse>(wave, in, n); break;
        case FeatureClass::kSmooth: ShadeQueues<FeatureClass::kSmooth>(wave, in, n); break;
        case FeatureClass::kLayered: ShadeQueues<FeatureClass::kLayered>(wave, in, n); break;
        default: ShadeQueues<FeatureClass::kGeneral>(wave, in, n); break;
      }
    }
    return n;
  }

  // The class whose queue kernels cover every queue the scene uses: c, or the general one
  // where c would leave a used queue without a kernel.
  FeatureClass QueueClass(FeatureClass c) const {
    for (uint32_t q = 0; q < kShadeQueueCount; ++q)
      if (keys_.Uses(q) && !ClassAdmitsQueue(c, q)) return FeatureClass::kGeneral;
    return c;
  }

  // The queue's slots ordered by key into orderedSlots_ (keys alongside).
  void Order(const uint32_t* queue, uint32_t n) {
    OrderShape shape{method_, keys_.keyBits, keys_.keyCount, n};
    backend_.OrderByKey(Stage::kSort, shape,
                        OrderArrays{sortKeys_.Data(), queue, orderedKeys_.Data(),
                                    orderedSlots_.Data()});
  }

  // ranges_[q] = the first ordered position of queue q; ranges_[kShadeQueueCount] = the end
  // of the paths to shade (finished ones follow).
  void FindQueueRanges(uint32_t n) {
    const uint32_t* keys = orderedKeys_.Data();
    uint32_t* ranges = ranges_.Data();
    QueueKeyTable table = table_;
    backend_.ParallelFor(Stage::kSort, kShadeQueueCount + 1, [=] PT_HD(uint32_t q) {
      ranges[q] = QueueStart(keys, n, table.firstKey[q]);
    });
  }

  // Whether Shade runs a flat copy: the diffuse and smooth classes have one for scenes without
  // an environment map (boxes of quads and spheres), whose curved-shading fold's registers
  // cost every shaded path (the Cornell box's shade stage 7.49 -> 6.92 ms on an H100,
  // benchmarks/RESULTS.md); the queue kernels have none. The statistics say what this says.
  static bool RunsFlatCopy(SortMode mode, FeatureClass c, bool envMap, bool flat) {
    return mode != SortMode::kQueues && flat && !envMap &&
           (c == FeatureClass::kDiffuse || c == FeatureClass::kSmooth);
  }

  void ShadeClass(FeatureClass c, bool envMap, bool flat, const WaveInfo& wave, const Inputs& in,
                  const uint32_t* order, uint32_t n) {
    if (RunsFlatCopy(SortMode::kOff, c, envMap, flat)) {
      if (c == FeatureClass::kDiffuse)
        ShadeAll<FeatureClass::kDiffuse, false, true>(wave, in, order, n);
      else
        ShadeAll<FeatureClass::kSmooth, false, true>(wave, in, order, n);
      return;
    }
    switch (c) {
      case FeatureClass::kDiffuse:
        if (envMap) ShadeAll<FeatureClass::kDiffuse, true>(wave, in, order, n);
        else ShadeAll<FeatureClass::kDiffuse, false>(wave, in, order, n);
        break;
      case FeatureClass::kSmooth:
        if (envMap) ShadeAll<FeatureClass::kSmooth, true>(wave, in, order, n);
        else ShadeAll<FeatureClass::kSmooth, false>(wave, in, order, n);
        break;
      case FeatureClass::kLayered: ShadeAll<FeatureClass::kLayered, true>(wave, in, order, n); break;
      default: ShadeAll<FeatureClass::kGeneral, true>(wave, in, order, n); break;
    }
  }

  template <FeatureClass C, bool kMap, bool kFlat = false>
  void ShadeAll(const WaveInfo& wave, const Inputs& in, const uint32_t* order, uint32_t n) {
    Inputs inputs = in;
    backend_.ParallelFor(Stage::kShade, n, [=] PT_HD(uint32_t i) {
      ShadePath<C, kAnyQueue, kMap, kFlat>(inputs.scene, inputs.params, wave, inputs.ps,
                                           order[i]);
    });
  }

  template <FeatureClass C>
  void ShadeQueues(const WaveInfo& wave, const Inputs& in, uint32_t n) {
    ShadeQueueList<C>(wave, in, n, std::make_integer_sequence<uint32_t, kShadeQueueCount>{});
  }

  template <FeatureClass C, uint32_t... Q>
  void ShadeQueueList(const WaveInfo& wave, const Inputs& in, uint32_t n,
                      std::integer_sequence<uint32_t, Q...>) {
    (ShadeQueueIfUsed<C, Q>(wave, in, n), ...);
  }

  // One kernel for queue Q, compiled only where class C can meet it, launched only where the
  // scene uses it; its range [ranges_[Q], ranges_[Q + 1]) is read on the device.
  // The layered class runs its own kernels only for the queues whose materials can be layered
  // (glTF, conductors with energy compensation); the others are the general class's kernels.
  template <FeatureClass C, uint32_t Q>
  void ShadeQueueIfUsed(const WaveInfo& wave, const Inputs& in, uint32_t n) {
    if constexpr (C == FeatureClass::kLayered && !QueueMayBeLayered(Q)) {
      ShadeQueueIfUsed<FeatureClass::kGeneral, Q>(wave, in, n);
    } else if constexpr (ClassAdmitsQueue(C, Q)) {
      if (!keys_.Uses(Q)) return;
      Inputs inputs = in;
      const uint32_t* order = orderedSlots_.Data();
      backend_.ParallelForRange(ShadeQueueStage(Q), n, ranges_.Data() + Q,
                                [=] PT_HD(uint32_t i) {
                                  ShadePath<C, Q>(inputs.scene, inputs.params, wave, inputs.ps,
                                                  order[i]);
                                });
    }
  }

 private:
  Backend& backend_;
  ShadeKeys keys_;
  QueueKeyTable table_{};
  SortMethod method_ = SortMethod::kCounting;
  bool ordering_ = false;
  size_t scratchBytes_ = 0;
  Buffer<uint32_t> materialKeys_, sortKeys_, orderedKeys_, orderedSlots_, ranges_;
};

}  // namespace pt
