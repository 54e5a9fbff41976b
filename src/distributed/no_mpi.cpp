// A build configured without MPI: starting under mpirun, or asking for its options, is a
// clear error, never N independent renders racing for the same output file.
#include "src/distributed/distributed.h"

namespace pt {

bool MpiBuilt() { return false; }

std::unique_ptr<MpiJob> MpiJob::Start() {
  throw MpiUnavailable(
      "this build has no MPI support (no MPI library was found when it was configured; install "
      "libopenmpi-dev and rebuild)");
}

DistributedResult RenderDistributed(MpiJob&, const SessionMaker&, const Scene&,
                                    const RenderOptions&, const DistributedOptions&,
                                    const std::function<void(uint64_t, uint64_t)>&,
                                    const StopSignalSource&) {
  throw MpiUnavailable("this build has no MPI support");
}

}  // namespace pt
