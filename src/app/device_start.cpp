#include "src/app/device_start.h"

namespace pt {

DeviceStart::DeviceStart(const AppBackends& backends, BackendKind requested, int localRank) {
  if (requested == BackendKind::kCpu || !backends.startDevice || !backends.cudaSession) return;
  started_ = true;
  auto start = backends.startDevice;
  future_ = std::async(std::launch::async, [this, start, localRank] {
    const auto t0 = std::chrono::steady_clock::now();
    const int count = start(localRank);
    ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return count;
  });
}

DeviceStart::~DeviceStart() {
  if (future_.valid()) future_.wait();
}

int DeviceStart::DeviceCount() {
  if (future_.valid()) count_ = future_.get();  // ms_ is written before the value is ready
  return count_;
}

double DeviceStart::BackgroundMs() {
  if (!started_) return -1.0;
  DeviceCount();
  return ms_;
}

}  // namespace pt
