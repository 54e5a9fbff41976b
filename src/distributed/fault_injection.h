// A test hook: PT_FAULT_INJECT=throw:RANK:N makes rank RANK's sessions throw on their N+1-th
// RenderRange call (N leaves rendered), as a GPU fault or an allocation failure in mid-render
// would, so that tests can check how a job ends when a rank fails. Unset: sessions as made.
#pragma once

#include "src/distributed/chunked_render.h"

namespace pt {

SessionMaker InjectFaults(SessionMaker make, int rank);

}  // namespace pt
