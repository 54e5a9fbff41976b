// Whether an MPI launcher started this process, from the variables launchers set; needs no
// MPI library, so that a build without MPI can refuse a start by mpirun clearly.
#include <cstdlib>
#include <string>

#include "src/distributed/distributed.h"

namespace pt {

int LauncherWorldSize() {
  // Open MPI's mpirun, MPICH's Hydra and PMI-1 launchers, Slurm's srun.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS"}) {
    const char* value = std::getenv(name);
    if (value && *value) {
      int n = std::atoi(value);
      return n > 0 ? n : -1;
    }
  }
  // PMIx (Open MPI 5, Slurm with --mpi=pmix) names the rank but not always the size.
  return std::getenv("PMIX_RANK") ? -1 : 0;
}

}  // namespace pt
