// The denoiser on the CUDA backend: src/denoise/'s passes as kernels through CudaBackend's
// ParallelFor (every pixel in each launch), with the image copied to the device and back.
#include <chrono>

#include "cuda/cuda_backend.cuh"
#include "src/denoise/denoise_runner.h"
#include "src/denoise/denoiser.h"

namespace pt {
namespace {

class CudaDenoiser final : public Denoiser {
 public:
  CudaDenoiser(int device, const DenoiseSettings& settings)
      : Denoiser(settings), backend_(device), runner_(backend_) {}

  void Denoise(FilmImage& image) override {
    backend_.BindThread();  // the calling thread may not be the one that made it
    auto start = std::chrono::steady_clock::now();
    runner_.Run(image, settings_);
    lastMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                  .count();
  }
  double LastMs() const override { return lastMs_; }
  double LastPassesMs() const override { return runner_.PassesMs(); }
  std::string BackendName() const override { return "cuda"; }

 private:
  CudaBackend backend_;
  DenoiseRunner<CudaBackend> runner_;
  double lastMs_ = 0.0;
};

}  // namespace

std::unique_ptr<Denoiser> MakeCudaDenoiser(int device, const DenoiseSettings& settings) {
  return std::make_unique<CudaDenoiser>(device, settings);
}

}  // namespace pt
