// Whether an MPI launcher started this process, from the variables launchers set; needs no
// MPI library, so that a build without MPI can refuse a start by mpirun clearly.
#include <cstdlib>
#include <string>

#include "src/distributed/distributed.h"

namespace pt {

int LauncherWorldSize() {
  // Open MPI's mpirun; MPICH's Hydra and other PMI-1 launchers (Slurm's srun).
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* value = std::getenv(name);
    if (value && *value) {
      int n = std::atoi(value);
      return n > 0 ? n : -1;
    }
  }
  // Hydra's local rank count, and PMIx (Open MPI 5, srun --mpi=pmix): a launcher, of a size
  // they do not give.
  return std::getenv("MPI_LOCALNRANKS") || std::getenv("PMIX_RANK") ? -1 : 0;
}

}  // namespace pt
