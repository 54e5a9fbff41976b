// A render that persists on one backend: it renders ranges of samples into its film, hands
// out and takes back the raw film (to resume a render, or to reduce films across processes),
// and takes camera, option and scene changes between ranges (a live preview). The one-shot
// RenderCpu / RenderCuda are a session's Render(). Host-side only: a virtual interface is
// fine here, since no device code sees it.
#pragma once

#include <memory>
#include <stdexcept>

#include "src/integrator/render_api.h"

namespace pt {

class RenderSession {
 public:
  virtual ~RenderSession() = default;

  // The whole render the options ask for (adaptive batches, time limit, callbacks); after
  // LoadFilm it continues each pixel from its own count.
  virtual RenderResult Render() = 0;

  // Every pixel of the crop takes samples [begin, end), in sample order. Returns the samples
  // taken (fewer when the stop callback or time limit ends it between waves).
  virtual uint64_t RenderRange(uint32_t begin, uint32_t end) = 0;
  // Samples [begin, end) of a coarse image of width x height pixels (no more than the film's,
  // the same field of view) into the film's first width x height entries, as a film of that
  // width: a live preview's quick frames. Reset the film before and after.
  virtual uint64_t RenderCoarse(uint32_t width, uint32_t height, uint32_t begin, uint32_t end) {
    (void)width, (void)height, (void)begin, (void)end;
    throw std::logic_error("this session renders no coarse images");
  }
  // Each pixel takes samples from its own count up to spp (resuming an interrupted render).
  virtual uint64_t RenderUpTo(uint32_t spp) = 0;

  FilmState SaveFilm() {
    FilmState film;
    SaveFilmInto(film);
    return film;
  }
  // Into the film's own arrays: saving over a film of the same size reuses its memory (a
  // 1080p film is 124 MB, whose fresh pages cost more than the copy).
  virtual void SaveFilmInto(FilmState& film) = 0;
  // A copy of the film kept on the session's device (waited for), and its save into `film`,
  // which may run on another thread while this one clears the film and renders on: a render
  // lane's leaf is saved while the next renders. The next SnapshotFilm must wait until that
  // save has returned.
  virtual void SnapshotFilm() = 0;
  virtual void SaveSnapshotInto(FilmState& film) = 0;
  // Throws std::invalid_argument when the film's size or feature channels do not match.
  virtual void LoadFilm(const FilmState& film) = 0;
  virtual void ResetFilm() = 0;
  virtual FilmImage Image() = 0;  // the film as mean and variance

  // Statistics of everything rendered so far (counters, stage times, memory).
  virtual RenderStats Stats() = 0;

  // Between ranges: a new camera; new options (flags, integrator, specialisation; film
  // precision, feature buffers, crop and paths in flight stay as created); the Scene the
  // session was made from was edited (materials, settings such as max_depth): re-read it.
  virtual void SetCamera(const Camera& camera) = 0;
  virtual void SetOptions(const RenderOptions& options) = 0;
  virtual void SceneChanged() = 0;
  // Only instance transforms changed, and RebuildTopLevel (src/scene/instances.h) ran on the
  // Scene: re-reads the top level alone (instances, top-level BVH, light probabilities), far
  // cheaper than SceneChanged for a scene of large meshes.
  virtual void TopLevelChanged() = 0;
  // Only Scene::desc.materials changed, and BuildLightTable ran on the Scene again: re-reads
  // the materials, the primitives' light indices and the light table, not the geometry (far
  // cheaper than SceneChanged on the GPU for a scene of large meshes).
  virtual void MaterialsChanged() = 0;
};

// Sessions on each backend. The Scene must outlive the session. MakeCudaSession throws
// BackendUnavailable when the CUDA backend is not built or no GPU is present.
std::unique_ptr<RenderSession> MakeCpuSession(const Scene& scene, const RenderOptions& options,
                                              const RenderCallbacks& callbacks = {});
std::unique_ptr<RenderSession> MakeCudaSession(const Scene& scene, const RenderOptions& options,
                                               const RenderCallbacks& callbacks = {});

}  // namespace pt
