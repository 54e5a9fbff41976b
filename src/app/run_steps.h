// The steps of a run that the one-process flow (run.cpp), the MPI flow (run_mpi.cpp) and the
// live preview (serve.cpp) share: loading, backend and options, the messages around the render, the stats' report.
// Failures are thrown as AppFailure. Internal to src/app/.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "src/app/cli.h"
#include "src/app/device_start.h"
#include "src/app/render_job.h"
#include "src/app/run.h"
#include "src/app/stats_json.h"
#include "src/io/scene_loader.h"

namespace pt {

using AppClock = std::chrono::steady_clock;
double MsSince(AppClock::time_point start);

void Warn(const std::string& warning);

// What the command line asks of the scene's loading (--camera, --animation, --time, --variant,
// whether --env is given).
LoadOptions CliLoadOptions(const CliOptions& cli);
SceneDesc LoadAndOverride(const CliOptions& cli, double* loadMs);
// The BVH layout and builder --bvh and --bvh-build ask for (auto: wide). With a started device,
// the linear BVH (--bvh-build gpu or auto) is built on it: GPU localRank mod the count.
// builtOnDevice (optional) is set when the device built a tree.
BvhBuildOptions ChooseBvh(const CliOptions& cli, const AppBackends& backends,
                          DeviceStart* device = nullptr, int localRank = 0,
                          bool* builtOnDevice = nullptr);
// The builder that ran (stats' bvh.builder) for the options ChooseBvh made: auto's choice is
// the linear BVH only where the device built it.
std::string BuilderThatRan(const CliOptions& cli, bool builtOnDevice);
Scene Build(SceneDesc desc, const BvhBuildOptions& bvh, double* bvhBuildMs);
// auto: CUDA when it is built and a GPU is present, else the CPU. With `started`, the count
// of its start-up (waited for) instead of a probe of its own.
BackendKind ChooseBackend(BackendKind requested, const AppBackends& backends,
                          DeviceStart* started = nullptr);
RenderOptions MakeRenderOptions(const CliOptions& cli, BackendKind backend,
                                const std::vector<float>* reference);

// --chunks (one process) and the MPI options against what the chunked and distributed
// renders do: a chunk count above spp, adaptive sampling, --reference, --preview-every,
// --checkpoint-every and --resume are refused (exit 1), and so are the MPI-only options in a
// build without MPI.
void CheckChunkOptions(const CliOptions& cli, const Scene& scene, const RenderOptions& options,
                       bool distributed);

// One line saying what the scene needs simulated and which stage variant runs it.
void PrintEffects(const Scene& scene, bool specialize);
// The summary line: size, spp, time, device, rates, and why the render stopped.
void PrintSummary(const JobOutcome& job);
// The last lines: each file written.
void PrintWritten(const std::vector<std::string>& files, const CliOptions& cli, bool resumable);

RunReport MakeReport(const CliOptions& cli, const Scene& scene, const JobOutcome& job,
                     BackendKind backend);

// Out of GPU memory: what was asked, and what to lower.
std::string OutOfMemoryMessage(const OutOfDeviceMemory& e, const CliOptions& cli);

}  // namespace pt
