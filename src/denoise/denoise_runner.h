// The denoiser over a backend: its planes in the backend's memory, and the passes of
// nlm_stages.h launched through the backend's ParallelFor. Generic like the integrator;
// cpu_backend/denoise_cpu.cpp and cuda/denoise_cuda.cu instantiate it.
//
// Lambdas copy what they need, never `this` (nvcc's extended lambdas run on the device).
#pragma once

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "src/denoise/denoise_settings.h"
#include "src/denoise/denoiser.h"
#include "src/denoise/nlm_outliers.h"
#include "src/denoise/nlm_stages.h"
#include "src/integrator/render_api.h"
#include "src/integrator/stage_id.h"

namespace pt {

template <typename Backend>
class DenoiseRunner {
 public:
  template <typename T>
  using Buffer = typename Backend::template Buffer<T>;

  // bandRows: the rows each group of per-offset passes covers (0: the whole image at once).
  // On the CPU a band's planes stay in the caches across the offsets; a GPU wants every
  // pixel in each launch.
  DenoiseRunner(Backend& backend, uint32_t bandRows) : backend_(backend), bandRows_(bandRows) {}

  // image.denoised := the filtered image. Throws std::invalid_argument on a bad image or
  // settings.
  void Run(FilmImage& image, const DenoiseSettings& settings) {
    std::string problem = DenoiseInputProblem(image);
    if (problem.empty()) problem = DenoiseSettingsProblem(settings);
    if (!problem.empty()) throw std::invalid_argument("denoise: " + problem);
    Layout(uint32_t(image.width), uint32_t(image.height), settings);
    Upload(image);
    backend_.Synchronize();
    double before = backend_.Times().accumulate;
    Fill(settings);
    for (uint32_t r0 = 0; r0 < planes_.height; r0 += Band()) {
      uint32_t r1 = std::min(planes_.height, r0 + Band());
      for (int dy = -settings.radius; dy <= settings.radius; ++dy) {
        for (int dx = -settings.radius; dx <= settings.radius; dx += kDenoiseGroup) {
          DenoiseOffsets group{ptrdiff_t(dy) * ptrdiff_t(planes_.stride), dx,
                               std::min(kDenoiseGroup, settings.radius - dx + 1)};
          Offsets(r0, r1, group, settings);
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
  uint32_t Band() const { return bandRows_ ? bandRows_ : planes_.height; }

  // The padded planes, one allocation.
  void Layout(uint32_t width, uint32_t height, const DenoiseSettings& s) {
    DenoisePlanes& d = planes_;
    d.width = width;
    d.height = height;
    d.padX = uint32_t(s.radius + s.patchRadius);
    d.padY = d.padX + 1;  // a neighbour of a padding column wraps into the next row: in range
    d.stride = width + 2 * d.padX;
    d.rows = height + 2 * d.padY;
    size_t plane = size_t(d.stride) * d.rows;
    constexpr size_t kPlanes = 2 * 3 + 2 * 3 + 3 + 3 + 1 + 3 + 2 * kDenoiseGroup +
                               kDenoiseCandidates * (2 * 4 + 1);
    if (store_.Size() != plane * kPlanes) {
      store_.Resize(plane * kPlanes);
      store_.Zero();  // padding the passes read but never write stays finite
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
      for (int g = 0; g < kDenoiseGroup; ++g) d.dist[g][h] = take();
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
  }

  void Upload(const FilmImage& image) {
    rgb_.Upload(image.rgb);
    variance_.Upload(image.variance);
    samples_.Upload(image.samples);
    evenRgb_.Upload(image.evenRgb);
    evenSamples_.Upload(image.evenSamples);
    albedo_.Upload(image.albedo);
    normal_.Upload(image.normal);
    depth_.Upload(image.depth);
  }

  void Fill(const DenoiseSettings& s) {
    DenoisePlanes d = planes_;
    DenoiseInput in{rgb_.Data(),     variance_.Data(), samples_.Data(), evenRgb_.Data(),
                    evenSamples_.Data(), albedo_.Data(), normal_.Data(),  depth_.Data()};
    backend_.ParallelFor(Stage::kAccumulate, d.stride * d.rows,
                         [=] PT_HD(uint32_t i) { DenoiseFillPixel(d, in, i); });
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

  // A group of offsets over the image rows [r0, r1): distances over the rows the patches
  // reach, then the weights and sums.
  void Offsets(uint32_t r0, uint32_t r1, const DenoiseOffsets& offset,
               const DenoiseSettings& s) {
    DenoisePlanes d = planes_;
    uint32_t f = uint32_t(s.patchRadius);
    size_t first = size_t(r0 + d.padY - f) * d.stride;
    backend_.ParallelFor(Stage::kAccumulate, (r1 - r0 + 2 * f) * d.stride, [=] PT_HD(uint32_t i) {
      DenoiseDistancePixel(d, offset, first + size_t(i));
    });
    // One kernel per patch size. Every candidate's sums are kept whatever candidateCount says
    // (those past it are never read): a third of the kernels to compile, and the default
    // (three candidates) pays nothing for it.
    switch (s.patchRadius) {
      case 0: Accumulate<0, kDenoiseCandidates>(r0, r1, offset); break;
      case 1: Accumulate<1, kDenoiseCandidates>(r0, r1, offset); break;
      case 2: Accumulate<2, kDenoiseCandidates>(r0, r1, offset); break;
      default: Accumulate<3, kDenoiseCandidates>(r0, r1, offset); break;
    }
  }

  template <int kPatch, int kCount>
  void Accumulate(uint32_t r0, uint32_t r1, const DenoiseOffsets& offset) {
    DenoisePlanes d = planes_;
    DenoiseBandwidths k = bandwidths_;
    size_t first = size_t(r0 + d.padY) * d.stride;
    backend_.ParallelFor(Stage::kAccumulate, (r1 - r0) * d.stride, [=] PT_HD(uint32_t i) {
      DenoiseAccumulatePixel<kPatch, kCount>(d, k, offset, first + size_t(i));
    });
  }

  // Each candidate's error, then each pixel's choice and value.
  void Finish(FilmImage& image, const DenoiseSettings& s) {
    DenoisePlanes d = planes_;
    int count = s.candidateCount, radius = s.selectRadius;
    size_t first = size_t(d.padY) * d.stride;
    backend_.ParallelFor(Stage::kAccumulate, d.height * d.stride, [=] PT_HD(uint32_t i) {
      DenoiseErrorPixel(d, count, first + size_t(i));
    });
    out_.Resize(size_t(3) * d.width * d.height);
    float* out = out_.Data();
    backend_.ParallelFor(Stage::kAccumulate, d.width * d.height, [=] PT_HD(uint32_t i) {
      DenoiseFinishPixel(d, count, radius, out, i);
    });
    backend_.Synchronize();
    out_.Download(image.denoised);
  }


 private:
  Backend& backend_;
  uint32_t bandRows_;
  double passesMs_ = 0.0;
  DenoisePlanes planes_{};
  DenoiseBandwidths bandwidths_{};
  Buffer<float> store_, out_;
  Buffer<float> rgb_, variance_, evenRgb_, albedo_, normal_, depth_;
  Buffer<uint32_t> samples_, evenSamples_;
};

}  // namespace pt
