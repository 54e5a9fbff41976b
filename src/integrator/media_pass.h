// What a scene with participating media adds to the wavefront (src/integrator/wavefront.h):
// its media arrays on the backend, the media path state, and the launches of the medium stage
// and of the media variants of shade and shadow. A scene without media allocates none of it
// and runs none of these kernels: its stages are compiled and launched exactly as before.
//
// The launches (media_pass_impl.h) are compiled in translation units of their own, explicitly
// instantiated per backend (cuda/media_cuda.cu, cpu_backend/media_cpu.cpp), so the media
// kernels build beside the others and a change to them rebuilds nothing else. Launchers are
// public because nvcc's extended lambdas may not live in private members.
#pragma once

#include <vector>

#include "src/integrator/media_state.h"
#include "src/integrator/path_state.h"
#include "src/integrator/stage_id.h"
#include "src/integrator/wave.h"
#include "src/media/media_tables.h"
#include "src/media/medium.h"
#include "src/scene/effects.h"

namespace pt {

template <typename Backend>
class MediaPass {
 public:
  template <typename T>
  using Buffer = typename Backend::template Buffer<T>;

  explicit MediaPass(Backend& backend) : backend_(backend) {}

  // The scene's media tables where the stages read them (again after every scene change).
  void SetScene(const Scene& scene) {
    const MediaDesc& md = scene.desc.media;
    active_ = md.Active();
    TransmittanceEstimator estimator = view_.estimator;
    view_ = MediaView{};
    view_.estimator = estimator;
    if (!active_) return;
    primMediaHost_ = BuildPrimMedia(scene, &view_.invisibleCount);
    view_.media = Place(md.media, media_);
    view_.grids = Place(md.grids, grids_);
    view_.cells = Place(md.cells, cells_);
    view_.voxels = Place(md.voxels, voxels_);
    view_.primMedia = Place(primMediaHost_, primMedia_);
    view_.mediumCount = uint32_t(md.media.size());
    view_.cameraMedium = md.cameraMedium;
  }
  void SetEstimator(TransmittanceEstimator e) { view_.estimator = e; }
  bool Active() const { return active_; }

  void AllocatePaths(size_t n) {
    size_t size = active_ ? n : 0;
    medium_.Resize(size);
    shadowMedium_.Resize(size);
    rHat_.Resize(size);
    state_ = MediaState{medium_.Data(), shadowMedium_.Data(), rHat_.Data()};
  }
  size_t BytesPerPath() const { return active_ ? kMediaStateBytes : 0; }

  // The medium stage over queue[0, n).
  void Sample(const SceneView& scene, const IntegratorParams& params, const WaveInfo& wave,
              PathState ps, const uint32_t* queue, uint32_t n, Counter* counters);

  // Shade in the scene's feature class, with or without environment-map code (the general
  // class always has it), in queue order.
  void Shade(FeatureClass c, bool envMap, const SceneView& scene, const IntegratorParams& params,
             const WaveInfo& wave, PathState ps, const uint32_t* queue, uint32_t n);

  template <FeatureClass C, bool kMap>
  void ShadeAll(const SceneView& scene, const IntegratorParams& params, const WaveInfo& wave,
                PathState ps, const uint32_t* queue, uint32_t n);

  // Shadow rays with their transmittance.
  void TraceShadows(const SceneView& scene, const WaveInfo& wave, PathState ps,
                    const uint32_t* queue, uint32_t n, Counter* counters);

 private:
  // Host vectors are read in place by a host backend, copied to the device otherwise.
  template <typename T>
  const T* Place(const std::vector<T>& host, Buffer<T>& buffer) {
    if constexpr (Backend::kHostMemory) {
      return host.empty() ? nullptr : host.data();
    } else {
      buffer.Upload(host);
      return host.empty() ? nullptr : buffer.Data();
    }
  }

  Backend& backend_;
  bool active_ = false;
  MediaView view_{};
  MediaState state_{};
  std::vector<uint32_t> primMediaHost_;
  Buffer<Medium> media_;
  Buffer<GridMedium> grids_;
  Buffer<GridCell> cells_;
  Buffer<float> voxels_;
  Buffer<uint32_t> primMedia_, medium_, shadowMedium_;
  Buffer<vec3> rHat_;
};

}  // namespace pt
