// The launches of MediaPass (src/integrator/media_pass.h): included only by the translation
// units that instantiate it per backend (cuda/media_cuda.cu, cpu_backend/media_cpu.cpp).
#pragma once

#include "src/integrator/media_pass.h"
#include "src/integrator/stages/medium.h"
#include "src/integrator/stages/medium_shade.h"
#include "src/integrator/stages/medium_shadow.h"

namespace pt {

// The medium stage over queue[0, n).
template <typename Backend>
void MediaPass<Backend>::Sample(const SceneView& scene, const IntegratorParams& params,
                              const WaveInfo& wave, PathState ps, const uint32_t* queue,
                              uint32_t n, Counter* counters) {
  MediaView mv = view_;
  MediaState ms = state_;
  backend_.ParallelFor(Stage::kMedium, n, [=] PT_HD(uint32_t i) {
    SampleMediumPath(scene, mv, params, wave, ps, ms, queue[i], counters);
  });
}

// Shade in the scene's feature class, with or without environment-map code (the general
// class always has it), in queue order.
template <typename Backend>
void MediaPass<Backend>::Shade(FeatureClass c, bool envMap, const SceneView& scene,
                             const IntegratorParams& params, const WaveInfo& wave,
                             PathState ps, const uint32_t* queue, uint32_t n) {
  switch (c) {
    case FeatureClass::kDiffuse:
      if (envMap) ShadeAll<FeatureClass::kDiffuse, true>(scene, params, wave, ps, queue, n);
      else ShadeAll<FeatureClass::kDiffuse, false>(scene, params, wave, ps, queue, n);
      break;
    case FeatureClass::kSmooth:
      if (envMap) ShadeAll<FeatureClass::kSmooth, true>(scene, params, wave, ps, queue, n);
      else ShadeAll<FeatureClass::kSmooth, false>(scene, params, wave, ps, queue, n);
      break;
    default: ShadeAll<FeatureClass::kGeneral, true>(scene, params, wave, ps, queue, n); break;
  }
}

template <typename Backend>
template <FeatureClass C, bool kMap>
void MediaPass<Backend>::ShadeAll(const SceneView& scene, const IntegratorParams& params,
                                const WaveInfo& wave, PathState ps, const uint32_t* queue,
                                uint32_t n) {
  MediaView mv = view_;
  MediaState ms = state_;
  backend_.ParallelFor(Stage::kShade, n, [=] PT_HD(uint32_t i) {
    ShadeMediumScenePath<C, kMap>(scene, mv, params, wave, ps, ms, queue[i]);
  });
}

// Shadow rays with their transmittance.
template <typename Backend>
void MediaPass<Backend>::TraceShadows(const SceneView& scene, const WaveInfo& wave, PathState ps,
                                    const uint32_t* queue, uint32_t n, Counter* counters) {
  MediaView mv = view_;
  MediaState ms = state_;
  backend_.ParallelFor(Stage::kShadow, n, [=] PT_HD(uint32_t i) {
    TraceShadowRayInMedia(scene, mv, wave, ps, ms, queue[i], counters);
  });
}

}  // namespace pt
