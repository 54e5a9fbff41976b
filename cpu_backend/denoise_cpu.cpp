// The denoiser on the CPU backend: src/denoise/'s passes in host loops. Built with
// -fno-trapping-math (CMakeLists.txt): GCC then turns the bodies' selects into vector blends
// and vectorises each pass over the pixels (about 7x faster); values are the same IEEE
// operations either way, so results do not change.
#include <chrono>

#include "cpu_backend/cpu_backend.h"
#include "src/denoise/denoise_runner.h"
#include "src/denoise/denoiser.h"

namespace pt {
namespace {

// Rows per band of per-offset passes: a band's planes (32 rows of a 1080p image: ~8 MB over
// all planes, the sums and distances ~2 MB) stay in the caches across the offsets.
constexpr uint32_t kCpuBandRows = 32;

class CpuDenoiser final : public Denoiser {
 public:
  CpuDenoiser(int threads, const DenoiseSettings& settings)
      : backend_(threads), runner_(backend_, kCpuBandRows), settings_(settings) {}

  void Denoise(FilmImage& image) override {
    auto start = std::chrono::steady_clock::now();
    runner_.Run(image, settings_);
    lastMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                  .count();
  }
  double LastMs() const override { return lastMs_; }
  double LastPassesMs() const override { return runner_.PassesMs(); }
  std::string BackendName() const override { return "cpu"; }

 private:
  CpuBackend backend_;
  DenoiseRunner<CpuBackend> runner_;
  DenoiseSettings settings_;
  double lastMs_ = 0.0;
};

}  // namespace

std::unique_ptr<Denoiser> MakeCpuDenoiser(int threads, const DenoiseSettings& settings) {
  return std::make_unique<CpuDenoiser>(threads, settings);
}

}  // namespace pt
