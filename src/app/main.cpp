// pathtracer: everything but the choice of linked backends lives in src/app/run.cpp.
#include "src/app/run.h"
#include "src/geometry/lbvh_build.h"

#if defined(PT_HAVE_SERVER)
#include "src/server/http_server.h"
#endif

int main(int argc, char** argv) {
  pt::AppBackends backends;
  backends.cpuSession = &pt::MakeCpuSession;
  backends.cpuDenoiser = &pt::MakeCpuDenoiser;
#if defined(PT_HAVE_CUDA)
  backends.cudaSession = &pt::MakeCudaSession;
  backends.cudaDenoiser = &pt::MakeCudaDenoiser;
  backends.lbvhBuild = &pt::BuildLbvhCuda;
  backends.wideLbvhBuild = &pt::BuildWideLbvhCuda;
  backends.prepareUploads = &pt::CudaPrepareUploads;
#endif
  backends.cudaDeviceCount = &pt::CudaDeviceCount;
  backends.startDevice = &pt::CudaStartDevice;
#if defined(PT_HAVE_SERVER)
  backends.startServer = &pt::StartHttpServer;
#endif
  return pt::RunApp(argc, argv, backends);
}
