// The steps of a run that the one-process flow (run.cpp) and the MPI flow (run_mpi.cpp)
// share. Internal to src/app/.
#pragma once

#include <string>
#include <vector>

#include "src/app/cli.h"
#include "src/app/run.h"

namespace pt::app {

// A failure with its exit status; thrown by the steps, caught once per flow.
struct AppFailure {
  int status;
  std::string message;
};

void CheckOutputsWritable(const CliOptions& cli);
SceneDesc LoadAndOverride(const CliOptions& cli, double* loadMs);
Scene Build(SceneDesc desc, double* bvhBuildMs);
BackendKind ChooseBackend(BackendKind requested, const AppBackends& backends);
RenderOptions MakeRenderOptions(const CliOptions& cli, BackendKind backend,
                                const std::vector<float>* reference);
void WriteOutputs(const CliOptions& cli, const FilmImage& image);
void PrintEffects(const Scene& scene, bool specialize);
void PrintSummary(const RenderResult& result);

// --chunks and the MPI options against what the chunked and distributed renders do: a
// chunk count above spp, adaptive sampling, --reference and --preview-every are refused
// (exit 1), and so are the MPI options in a build without MPI. Defined in run_mpi.cpp.
void CheckChunkOptions(const CliOptions& cli, const Scene& scene, const RenderOptions& options,
                       bool distributed);

}  // namespace pt::app
