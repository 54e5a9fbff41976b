// Entry point of the CPU backend: the generic wavefront integrator over CpuBackend.
#include <fstream>

#include "cpu_backend/cpu_backend.h"
#include "src/integrator/backend_session.h"

namespace pt {

void CpuBackend::SortByKey(Stage stage, uint32_t* keys, uint32_t* queue, uint32_t n) {
  auto t0 = Clock::now();
  // Pack (key, slot) into one word and sort those: stable by construction, no comparator
  // indirection.
  sortScratch_.resize(n);
  for (uint32_t i = 0; i < n; ++i) sortScratch_[i] = (uint64_t(keys[i]) << 32) | queue[i];
  std::sort(sortScratch_.begin(), sortScratch_.end());
  for (uint32_t i = 0; i < n; ++i) {
    keys[i] = uint32_t(sortScratch_[i] >> 32);
    queue[i] = uint32_t(sortScratch_[i]);
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
