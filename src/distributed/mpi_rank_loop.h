// One rank's side of a distributed render (built only with MPI). The main thread runs this
// loop and makes every MPI call; the render lanes only post events and wait for grants. It
// never blocks on another rank: it polls with MPI_Test/Iprobe, sleeping briefly when idle,
// and gives up on a rank that stays silent past the rank timeout.
//
// Rank 0 also coordinates: it hands out leaves (LeafScheduler), watches the time limit, the
// other ranks' liveness and progress, and broadcasts a stop when the time is up, a rank is
// interrupted, fails or is lost. Films go up a binomial tree of ranks (rank r's parent is r
// with its lowest set bit cleared) once a rank's lanes and children are done; after a stop
// other than the time limit every rank sends straight to rank 0 instead ("flat"), so that
// one dead rank cannot hold up the others' samples.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "src/distributed/film_assembler.h"
#include "src/distributed/leaf_scheduler.h"
#include "src/distributed/mpi_transfer.h"
#include "src/distributed/render_lane.h"

namespace pt::mpi {

class RankLoop {
 public:
  RankLoop(MpiJobImpl& job, const SessionMaker& make, const Scene& scene,
           const RenderOptions& options, const DistributedOptions& distributed,
           const std::function<void(uint64_t, uint64_t)>& onProgress,
           const StopSignalSource& stopSignal);
  DistributedResult Run();

 private:
  using Clock = std::chrono::steady_clock;
  bool IsRoot() const { return rank_ == 0; }

  std::pair<int, std::string> StartLanes();
  void StockFilms();
  bool Step();
  bool Finished();
  DistributedResult Finish();

  // Lanes (rank_loop_lanes part of mpi_rank_loop.cpp).
  void OnLaneEvent(LaneEvent& event);
  void GrantLane(int lane, std::optional<uint32_t> leaf);
  void StopLocal(StopReason reason);

  // Messages and timers.
  bool PollControl();
  bool PollRootControl();
  bool PollWorkerControl();
  void OnRequest(int rank, int lane);
  void StopAll(StopReason reason, const std::string& why);
  void CheckTimers();
  void CheckRootTimers(Clock::time_point now);

  // Films going up.
  bool PollTransfers();
  void MaybeHandOver();
  double GraceSeconds() const;
  bool GraceOver() const;

  MpiJobImpl& job_;
  MPI_Comm comm_;
  int rank_, size_;
  SessionMaker make_;
  const Scene& scene_;
  RenderOptions options_;
  DistributedOptions distributed_;
  const std::function<void(uint64_t, uint64_t)>& onProgress_;
  const StopSignalSource& stopSignal_;

  ChunkTree tree_;
  uint32_t filmWidth_ = 0, filmHeight_ = 0;  // the crop window's
  LaneShared shared_;
  FilmAssembler assembler_;
  Outbox outbox_;
  std::vector<std::unique_ptr<RenderLane>> lanes_;
  std::vector<Clock::time_point> wantSince_;
  std::set<int> waiting_;  // lanes whose request rank 0 has not answered yet
  int lanesRunning_ = 0;
  bool lanesFinished_ = false;
  Clock::time_point start_, lanesDone_;
  RankReport own_;

  StopReason stop_ = kStopNone;
  bool flat_ = false, signalSeen_ = false;  // signalSeen_: this rank's own stop signal
  int signal_ = 0;  // rank 0: the first stop signal of the job
  Clock::time_point stopAt_;
  std::string why_;  // the first reason to stop early

  std::set<int> childrenLeft_;
  std::vector<std::unique_ptr<FilmTransferIn>> incoming_;
  std::unique_ptr<FilmTransferOut> outgoing_;
  bool handedOver_ = false, handedOverDone_ = false;  // films sent; and delivered
  std::vector<RankReport> reports_;  // the ranks whose samples this rank holds

  // Rank 0.
  std::unique_ptr<LeafScheduler> scheduler_;
  std::vector<Clock::time_point> lastHeard_;
  std::vector<uint64_t> progress_;
  std::set<int> handed_, lost_;
  StopReason stopSent_ = kStopNone;
  Clock::time_point lastHeartbeat_, lastProgress_;
  // Workers.
  Clock::time_point lastHeardRoot_;
};

}  // namespace pt::mpi
