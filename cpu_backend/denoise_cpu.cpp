// The denoiser on the CPU backend: src/denoise/'s passes in host loops. Built with
// -fno-trapping-math (CMakeLists.txt): GCC then turns the bodies' selects into vector blends
// and vectorises each pass over the pixels (about 7x faster); values are the same IEEE
// operations either way, so results do not change.
#include <chrono>
#include <utility>

#include "cpu_backend/cpu_backend.h"
#include "src/denoise/denoise_runner.h"
#include "src/denoise/denoise_tiles.h"
#include "src/denoise/denoiser.h"

namespace pt {
namespace {

template <int kPatch, int kGroup>
void DenoiseGroupV3(const DenoiseBand& band, const DenoiseOffsets& o, size_t c0, size_t c1) {
  DenoiseTileGroup<kPatch, kGroup>(band, o, c0, c1);
}

// The same passes compiled for AVX-512 (x86-64-v4), everything they call inlined into them
// (flatten), so no code of theirs is shared with the v3 path. Twice the lanes and twice the
// vector registers (the sums stay in them); the same IEEE operations lane by lane (no
// contraction on the host), so the image is bit for bit the v3 path's.
template <int kPatch, int kGroup>
[[gnu::target("arch=x86-64-v4,prefer-vector-width=512"), gnu::flatten]] void DenoiseGroupV4(
    const DenoiseBand& band, const DenoiseOffsets& o, size_t c0, size_t c1) {
  DenoiseTileGroup<kPatch, kGroup>(band, o, c0, c1);
}

// The group functions of one patch radius, for the sizes DenoiseOffsets::Group makes: wide
// groups (whole window rows up to radius 7) for the default patch only, which keeps the
// file's build time (each function is a large vectorised loop) near what it was.
template <int kPatch, bool kV4>
DenoiseGroupFns GroupFunctions(bool wide) {
  DenoiseGroupFns f{};
  auto put = [&]<int... kSizes>(std::integer_sequence<int, kSizes...>) {
    ((f[kSizes] = kV4 ? DenoiseGroupV4<kPatch, kSizes> : DenoiseGroupV3<kPatch, kSizes>), ...);
  };
  put(std::integer_sequence<int, 1, 3, 5, 7, kDenoiseGroup>{});
  if constexpr (kPatch == 1) {
    if (wide) put(std::integer_sequence<int, 9, 11, 13, kDenoiseWideGroup>{});
  }
  return f;
}

template <bool kV4>
void PutGroupFunctions(DenoiseTiling& t, bool wide) {
  t.groups = {GroupFunctions<0, kV4>(wide), GroupFunctions<1, kV4>(wide),
              GroupFunctions<2, kV4>(wide), GroupFunctions<3, kV4>(wide)};
  t.maxGroup = {kDenoiseGroup, wide ? kDenoiseWideGroup : kDenoiseGroup, kDenoiseGroup,
                kDenoiseGroup};
}

DenoiseTiling CpuTiling(const CpuDenoiseOptions& options) {
  DenoiseTiling t;
  t.rows = options.tileRows;
  t.columns = options.tileColumns;
  if (options.avx512 && CpuDenoiserHasAvx512())
    PutGroupFunctions<true>(t, options.wideGroups);
  else
    PutGroupFunctions<false>(t, options.wideGroups);
  return t;
}

class CpuDenoiser final : public Denoiser {
 public:
  CpuDenoiser(int threads, const DenoiseSettings& settings, const CpuDenoiseOptions& options)
      : Denoiser(settings), backend_(threads), runner_(backend_, CpuTiling(options)) {}

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
  double lastMs_ = 0.0;
};

}  // namespace

bool CpuDenoiserHasAvx512() {
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
         __builtin_cpu_supports("avx512cd");
}

// Tiles of 16 rows of 128 padded pixels: the planes the 225 offsets read (the sums, a row's
// 30 distance planes and the inputs the window reaches, about 0.85 MB) stay in a core's L2
// cache, 1 MB on the EPYC where 32 rows (1.5 MB with whole-row groups) took 7% longer.
std::unique_ptr<Denoiser> MakeCpuDenoiser(int threads, const DenoiseSettings& settings) {
  return std::make_unique<CpuDenoiser>(threads, settings, CpuDenoiseOptions{});
}

std::unique_ptr<Denoiser> MakeCpuDenoiserWith(int threads, const DenoiseSettings& settings,
                                              const CpuDenoiseOptions& options) {
  return std::make_unique<CpuDenoiser>(threads, settings, options);
}

}  // namespace pt
