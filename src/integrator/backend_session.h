// RenderSession on a backend: owns the backend and the generic wavefront integrator over it.
// Each backend's entry file instantiates it once (cpu_backend/render_cpu.cpp,
// cuda/render_cuda.cu).
#pragma once

#include <utility>

#include "src/integrator/render_session.h"
#include "src/integrator/wavefront.h"

namespace pt {

template <typename Backend>
class BackendSession final : public RenderSession {
 public:
  template <typename... BackendArgs>
  BackendSession(const Scene& scene, const RenderOptions& options,
                 const RenderCallbacks& callbacks, BackendArgs&&... backendArgs)
      : backend_(std::forward<BackendArgs>(backendArgs)...),
        integrator_(backend_, scene, options, callbacks) {}

  RenderResult Render() override { return integrator_.Render(); }
  uint64_t RenderRange(uint32_t begin, uint32_t end) override {
    return integrator_.RenderRange(begin, end);
  }
  uint64_t RenderCoarse(uint32_t width, uint32_t height, uint32_t begin, uint32_t end) override {
    return integrator_.RenderCoarse(width, height, begin, end);
  }
  uint64_t RenderUpTo(uint32_t spp) override { return integrator_.RenderUpTo(spp); }
  void SaveFilmInto(FilmState& film) override { integrator_.SaveFilmInto(film); }
  void SnapshotFilm() override { integrator_.SnapshotFilm(); }
  void SaveSnapshotInto(FilmState& film) override {
    backend_.BindThread();  // the saving thread may be another one
    integrator_.SaveSnapshotInto(film);
  }
  void LoadFilm(const FilmState& film) override { integrator_.LoadFilm(film); }
  void ResetFilm() override { integrator_.ResetFilm(); }
  FilmImage Image() override { return integrator_.ResolveFilm(); }
  RenderStats Stats() override { return integrator_.Stats(); }
  void SetCamera(const Camera& camera) override { integrator_.SetCamera(camera); }
  void SetOptions(const RenderOptions& options) override { integrator_.ApplyOptions(options); }
  void SceneChanged() override { integrator_.SceneChanged(); }
  void TopLevelChanged() override { integrator_.TopLevelChanged(); }
  void MaterialsChanged() override { integrator_.MaterialsChanged(); }

 private:
  Backend backend_;
  WavefrontIntegrator<Backend> integrator_;
};

}  // namespace pt
