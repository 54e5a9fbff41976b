#include "src/distributed/chunked_render.h"

#include <algorithm>
#include <chrono>

#include "src/distributed/film_assembler.h"
#include "src/integrator/wave_plan.h"

namespace pt {
namespace {

// Merging films between leaves stalls the render; it is memory-bound and splits well.
constexpr int kChunkMergeThreads = 4;

}  // namespace

LeafRender RenderLeafSamples(RenderSession& session, const ChunkTree& tree, uint32_t leaf) {
  using Clock = std::chrono::steady_clock;
  ChunkNode node = ChunkTree::Leaf(leaf);
  Clock::time_point t0 = Clock::now();
  session.ResetFilm();
  LeafRender r;
  r.samples = session.RenderRange(tree.FirstSample(node), tree.EndSample(node));
  r.renderMs = Ms(t0, Clock::now());
  return r;
}

LeafResult RenderLeaf(RenderSession& session, const ChunkTree& tree, uint32_t leaf,
                      FilmState reuse) {
  LeafRender rendered = RenderLeafSamples(session, tree, leaf);
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  session.SaveFilmInto(reuse);
  LeafResult r;
  r.samples = rendered.samples;
  r.renderMs = rendered.renderMs;
  r.film = std::move(reuse);
  r.saveMs = Ms(t0, std::chrono::steady_clock::now());
  return r;
}

RenderResult RenderChunked(const SessionMaker& make, const Scene& scene,
                           const RenderOptions& options, const RenderCallbacks& callbacks,
                           uint32_t chunks) {
  ChunkTree tree(uint32_t(scene.desc.render.spp), chunks);
  uint64_t base = 0;  // samples of the leaves finished before the current one
  uint64_t pixels = 0;
  RenderCallbacks inner = callbacks;
  if (callbacks.onProgress) {
    inner.onProgress = [&](uint64_t done, uint64_t) {
      callbacks.onProgress(base + done, pixels * tree.Spp());
    };
  }
  std::unique_ptr<RenderSession> session = make(scene, options, inner);
  FilmPool pool;
  FilmAssembler assembler(tree, kChunkMergeThreads, &pool);
  FilmState empty = session->SaveFilm();
  pixels = empty.PixelCount();
  for (uint32_t leaf = 0; leaf < tree.Chunks(); ++leaf) {
    if (callbacks.shouldStop && callbacks.shouldStop()) break;
    uint64_t expected = pixels * (tree.EndSample(ChunkTree::Leaf(leaf)) -
                                  tree.FirstSample(ChunkTree::Leaf(leaf)));
    LeafResult r = RenderLeaf(*session, tree, leaf, pool.Take());
    base += r.samples;
    assembler.Add(ChunkTree::Leaf(leaf), std::move(r.film));
    if (r.samples < expected) break;  // stopped: Ctrl-C or the time limit
  }
  RenderResult result;
  result.image = ResolveFilmImage(assembler.Finish(std::move(empty)));
  result.stats = session->Stats();
  result.stats.samples = base;
  uint64_t filmSamples = 0;
  for (uint32_t c : result.image.samples) filmSamples += c;
  result.stats.sppMean = double(filmSamples) / double(std::max<uint64_t>(1, pixels));
  return result;
}

bool AdaptiveRequested(const Scene& scene, const RenderOptions& options) {
  if (options.adaptive != Toggle::kAuto) return options.adaptive == Toggle::kOn;
  return scene.desc.render.adaptive.enabled;
}

}  // namespace pt
