// The GPU's start-up (driver and context, then the render module: 0.3-0.45 s on an H100) on a
// thread of its own, begun before the scene is loaded, so that it overlaps loading and the BVH
// build instead of following them (issue 28).
#pragma once

#include <chrono>
#include <future>

#include "src/app/run.h"
#include "src/integrator/render_api.h"

namespace pt {

class DeviceStart {
 public:
  // Starts the device of this local rank (localRank mod the GPUs) when the build has the CUDA
  // backend and `requested` is not the CPU; else does nothing.
  DeviceStart(const AppBackends& backends, BackendKind requested, int localRank = 0);
  ~DeviceStart();  // waits for the thread
  DeviceStart(const DeviceStart&) = delete;
  DeviceStart& operator=(const DeviceStart&) = delete;

  // The GPUs found (0: none, or not asked for); waits for the start-up.
  int DeviceCount();
  // How long the start-up took on its thread (ms), or -1 when there was none.
  double BackgroundMs();

 private:
  std::future<int> future_;
  int count_ = 0;
  double ms_ = -1.0;
  bool started_ = false;
};

}  // namespace pt
