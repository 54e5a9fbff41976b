// One process rendering a ChunkTree's leaves in turn and merging them along the tree: the
// image an MPI job with the same --chunks gives, whatever its ranks (`pathtracer --chunks N`).
#pragma once

#include <chrono>
#include <functional>
#include <memory>

#include "src/distributed/chunk_tree.h"
#include "src/integrator/render_session.h"

namespace pt {

using SessionMaker = std::function<std::unique_ptr<RenderSession>(
    const Scene&, const RenderOptions&, const RenderCallbacks&)>;

// Milliseconds between two steady-clock times (leaf and rank timings).
inline double Ms(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// One leaf's samples rendered into the session's film, cleared first: the samples taken
// (fewer than the leaf holds when the session's stop callback or time limit ended it between
// waves) and the milliseconds it took.
struct LeafRender {
  uint64_t samples = 0;
  double renderMs = 0.0;
};
LeafRender RenderLeafSamples(RenderSession& session, const ChunkTree& tree, uint32_t leaf);

// The same, and the film saved into `reuse`'s memory (a film from a FilmPool), with the
// milliseconds the save took.
struct LeafResult {
  uint64_t samples = 0;
  FilmState film;
  double renderMs = 0.0, saveMs = 0.0;
};
LeafResult RenderLeaf(RenderSession& session, const ChunkTree& tree, uint32_t leaf,
                      FilmState reuse = {});

// Every leaf on one session made with callbacks that see the whole render's progress. The
// options' adaptive sampling, preview and reference must be off (the app refuses them).
RenderResult RenderChunked(const SessionMaker& make, const Scene& scene,
                           const RenderOptions& options, const RenderCallbacks& callbacks,
                           uint32_t chunks);

// Whether the options and scene ask for adaptive sampling (which the chunked and distributed
// renders do not do yet).
bool AdaptiveRequested(const Scene& scene, const RenderOptions& options);

}  // namespace pt
