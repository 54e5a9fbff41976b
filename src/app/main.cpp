// pathtracer: everything but the choice of linked backends lives in src/app/run.cpp.
#include "src/app/run.h"

int main(int argc, char** argv) {
  pt::AppBackends backends;
  backends.renderCpu = &pt::RenderCpu;
#if defined(PT_HAVE_CUDA)
  backends.renderCuda = &pt::RenderCuda;
#endif
  backends.cudaDeviceCount = &pt::CudaDeviceCount;
  return pt::RunApp(argc, argv, backends);
}
