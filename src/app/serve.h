// pathtracer SCENE --serve [PORT]: the live preview. Loads the scene as a render would, renders
// it progressively on the chosen backend (src/server/live_render.h) and serves the page and API
// of src/server/ until a stop signal; returns the exit status.
#pragma once

#include "src/app/cli.h"
#include "src/app/run.h"

namespace pt {

// Throws AppFailure: 3 when this build has no server or the address cannot be bound, 2 for a
// bad scene.
int Serve(const CliOptions& cli, const AppBackends& backends);

}  // namespace pt
