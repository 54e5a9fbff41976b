// The steps a render and the live preview share: the scene loaded with the command line's
// overrides, built, the backend chosen and the render options made; failures are AppFailure.
#pragma once

#include <string>
#include <vector>

#include "src/app/cli.h"
#include "src/app/run.h"
#include "src/scene/scene.h"

namespace pt {

void Warn(const std::string& warning);

// The scene file with the overrides applied (exit 2 for a bad scene, 1 for bad overrides).
SceneDesc LoadAndOverride(const CliOptions& cli, double* loadMs);

// The BVH and light table (exit 2 when the scene cannot be built).
Scene Build(SceneDesc desc, double* bvhBuildMs);

// auto: CUDA when it is built and a GPU is present, else the CPU (exit 3 for --backend cuda
// without either).
BackendKind ChooseBackend(BackendKind requested, const AppBackends& backends);

RenderOptions MakeRenderOptions(const CliOptions& cli, BackendKind backend,
                                const std::vector<float>* reference);

}  // namespace pt
