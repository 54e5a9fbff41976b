// The application behind main(): command line, scene, render, outputs and exit status, as
// ../shared/cli.md defines them.
#pragma once

#include <memory>

#include "src/denoise/denoiser.h"
#include "src/geometry/bvh.h"
#include "src/geometry/bvh_wide.h"
#include "src/integrator/render_session.h"

namespace pt {

class HttpServer;
class LiveRender;
struct HttpServerConfig;

inline constexpr int kExitOk = 0;
inline constexpr int kExitBadCommandLine = 1;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitRuntimeFailure = 3;
inline constexpr int kExitInterrupted = 130;  // SIGINT; any stop signal N exits 128 + N

using SessionFactory = std::unique_ptr<RenderSession> (*)(const Scene&, const RenderOptions&,
                                                         const RenderCallbacks&);

// The backends, handed in by main(): the executable, not pt_core, must reference them, since
// the static backend libraries come before pt_core on the link line. cudaSession is null when
// the CUDA backend is not built.
struct AppBackends {
  SessionFactory cpuSession = nullptr;
  SessionFactory cudaSession = nullptr;
  int (*cudaDeviceCount)() = nullptr;
  // --denoise on each backend (src/denoise/); cudaDenoiser is null without the CUDA backend.
  DenoiserFactory cpuDenoiser = nullptr;
  DenoiserFactory cudaDenoiser = nullptr;
  // Starts the GPU of a local rank (its context and modules); returns the GPUs found.
  int (*startDevice)(int localRank) = nullptr;
  // Readies, on a thread of its own, what a big scene's upload goes through (pinned buffers).
  void (*prepareUploads)(int localRank) = nullptr;
  // The linear BVH (--bvh-build gpu) on a GPU; false when it cannot run there.
  bool (*lbvhBuild)(const std::vector<Aabb>& bounds, int device, BvhBuildResult* out) = nullptr;
  bool (*wideLbvhBuild)(const std::vector<Aabb>& bounds, int device, WideBvhResult* out) =
      nullptr;
  // The preview server (src/server/http_server.h); null when cpp-httplib was not found.
  std::unique_ptr<HttpServer> (*startServer)(LiveRender&, const HttpServerConfig&) = nullptr;
};

// Runs the whole program; returns the exit status. Started by an MPI launcher, it runs
// RunMpiApp (src/app/run_mpi.cpp), else RunProcess.
int RunApp(int argc, const char* const* argv, const AppBackends& backends);
// The program as one process (also what one rank under mpirun does).
int RunProcess(int argc, const char* const* argv, const AppBackends& backends);
// The program as one rank of an MPI job: every rank loads the scene, renders the leaves it is
// given, and rank 0 writes every output. A build without MPI refuses more than one process.
int RunMpiApp(int argc, const char* const* argv, const AppBackends& backends);

}  // namespace pt
