// The built-in denoiser as the app and the preview server use it: an image of the film in
// (its features and its two half buffers: RenderOptions::featureBuffers and halfFilms), the
// denoised image out, on the CPU or a GPU. Host-side: a virtual interface is fine here.
// The method and its parameters: docs/denoise.md, src/denoise/nlm_stages.h.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "src/denoise/denoise_settings.h"
#include "src/integrator/render_api.h"

namespace pt {

class Denoiser {
 public:
  explicit Denoiser(const DenoiseSettings& settings) : settings_(settings) {}
  virtual ~Denoiser() = default;
  // The parameters of the next Denoise calls: the live preview changes the variance rule with
  // its sampler flag (checked by Denoise, which throws std::invalid_argument on bad ones).
  const DenoiseSettings& Settings() const { return settings_; }
  void SetSettings(const DenoiseSettings& settings) { settings_ = settings; }
  // image.denoised := the denoised image (3 floats per pixel). Throws std::invalid_argument
  // when the image lacks features or half buffers (DenoiseInputProblem says which).
  virtual void Denoise(FilmImage& image) = 0;
  // Milliseconds the last Denoise took: all of it (copies to and from a GPU included), and
  // its passes alone (the kernels on a GPU).
  virtual double LastMs() const = 0;
  virtual double LastPassesMs() const = 0;
  virtual std::string BackendName() const = 0;

 protected:
  DenoiseSettings settings_;
};

// What an image lacks to be denoised, or an empty string.
std::string DenoiseInputProblem(const FilmImage& image);

// threads: 0 = all cores. The CUDA one throws BackendUnavailable when the backend is not built
// or no GPU is present.
std::unique_ptr<Denoiser> MakeCpuDenoiser(int threads, const DenoiseSettings& settings = {});
std::unique_ptr<Denoiser> MakeCudaDenoiser(int device, const DenoiseSettings& settings = {});

// The CPU denoiser's loop order and vector code (cpu_backend/denoise_cpu.cpp), for tests and
// benchmarks: tiles of tileRows x tileColumns padded pixels (0: the whole image) and AVX-512
// code where the host has it (else x86-64-v3), and wide groups of offsets (a window row of up
// to 15 offsets per pass, else 8; nlm_stages.h). The image is the same bit for bit whatever
// they are.
struct CpuDenoiseOptions {
  uint32_t tileRows = 16, tileColumns = 128;
  bool avx512 = true;
  bool wideGroups = true;
};
std::unique_ptr<Denoiser> MakeCpuDenoiserWith(int threads, const DenoiseSettings& settings,
                                              const CpuDenoiseOptions& options);
// Whether the host runs the CPU denoiser's AVX-512 code.
bool CpuDenoiserHasAvx512();

using DenoiserFactory = std::unique_ptr<Denoiser> (*)(int, const DenoiseSettings&);

}  // namespace pt
