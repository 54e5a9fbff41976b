// Entry point of the CPU backend: the generic wavefront integrator over CpuBackend.
#include <algorithm>
#include <fstream>
#include <utility>

#include "cpu_backend/cpu_backend.h"
#include "src/integrator/backend_session.h"

namespace pt {

// Grow-only: shading's material order and --ray-order share the scratch (counting sort scans
// all of keyCursor_, extra zero counters included).
size_t CpuBackend::ReserveOrdering(const OrderShape& shape) {
  bool counting = shape.method == SortMethod::kCounting;
  if (counting && shape.keyCount > keyCursor_.size()) keyCursor_.assign(shape.keyCount, 0);
  if (!counting && shape.n > sortScratch_.size()) sortScratch_.resize(shape.n);
  return keyCursor_.size() * sizeof(uint32_t) + sortScratch_.size() * sizeof(uint64_t);
}

void CpuBackend::OrderByKey(Stage stage, const OrderShape& shape, const OrderArrays& a) {
  auto t0 = Clock::now();
  uint32_t n = shape.n;
  if (shape.method == SortMethod::kCounting) {
    // Histogram, exclusive scan, scatter.
    std::fill(keyCursor_.begin(), keyCursor_.end(), 0u);
    for (uint32_t i = 0; i < n; ++i) ++keyCursor_[a.keys[i]];
    uint32_t sum = 0;
    for (uint32_t& c : keyCursor_) sum += std::exchange(c, sum);
    for (uint32_t i = 0; i < n; ++i) {
      uint32_t p = keyCursor_[a.keys[i]]++;
      a.keysOut[p] = a.keys[i];
      a.valuesOut[p] = a.values[i];
    }
  } else {
    // Pack (key, value) into one word and sort those: no comparator indirection.
    sortScratch_.resize(n);
    for (uint32_t i = 0; i < n; ++i) sortScratch_[i] = (uint64_t(a.keys[i]) << 32) | a.values[i];
    std::sort(sortScratch_.begin(), sortScratch_.begin() + n);
    for (uint32_t i = 0; i < n; ++i) {
      a.keysOut[i] = uint32_t(sortScratch_[i] >> 32);
      a.valuesOut[i] = uint32_t(sortScratch_[i]);
    }
  }
  AddTime(stage, t0);
}

std::string CpuBackend::DeviceName() const {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  }
  return "CPU";
}

std::unique_ptr<RenderSession> MakeCpuSession(const Scene& scene, const RenderOptions& options,
                                              const RenderCallbacks& callbacks) {
  return std::make_unique<BackendSession<CpuBackend>>(scene, options, callbacks, options.threads);
}

RenderResult RenderCpu(const Scene& scene, const RenderOptions& options,
                       const RenderCallbacks& callbacks) {
  return MakeCpuSession(scene, options, callbacks)->Render();
}

}  // namespace pt
