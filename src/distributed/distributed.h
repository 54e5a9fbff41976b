// One render over the processes of an MPI job: each rank renders the chunk-tree leaves rank 0
// hands it (on its own GPU, local rank mod device count, or on CPU threads), merges what it
// can along the tree, and the films travel up a binomial tree of ranks to rank 0, which ends
// with the root film: the same bits for any number of ranks and any assignment of leaves.
// This header is MPI-free; the implementation is src/distributed/mpi_*.cpp (built with MPI)
// or no_mpi.cpp (which refuses).
#pragma once

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "src/distributed/chunked_render.h"
#include "src/distributed/rank_report.h"

namespace pt {

// This build has no MPI (exit status 3 in the app, as for a missing CUDA backend).
struct MpiUnavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// An MPI call failed.
struct MpiFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// This process's stop signal: the number of the first SIGINT, SIGTERM or SIGHUP it received,
// 0 while none has come (the app's StopSignal).
using StopSignalSource = std::function<int()>;

bool MpiBuilt();

// The process count an MPI launcher announced in the environment (Open MPI, MPICH/Hydra,
// PMI/PMIx under Slurm): 0 when not started by one, -1 when started by one that does not say.
int LauncherWorldSize();

class MpiJob {
 public:
  // MPI_Init_thread (MPI_THREAD_FUNNELED: only the main thread calls MPI), errors returned
  // rather than fatal. Throws MpiUnavailable in a build without MPI.
  static std::unique_ptr<MpiJob> Start();
  virtual ~MpiJob() = default;  // MPI_Finalize

  virtual int Rank() const = 0;
  virtual int Size() const = 0;
  virtual int LocalRank() const = 0;  // among the ranks of this host
  virtual int LocalSize() const = 0;
  virtual std::string Host() const = 0;

  // Collective: every rank's status (0 = fine) and message; all ranks get the largest status
  // and the message of the lowest rank that reported it, prefixed "rank N: ".
  virtual std::pair<int, std::string> Agree(int status, const std::string& message) = 0;
  // Collective: every rank's value, in rank order.
  virtual std::vector<uint64_t> AllGather(uint64_t value) = 0;

  // Rank 0, once the outputs are written: tells every rank the job's exit status. The other
  // ranks wait for it (leaving early, with `status`, once this rank has a stop signal) and
  // return it.
  virtual int ShareExitStatus(int status, const StopSignalSource& stopSignal) = 0;
  // Ends every rank of the job now, with this exit status (a rank stopped answering).
  [[noreturn]] virtual void Abort(int status) = 0;
};

struct DistributedOptions {
  uint32_t chunks = 32;
  double timeLimitSeconds = 0.0;    // <= 0: none
  double rankTimeoutSeconds = 60.0; // a rank silent this long is lost
  int lanes = 1;                    // this rank's render lanes
  int mergeThreads = 1;
};

struct DistributedResult {
  // Rank 0 only: the root film (no samples anywhere: empty), every rank's report, and the
  // wall time from the common render start to the root film.
  FilmState film;
  std::vector<RankReport> ranks;
  double renderMs = 0.0;
  double reductionMs = 0.0;    // from the last rank's last leaf to the root film
  uint32_t leavesRendered = 0; // leaves in the root (rendered whole or in part)
  uint64_t samples = 0;
  bool interrupted = false;    // a stop signal (Ctrl-C, SIGTERM, SIGHUP) on some rank
  int signal = 0;              // the first one rank 0 knows of (its own, or a rank's report)
  bool timeLimited = false;
  std::string why;             // why the job ended early, naming the rank; empty if not
  bool rankLost = false;       // a rank stopped answering: the job must be aborted
  int status = 0;              // 0; 3 a rank failed or was lost; 128 + signal interrupted
};

// Collective over the job. `stopSignal` is this process's stop signal; onProgress
// (rank 0) gets the samples done by every rank and the total.
DistributedResult RenderDistributed(MpiJob& job, const SessionMaker& make, const Scene& scene,
                                    const RenderOptions& options,
                                    const DistributedOptions& distributed,
                                    const std::function<void(uint64_t, uint64_t)>& onProgress,
                                    const StopSignalSource& stopSignal);

}  // namespace pt
