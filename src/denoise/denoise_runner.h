// The denoiser over a backend: its planes in the backend's memory, and the passes of
// nlm_stages.h launched through the backend's ParallelFor. Generic like the integrator;
// cpu_backend/denoise_cpu.cpp and cuda/denoise_cuda.cu instantiate it.
//
// Lambdas copy what they need, never `this` (nvcc's extended lambdas run on the device).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "src/denoise/denoise_settings.h"
#include "src/denoise/denoiser.h"
#include "src/denoise/denoise_tiles.h"
#include "src/denoise/nlm_outliers.h"
#include "src/denoise/nlm_stages.h"
#include "src/denoise/nlm_variance.h"
#include "src/integrator/render_api.h"
#include "src/integrator/stage_id.h"

namespace pt {

template <typename Backend>
class DenoiseRunner {
 public:
  template <typename T>
  using Buffer = typename Backend::template Buffer<T>;

  // A GPU runs each pass over the whole image (it wants every pixel in each launch); the CPU
  // (Backend::kHostMemory) runs them tile by tile as `tiling` says (denoise_tiles.h).
  explicit DenoiseRunner(Backend& backend, const DenoiseTiling& tiling = {})
      : backend_(backend), tiling_(tiling) {}

  // image.denoised := the filtered image. Throws std::invalid_argument on a bad image or
  // settings.
  void Run(FilmImage& image, const DenoiseSettings& settings) {
    std::string problem = DenoiseInputProblem(image);
    if (problem.empty()) problem = DenoiseSettingsProblem(settings);
    if (!problem.empty()) throw std::invalid_argument("denoise: " + problem);
    Layout(uint32_t(image.width), uint32_t(image.height), settings);
    Upload(image, settings.keepSeenEmission);
    backend_.Synchronize();
    double before = backend_.Times().accumulate;
    Fill(settings);
    if constexpr (Backend::kHostMemory) {
      Tiles(settings);
    } else {
      for (int dy = -settings.radius; dy <= settings.radius; ++dy) {
        for (int dx = -settings.radius; dx <= settings.radius; dx += kDenoiseGroup) {
          Offsets(0, planes_.height, Group(dy, dx, settings), settings);
        }
      }
    }
    Finish(image, settings);
    passesMs_ = backend_.Times().accumulate - before;
  }

  // The passes' time in the last Run (each backend times its own launches).
  double PassesMs() const { return passesMs_; }

  // The steps of Run, public because nvcc's extended lambdas may not live in private member
  // functions.
  // The group of offsets (dy, dx .. dx + 7), within the window.
  DenoiseOffsets Group(int dy, int dx, const DenoiseSettings& s) const {
    return DenoiseOffsets::Group(dy, dx, s.radius, planes_.stride);
  }

  // The padded planes, one allocation.
  void Layout(uint32_t width, uint32_t height, const DenoiseSettings& s) {
    DenoisePlanes& d = planes_;
    d.width = width;
    d.height = height;
    // (At least the selection's radius: its window reads the error planes' padding.)
    d.padX = uint32_t(std::max(s.radius + s.patchRadius, s.selectRadius));
    d.padY = d.padX + 1;  // a neighbour of a padding column wraps into the next row: in range
    d.stride = width + 2 * d.padX;
    d.rows = height + 2 * d.padY;
    size_t plane = size_t(d.stride) * d.rows;
    constexpr size_t kPlanes = 2 * 3 + 2 * 3 + 3 + 3 + 1 + 3 + kDenoiseCandidates * (2 * 4 + 1);
    // The CPU's distance planes: each task's own, over a tile's rows and the patches' reach.
    size_t dist = 2 * kDenoiseGroup * plane;
    if constexpr (Backend::kHostMemory) {
      tasks_ = uint32_t(backend_.ThreadCount());
      distRegion_ = size_t(TileRows() + 2 * s.patchRadius) * d.stride + 2 * s.patchRadius;
      dist = 2 * size_t(MaxGroup(s)) * distRegion_ * tasks_;
    }
    if (store_.Size() != plane * kPlanes + dist) {
      // The GPU's whole-image passes read distances at the edge they never wrote: zeros keep
      // them finite. The CPU's passes read only what they wrote, and zeroing 420 MB costs.
      if constexpr (Backend::kHostMemory) {
        store_.ResizeForOverwrite(plane * kPlanes + dist);
      } else {
        store_.Resize(plane * kPlanes + dist);
        store_.Zero();
      }
    }
    float* next = store_.Data();
    auto take = [&] {
      float* p = next;
      next += plane;
      return p;
    };
    for (int h = 0; h < kDenoiseHalves; ++h) {
      for (int c = 0; c < 3; ++c) d.half[h][c] = take();
      for (int c = 0; c < 3; ++c) d.halfVar[h][c] = take();
      if constexpr (!Backend::kHostMemory) {
        for (int g = 0; g < kDenoiseGroup; ++g) d.dist[g][h] = take();
      }
    }
    for (int k = 0; k < kDenoiseCandidates; ++k) {
      for (int h = 0; h < kDenoiseHalves; ++h)
        for (int c = 0; c < 4; ++c) d.sum[k][h][c] = take();
      d.error[k] = take();
    }
    for (int c = 0; c < 3; ++c) {
      d.albedo[c] = take();
      d.normal[c] = take();
      d.featureScale[c] = take();
    }
    d.depth = take();
    distStore_ = next;  // the tasks' distance planes, last (Tiles points below them)
  }

  // The film's arrays where the passes read them: on the CPU in place (a copy would fault in
  // and fill 116 MB more at 1080p), on a GPU copied to the device.
  // keepEmission: the passes filter the residual (settings.keepSeenEmission, where the image
  // has the emission planes).
  void Upload(const FilmImage& image, bool keepEmission) {
    const bool residual = keepEmission && !image.emission.empty();
    if constexpr (Backend::kHostMemory) {
      input_ = DenoiseInput{image.rgb.data(),
                            image.variance.data(),
                            image.samples.data(),
                            image.evenRgb.data(),
                            image.evenSamples.data(),
                            image.albedo.data(),
                            image.normal.data(),
                            image.depth.data(),
                            residual ? image.emission.data() : nullptr,
                            residual ? image.evenEmission.data() : nullptr,
                            residual ? image.residualVariance.data() : nullptr};
    } else {
      rgb_.Upload(image.rgb);
      variance_.Upload(image.variance);
      samples_.Upload(image.samples);
      evenRgb_.Upload(image.evenRgb);
      evenSamples_.Upload(image.evenSamples);
      albedo_.Upload(image.albedo);
      normal_.Upload(image.normal);
      depth_.Upload(image.depth);
      if (residual) {
        emission_.Upload(image.emission);
        evenEmission_.Upload(image.evenEmission);
        residualVariance_.Upload(image.residualVariance);
      }
      input_ = DenoiseInput{rgb_.Data(),
                            variance_.Data(),
                            samples_.Data(),
                            evenRgb_.Data(),
                            evenSamples_.Data(),
                            albedo_.Data(),
                            normal_.Data(),
                            depth_.Data(),
                            residual ? emission_.Data() : nullptr,
                            residual ? evenEmission_.Data() : nullptr,
                            residual ? residualVariance_.Data() : nullptr};
    }
  }

  void Fill(const DenoiseSettings& s) {
    DenoisePlanes d = planes_;
    DenoiseInput in = input_;
    backend_.ParallelFor(Stage::kAccumulate, d.stride * d.rows,
                         [=] PT_HD(uint32_t i) { DenoiseFillPixel(d, in, i); });
    if (s.calibrateVariance) CalibrateVariance();
    if (s.outliers) Outliers();
    float tau = s.featureTau;
    backend_.ParallelFor(Stage::kAccumulate, d.stride * (d.rows - 2),
                         [=] PT_HD(uint32_t i) { DenoiseFeatureScalePixel(d, tau, i); });
    for (int k = 0; k < kDenoiseCandidates; ++k) {
      const DenoiseCandidate& c = s.candidates[k < s.candidateCount ? k : 0];
      bandwidths_.color[k] = 1.0f / (c.colorK * c.colorK);
      bandwidths_.feature[k] = 1.0f / (c.featureK * c.featureK);
    }
  }

  // The halves' variances scaled to their measured difference (nlm_variance.h).
  void CalibrateVariance() {
    DenoisePlanes d = planes_;
    uint32_t n = d.stride * d.rows;
    backend_.ParallelFor(Stage::kAccumulate, n,
                         [=] PT_HD(uint32_t i) { DenoiseVarianceTermsPixel(d, i); });
    backend_.ParallelFor(Stage::kAccumulate, n,
                         [=] PT_HD(uint32_t i) { DenoiseVarianceRowPixel(d, i); });
    backend_.ParallelFor(Stage::kAccumulate, n,
                         [=] PT_HD(uint32_t i) { DenoiseVarianceScalePixel(d, i); });
  }

  // Fireflies scaled down in each half (nlm_outliers.h).
  void Outliers() {
    DenoisePlanes d = planes_;
    size_t first = size_t(d.padY) * d.stride;
    backend_.ParallelFor(Stage::kAccumulate, d.stride * d.rows,
                         [=] PT_HD(uint32_t i) { DenoiseOutlierLumPixel(d, i); });
    backend_.ParallelFor(Stage::kAccumulate, d.height * d.stride, [=] PT_HD(uint32_t i) {
      DenoiseOutlierDetectPixel(d, first + size_t(i));
    });
    backend_.ParallelFor(Stage::kAccumulate, d.height * d.stride, [=] PT_HD(uint32_t i) {
      DenoiseOutlierResolvePixel(d, first + size_t(i));
    });
    backend_.ParallelFor(Stage::kAccumulate, d.stride * d.rows,
                         [=] PT_HD(uint32_t i) { DenoiseOutlierApplyPixel(d, i); });
  }

  // A group of offsets over the image rows [r0, r1), compiled for its size: 8, or a window
  // row's last group (nlm_stages.h).
  void Offsets(uint32_t r0, uint32_t r1, const DenoiseOffsets& offset,
               const DenoiseSettings& s) {
    switch (offset.count) {
      case 1: Offsets<1>(r0, r1, offset, s); break;
      case 3: Offsets<3>(r0, r1, offset, s); break;
      case 5: Offsets<5>(r0, r1, offset, s); break;
      case 7: Offsets<7>(r0, r1, offset, s); break;
      case kDenoiseGroup: Offsets<kDenoiseGroup>(r0, r1, offset, s); break;
      default: throw std::logic_error("denoise: no passes for a group of this size");
    }
  }

  // Distances over the rows the patches reach, then the weights and sums.
  template <int kGroup>
  void Offsets(uint32_t r0, uint32_t r1, const DenoiseOffsets& offset,
               const DenoiseSettings& s) {
    DenoisePlanes d = planes_;
    uint32_t f = uint32_t(s.patchRadius);
    size_t first = size_t(r0 + d.padY - f) * d.stride;
    backend_.ParallelFor(Stage::kAccumulate, (r1 - r0 + 2 * f) * d.stride, [=] PT_HD(uint32_t i) {
      DenoiseDistancePixel<kGroup>(d, offset, first + size_t(i));
    });
    // One kernel per patch size and group size. Every candidate's sums are kept whatever
    // candidateCount says (those past it are never read): a third of the kernels to compile,
    // and the default (three candidates) pays nothing for it.
    switch (s.patchRadius) {
      case 0: Accumulate<0, kGroup>(r0, r1, offset); break;
      case 1: Accumulate<1, kGroup>(r0, r1, offset); break;
      case 2: Accumulate<2, kGroup>(r0, r1, offset); break;
      default: Accumulate<3, kGroup>(r0, r1, offset); break;
    }
  }

  template <int kPatch, int kGroup>
  void Accumulate(uint32_t r0, uint32_t r1, const DenoiseOffsets& offset) {
    DenoisePlanes d = planes_;
    DenoiseBandwidths k = bandwidths_;
    size_t first = size_t(r0 + d.padY) * d.stride;
    backend_.ParallelFor(Stage::kAccumulate, (r1 - r0) * d.stride, [=] PT_HD(uint32_t i) {
      DenoiseAccumulatePixel<kPatch, kGroup>(d, k, offset, first + size_t(i));
    });
  }

  uint32_t TileRows() const {
    return tiling_.rows ? std::min(tiling_.rows, planes_.height) : planes_.height;
  }
  uint32_t TileColumns() const { return tiling_.columns ? tiling_.columns : planes_.stride; }
  int MaxGroup(const DenoiseSettings& s) const {
    return tiling_.maxGroup[size_t(std::min(s.patchRadius, 3))];
  }

  // The CPU's order (denoise_tiles.h): one task per thread takes bands of tile rows from a
  // counter. A task has its own distance planes, so no two threads write one value (a tile's
  // distances reach into its neighbours'); each pixel's sums take the offsets in the GPU's
  // order, so the image is the same for any tiling, group size and thread count.
  void Tiles(const DenoiseSettings& s) {
    uint32_t bands = (planes_.height + TileRows() - 1) / TileRows();
    const DenoiseGroupFns& groups = tiling_.groups[size_t(std::min(s.patchRadius, 3))];
    int maxGroup = MaxGroup(s);
    std::atomic<uint32_t> next{0};
    backend_.ParallelTasks(Stage::kAccumulate, tasks_, [&](uint32_t task) {
      DenoiseBand band{planes_, bandwidths_, 0, 0, TileColumns(), s.radius, maxGroup};
      for (uint32_t b; (b = next.fetch_add(1, std::memory_order_relaxed)) < bands;) {
        band.r0 = b * TileRows();
        band.r1 = std::min(planes_.height, band.r0 + TileRows());
        // The task's planes placed where the bodies look for them: rows r0 - f .. r1 + f - 1
        // and f more floats either side (f the patch radius). Within store_: they are last.
        size_t f = size_t(s.patchRadius);
        size_t origin = (band.r0 + planes_.padY - f) * planes_.stride - f;
        for (int g = 0; g < maxGroup; ++g) {
          for (int h = 0; h < kDenoiseHalves; ++h) {
            size_t plane = size_t(task) * size_t(maxGroup) + size_t(g);
            plane = plane * kDenoiseHalves + size_t(h);
            band.d.dist[g][h] = distStore_ + plane * distRegion_ - origin;
          }
        }
        DenoiseBandPasses(band, groups);
      }
    });
  }

  // Each candidate's error, its padding, then each pixel's choice and value.
  void Finish(FilmImage& image, const DenoiseSettings& s) {
    DenoisePlanes d = planes_;
    int count = s.candidateCount, radius = s.selectRadius;
    size_t first = size_t(d.padY) * d.stride;
    backend_.ParallelFor(Stage::kAccumulate, d.height * d.stride, [=] PT_HD(uint32_t i) {
      DenoiseErrorPixel(d, count, first + size_t(i));
    });
    uint32_t padFirst = (d.padY - uint32_t(radius)) * d.stride;
    backend_.ParallelFor(Stage::kAccumulate, (d.height + 2 * uint32_t(radius)) * d.stride,
                         [=] PT_HD(uint32_t i) { DenoiseErrorPadPixel(d, count, padFirst + i); });
    if constexpr (Backend::kHostMemory) {  // straight into the image
      image.denoised.resize(size_t(3) * d.width * d.height);
      float* out = image.denoised.data();
      // One task per thread takes rows from a counter, with its own row of window sums.
      std::atomic<uint32_t> next{0};
      backend_.ParallelTasks(Stage::kAccumulate, tasks_, [&](uint32_t) {
        std::vector<float> acc(size_t(kDenoiseCandidates) * d.width);
        for (uint32_t y; (y = next.fetch_add(1, std::memory_order_relaxed)) < d.height;) {
          DenoiseSelectRow(d, count, radius, out, y, acc.data());
        }
      });
      AddEmission(out);
    } else {
      out_.Resize(size_t(3) * d.width * d.height);
      float* out = out_.Data();
      backend_.ParallelFor(Stage::kAccumulate, d.width * d.height, [=] PT_HD(uint32_t i) {
        DenoiseFinishPixel(d, count, radius, out, i);
      });
      AddEmission(out);
      backend_.Synchronize();
      out_.Download(image.denoised);
    }
  }

  // The seen emission back onto the filtered residual (none without FilmImage::emission).
  void AddEmission(float* out) {
    const float* emission = input_.emission;
    if (!emission) return;
    backend_.ParallelFor(Stage::kAccumulate, 3 * planes_.width * planes_.height,
                         [=] PT_HD(uint32_t i) { DenoiseAddEmissionPixel(out, emission, i); });
  }

 private:
  Backend& backend_;
  DenoiseTiling tiling_;
  uint32_t tasks_ = 1;       // CPU: the tasks that take bands (one per thread)
  size_t distRegion_ = 0;    // CPU: the floats of one task's distance plane
  float* distStore_ = nullptr;
  double passesMs_ = 0.0;
  DenoisePlanes planes_{};
  DenoiseBandwidths bandwidths_{};
  DenoiseInput input_{};
  Buffer<float> store_, out_;
  Buffer<float> rgb_, variance_, evenRgb_, albedo_, normal_, depth_, emission_, evenEmission_,
      residualVariance_;
  Buffer<uint32_t> samples_, evenSamples_;
};

}  // namespace pt
