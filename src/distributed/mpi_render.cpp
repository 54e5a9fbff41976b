// The films' way up the tree of ranks, the end of a rank's loop, and RenderDistributed.
#include <algorithm>
#include <csignal>

#include "src/distributed/film_merge.h"
#include "src/distributed/mpi_rank_loop.h"

namespace pt {
namespace mpi {

bool RankLoop::PollTransfers() {
  bool busy = false;
  // Children's films (and, after a stop, anyone's on rank 0).
  while (std::unique_ptr<FilmTransferIn> in = FilmTransferIn::TryStart(comm_, MPI_ANY_SOURCE,
                                                                         &shared_.films)) {
    if (IsRoot()) lastHeard_[size_t(in->Source())] = Clock::now();
    incoming_.push_back(std::move(in));
    busy = true;
  }
  for (auto it = incoming_.begin(); it != incoming_.end();) {
    if (!(*it)->Done()) {
      ++it;
      continue;
    }
    for (auto& [node, film] : (*it)->TakeFilms()) assembler_.Add(node, std::move(film));
    const std::vector<RankReport>& reports = (*it)->Reports();
    reports_.insert(reports_.end(), reports.begin(), reports.end());
    childrenLeft_.erase((*it)->Source());
    it = incoming_.erase(it);
    busy = true;
  }
  return busy;
}

// After a stop other than the time limit: how long rank 0 (and a rank waiting for children)
// waits for the others' films. Short when this rank was signalled itself: that is how mpirun
// tears a job down (a rank died, or Ctrl-C), and it kills every rank a second later.
double RankLoop::GraceSeconds() const {
  if (signalSeen_) return 0.5;
  if (stop_ == kStopLost) return 2.0;
  return distributed_.rankTimeoutSeconds;
}

bool RankLoop::GraceOver() const {
  return flat_ && Ms(stopAt_, Clock::now()) >= GraceSeconds() * 1000.0;
}

// A rank hands its films on once its lanes are done and every child has either sent its
// films here or said it sent them to rank 0; after a stop, a silent child is given up once
// the grace period is over.
void RankLoop::MaybeHandOver() {
  if (handedOver_ || !lanesFinished_) return;
  if (!(childrenLeft_.empty() && incoming_.empty()) && !GraceOver()) return;
  for (auto& in : incoming_) in->Cancel();  // a child that went silent mid-way
  incoming_.clear();
  int parent = rank_ & (rank_ - 1);
  int dest = flat_ ? 0 : parent;
  own_.mergeMs = assembler_.MergeMs();
  own_.sendMs = Ms(lanesDone_, Clock::now());
  reports_.push_back(own_);
  outgoing_ = std::make_unique<FilmTransferOut>(comm_, dest, reports_, assembler_.Take());
  if (dest != 0) outbox_.SendValue(0, kTagHandedOver, int32_t(dest));
  if (dest != parent) outbox_.SendValue(parent, kTagWentToRoot, int32_t(0));
  handedOver_ = true;
}

bool RankLoop::Finished() {
  if (!IsRoot()) {
    if (!handedOver_) return false;
    handedOverDone_ = handedOverDone_ || outgoing_->Done();
    if (handedOverDone_ && outbox_.Progress() == 0) return true;
    // Rank 0 has finished without these films (they were late after a stop): stop waiting.
    int done = 0;
    Check(MPI_Iprobe(0, kTagDone, comm_, &done, MPI_STATUS_IGNORE), "MPI_Iprobe");
    return done != 0;
  }
  if (!lanesFinished_) return false;
  std::set<int> accounted = lost_;
  accounted.insert(0);
  for (const RankReport& r : reports_) accounted.insert(r.rank);
  if (int(accounted.size()) == size_ && incoming_.empty()) return true;
  if (!GraceOver()) return false;
  for (auto& in : incoming_) in->Cancel();
  incoming_.clear();
  return true;
}

DistributedResult RankLoop::Finish() {
  DistributedResult result;
  result.interrupted = signalSeen_ || stop_ == kStopInterrupt;
  result.timeLimited = stop_ == kStopTimeLimit;
  result.why = why_;
  result.rankLost = !lost_.empty();
  // A worker stopped by rank 0 for another rank's signal knows no number: its status is
  // replaced by rank 0's (ShareExitStatus) anyway.
  result.signal = result.interrupted ? (signal_ != 0 ? signal_ : SIGINT) : 0;
  result.status = stop_ >= kStopFailure ? 3 : result.interrupted ? 128 + result.signal : 0;
  if (!IsRoot()) {
    lanes_.clear();  // every lane has finished: joins their threads
    return result;
  }
  own_.mergeMs = assembler_.MergeMs();
  reports_.push_back(own_);
  std::sort(reports_.begin(), reports_.end(),
            [](const RankReport& a, const RankReport& b) { return a.rank < b.rank; });
  // An empty film only when no node came (making one first cost a 1080p job ~35 ms of
  // fresh pages in its reduction).
  std::optional<FilmState> root = assembler_.TakeRoot();
  result.film = root ? std::move(*root)
                     : EmptyFilm(filmWidth_, filmHeight_, options_.featureBuffers,
                                 options_.halfFilms);
  // The render ends with the root film. Joining the lanes waits for their sessions to free
  // their memory (tens of milliseconds on a GPU), which a one-process render's time leaves
  // out as well.
  result.renderMs = Ms(start_, Clock::now());
  lanes_.clear();
  double lastRank = 0.0;
  for (const RankReport& r : reports_) {
    lastRank = std::max(lastRank, r.finishedMs);
    result.leavesRendered += uint32_t(r.leaves);
    result.samples += r.samples;
  }
  // Ranks time from their own start, which leaves the last collective within a millisecond
  // or so of rank 0's: clamp the skew away.
  result.reductionMs = std::max(0.0, result.renderMs - lastRank);
  result.ranks = std::move(reports_);
  std::string missing;
  for (int r = 0, i = 0; r < size_; ++r) {
    if (i < int(result.ranks.size()) && result.ranks[size_t(i)].rank == r) ++i;
    else missing += (missing.empty() ? "" : ", ") + std::to_string(r);
  }
  if (!missing.empty()) {
    result.why += (result.why.empty() ? "" : "; ") + std::string("the samples of rank(s) ") +
                  missing + " did not arrive";
  }
  return result;
}

}  // namespace mpi

DistributedResult RenderDistributed(MpiJob& job, const SessionMaker& make, const Scene& scene,
                                    const RenderOptions& options,
                                    const DistributedOptions& distributed,
                                    const std::function<void(uint64_t, uint64_t)>& onProgress,
                                    const StopSignalSource& stopSignal) {
  mpi::RankLoop loop(dynamic_cast<mpi::MpiJobImpl&>(job), make, scene, options, distributed,
                     onProgress, stopSignal);
  return loop.Run();
}

}  // namespace pt
