#include "src/integrator/wave_plan.h"

#include <algorithm>

#include "src/core/parallel_ranges.h"
#include "src/integrator/film.h"

namespace pt {

namespace {

// Waves of `tile` pixels x `samples` samples: every pixel of a tile when the pixels fit in
// maxPaths, as many of their samples as fit.
struct WaveShape {
  uint32_t tile = 0, samples = 1;
};

WaveShape ShapeOf(uint32_t pixelCount, uint32_t sampleCount, size_t maxPaths) {
  maxPaths = std::max<size_t>(maxPaths, 1);
  WaveShape shape;
  shape.tile = uint32_t(std::min<size_t>(pixelCount, maxPaths));
  if (shape.tile == pixelCount && pixelCount > 0)
    shape.samples =
        uint32_t(std::clamp<size_t>(maxPaths / pixelCount, 1, std::max(sampleCount, 1u)));
  return shape;
}

}  // namespace

void AppendWaves(const WaveInfo& base, const uint32_t* pixelList, uint32_t pixelCount,
                 uint32_t sampleStart, uint32_t sampleCount, size_t maxPaths,
                 std::vector<WaveInfo>& waves) {
  auto [tile, samplesPerWave] = ShapeOf(pixelCount, sampleCount, maxPaths);
  uint32_t end = sampleStart + sampleCount;
  for (uint32_t s = sampleStart; s < end; s += samplesPerWave) {
    for (uint32_t p = 0; p < pixelCount; p += tile) {
      WaveInfo w = base;
      w.pixelList = pixelList ? pixelList + p : nullptr;
      w.pixelStart = pixelList ? 0 : p;
      w.pixelCount = std::min(tile, pixelCount - p);
      w.sampleStart = s;
      w.samplesInWave = std::min(samplesPerWave, end - s);
      waves.push_back(w);
    }
  }
}

WavePlan MakeWavePlan(const RenderSettings& render, const CropWindow& crop,
                      size_t defaultPathsInFlight, size_t requestedPathsInFlight) {
  WavePlan plan;
  CropWindow c = crop.Empty() ? CropWindow{0, 0, render.width, render.height} : crop;
  plan.cropX0 = uint32_t(c.x0);
  plan.cropY0 = uint32_t(c.y0);
  plan.cropWidth = uint32_t(c.x1 - c.x0);
  plan.cropHeight = uint32_t(c.y1 - c.y0);
  plan.cropPixels = plan.cropWidth * plan.cropHeight;
  plan.spp = uint32_t(render.spp);
  plan.maxPaths = requestedPathsInFlight ? requestedPathsInFlight : defaultPathsInFlight;

  WaveInfo& base = plan.base;
  base = WaveInfo{};
  base.cropX0 = plan.cropX0;
  base.cropY0 = plan.cropY0;
  base.cropWidth = plan.cropWidth;
  base.imageWidth = uint32_t(render.width);
  base.imageHeight = uint32_t(render.height);
  base.seed = render.seed;
  // The largest wave AppendWaves cuts for the whole crop (the first; no list of them is kept:
  // each render step cuts its own from `base`).
  if (plan.spp > 0) {
    WaveShape shape = ShapeOf(plan.cropPixels, plan.spp, plan.maxPaths);
    plan.pathCapacity = shape.tile * shape.samples;
  }
  return plan;
}

namespace {

// FilmView's pointers are writable (stage bodies accumulate through them); this one is only
// read. Null for a channel the film does not keep.
template <typename T>
T* ReadOnly(const std::vector<T>& v) {
  return v.empty() ? nullptr : const_cast<T*>(v.data());
}

// A saved film seen as a double film, for ResolveFilmPixel: the host's resolve and the
// backends' are one body, so they give the same floats.
FilmView ReadOnlyView(const FilmState& f) {
  return FilmView{nullptr,           nullptr,         ReadOnly(f.mean),      ReadOnly(f.m2),
                  ReadOnly(f.lumMean), ReadOnly(f.lumM2), ReadOnly(f.count), ReadOnly(f.albedoSum),
                  ReadOnly(f.normalSum), ReadOnly(f.depthSum), ReadOnly(f.evenSum),
                  ReadOnly(f.evenCount), ReadOnly(f.residualMean), ReadOnly(f.residualM2),
                  ReadOnly(f.evenEmissionSum)};
}

}  // namespace

// Every core resolves a range of pixels: a 1080p film took ~30 ms on one (issue 28's time to
// image), most of it the doubles' reads and the divisions.
FilmImage ResolveFilmImage(const FilmState& film) {
  FilmImage img;
  img.width = int(film.width);
  img.height = int(film.height);
  size_t n = film.PixelCount();
  img.rgb.assign(3 * n, 0.0f);
  img.variance.assign(3 * n, 0.0f);
  img.samples = film.count;
  bool features = !film.albedoSum.empty();
  if (features) {
    img.albedo.assign(3 * n, 0.0f);
    img.normal.assign(3 * n, 0.0f);
    img.depth.assign(n, 0.0f);
  }
  bool halves = !film.evenSum.empty();
  if (halves) {
    img.evenRgb.assign(3 * n, 0.0f);
    img.evenSamples = film.evenCount;
    for (std::vector<float>* v : {&img.emission, &img.evenEmission, &img.residualVariance})
      v->assign(3 * n, 0.0f);
  }
  const FilmView view = ReadOnlyView(film);
  const ImageView out{img.rgb.data(),    img.variance.data(),
                      features ? img.albedo.data() : nullptr,
                      features ? img.normal.data() : nullptr,
                      features ? img.depth.data() : nullptr,
                      halves ? img.evenRgb.data() : nullptr,
                      halves ? img.emission.data() : nullptr,
                      halves ? img.evenEmission.data() : nullptr,
                      halves ? img.residualVariance.data() : nullptr};
  ForRangesOnThreads(n, 0, size_t(1) << 16, [&](size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i) ResolveFilmPixel(view, out, uint32_t(i));
  });
  return img;
}

}  // namespace pt
