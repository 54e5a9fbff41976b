#include "src/distributed/mpi_rank_loop.h"

#include <algorithm>
#include <array>
#include <thread>

#include "src/distributed/film_merge.h"

namespace pt::mpi {
namespace {

using Clock = std::chrono::steady_clock;

int LowestBit(int r) { return r & -r; }

// Rank r's children in the binomial tree: r + 2^k below r's lowest set bit (every k for 0).
std::set<int> Children(int rank, int size) {
  std::set<int> children;
  for (int step = 1; rank + step < size; step <<= 1) {
    if (rank != 0 && step >= LowestBit(rank)) break;
    children.insert(rank + step);
  }
  return children;
}

}  // namespace

RankLoop::RankLoop(MpiJobImpl& job, const SessionMaker& make, const Scene& scene,
                   const RenderOptions& options, const DistributedOptions& distributed,
                   const std::function<void(uint64_t, uint64_t)>& onProgress,
                   const StopSignalSource& stopSignal)
    : job_(job), comm_(job.Comm()), rank_(job.Rank()), size_(job.Size()), make_(make),
      scene_(scene), options_(options), distributed_(distributed), onProgress_(onProgress),
      stopSignal_(stopSignal), tree_(uint32_t(scene.desc.render.spp), distributed.chunks),
      assembler_(tree_, distributed.mergeThreads, &shared_.films), outbox_(job.Comm()) {
  childrenLeft_ = Children(rank_, size_);
  const RenderSettings& r = scene.desc.render;
  CropWindow crop = options.crop.Empty() ? CropWindow{0, 0, r.width, r.height} : options.crop;
  filmWidth_ = uint32_t(crop.x1 - crop.x0);
  filmHeight_ = uint32_t(crop.y1 - crop.y0);
}

// Makes the lanes (sessions allocated, scene uploaded) and agrees with every rank that all
// are ready: a rank whose lane failed (no GPU, out of memory) fails the job before it starts.
std::pair<int, std::string> RankLoop::StartLanes() {
  Clock::time_point t0 = Clock::now();
  for (int i = 0; i < distributed_.lanes; ++i)
    lanes_.push_back(std::make_unique<RenderLane>(i, make_, scene_, options_, tree_, shared_));
  wantSince_.assign(lanes_.size(), t0);
  lanesRunning_ = int(lanes_.size());
  int status = 0, ready = 0;
  std::string message;
  std::vector<LaneEvent> early;  // each lane's first request
  while (ready < int(lanes_.size()) && status == 0) {
    std::optional<LaneEvent> e = shared_.inbox.TryPop();
    if (!e) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      continue;
    }
    if (e->kind == LaneEvent::kReady) {
      ++ready;
      OnLaneEvent(*e);
    }
    else if (e->kind == LaneEvent::kFailed) status = 3, message = e->message;
    else early.push_back(std::move(*e));
  }
  own_.startupMs = Ms(t0, Clock::now());
  auto agreed = job_.Agree(status, message);
  for (LaneEvent& e : early) shared_.inbox.Post(std::move(e));
  return agreed;
}

DistributedResult RankLoop::Run() {
  own_.rank = rank_;
  own_.host = job_.Host();
  own_.lanes = distributed_.lanes;
  StockFilms();  // beside the lanes' start-up
  auto [status, message] = StartLanes();
  if (status != 0) {
    shared_.stop = true;
    lanes_.clear();
    DistributedResult failed;
    failed.why = message;
    failed.status = status;
    return failed;
  }
  std::vector<uint64_t> lanesPerRank = job_.AllGather(uint64_t(lanes_.size()));
  if (IsRoot()) {
    scheduler_ = std::make_unique<LeafScheduler>(
        tree_.Chunks(), std::vector<int>(lanesPerRank.begin(), lanesPerRank.end()));
  }
  start_ = lastHeartbeat_ = lastProgress_ = lastHeardRoot_ = Clock::now();
  lastHeard_.assign(size_t(size_), start_);
  progress_.assign(size_t(size_), 0);
  while (!Finished()) {
    // Large messages move only while MPI is called (without single-copy shared memory, a
    // fragment per call): no sleeping while films are on the way.
    bool moving = !incoming_.empty() || (outgoing_ && !handedOverDone_);
    if (!Step() && !moving) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return Finish();
}

// Warm films for the leaves' saves and the children's films: about as many as this rank
// holds at once (one a lane, one a level of the tree over its share of the leaves).
void RankLoop::StockFilms() {
  uint32_t share = std::max<uint32_t>(1, tree_.Chunks() / uint32_t(size_));
  size_t levels = 0;
  while ((uint32_t(1) << levels) < share) ++levels;
  shared_.films.Stock(size_t(distributed_.lanes) + levels,
                      [w = filmWidth_, h = filmHeight_, f = options_.featureBuffers,
                       halves = options_.halfFilms] { return EmptyFilm(w, h, f, halves); });
}

bool RankLoop::Step() {
  bool busy = false;
  while (std::optional<LaneEvent> e = shared_.inbox.TryPop()) {
    OnLaneEvent(*e);
    busy = true;
  }
  busy = PollControl() || busy;
  busy = PollTransfers() || busy;
  outbox_.Progress();
  CheckTimers();
  if (!IsRoot()) MaybeHandOver();
  return busy;
}

void RankLoop::OnLaneEvent(LaneEvent& e) {
  switch (e.kind) {
    case LaneEvent::kReady:
      own_.backend = e.stats.backend;
      own_.device = e.stats.device;
      break;
    case LaneEvent::kWantLeaf:
      wantSince_[size_t(e.lane)] = Clock::now();
      if (stop_ != kStopNone) {
        GrantLane(e.lane, std::nullopt);
      } else if (IsRoot()) {
        OnRequest(0, e.lane);
      } else {
        waiting_.insert(e.lane);
        outbox_.SendValue(0, kTagRequest, int32_t(e.lane));
      }
      break;
    case LaneEvent::kLeafDone:
      assembler_.Add(ChunkTree::Leaf(e.leaf), std::move(e.film));
      ++own_.leaves;
      own_.samples += e.samples;
      own_.renderMs += e.renderMs;
      own_.saveMs += e.saveMs;
      break;
    case LaneEvent::kFailed:
      --lanesRunning_;
      own_.failure = e.message;
      if (IsRoot()) {
        StopAll(kStopFailure, "rank 0: " + e.message);
      } else {
        std::vector<char> bytes(sizeof(int32_t));
        int32_t kind = kEventFailed;
        std::copy_n(reinterpret_cast<const char*>(&kind), sizeof(kind), bytes.data());
        bytes.insert(bytes.end(), e.message.begin(), e.message.end());
        outbox_.Send(0, kTagEvent, std::move(bytes));
        StopLocal(kStopFailure);
      }
      break;
    case LaneEvent::kFinished:
      --lanesRunning_;
      AddRenderStats(own_.stats, e.stats);
      break;
  }
  if (lanesRunning_ == 0 && !lanesFinished_) {
    lanesFinished_ = true;
    lanesDone_ = Clock::now();
    own_.finishedMs = Ms(start_, lanesDone_);
  }
}

void RankLoop::GrantLane(int lane, std::optional<uint32_t> leaf) {
  own_.waitMs += Ms(wantSince_[size_t(lane)], Clock::now());
  lanes_[size_t(lane)]->Grant(leaf);
}

void RankLoop::StopLocal(StopReason reason) {
  if (reason <= stop_) return;
  if (stop_ == kStopNone) stopAt_ = Clock::now();
  stop_ = reason;
  flat_ = flat_ || reason >= kStopInterrupt;
  shared_.stop = true;
  for (int lane : waiting_) GrantLane(lane, std::nullopt);
  waiting_.clear();
  if (scheduler_) scheduler_->Close();
}

void RankLoop::StopAll(StopReason reason, const std::string& why) {
  if (why_.empty()) why_ = why;
  StopLocal(reason);
  if (reason <= stopSent_) return;
  stopSent_ = reason;
  for (int r = 1; r < size_; ++r)
    if (!lost_.count(r)) outbox_.SendValue(r, kTagStop, int32_t(reason));
}

void RankLoop::OnRequest(int rank, int lane) {
  std::optional<uint32_t> leaf;
  if (stop_ == kStopNone) leaf = scheduler_->Next(rank);
  if (rank == 0) {
    GrantLane(lane, leaf);
  } else {
    outbox_.SendValue(rank, kTagGrant,
                      std::array<int32_t, 2>{lane, leaf ? int32_t(*leaf) : -1});
  }
}

bool RankLoop::PollControl() { return IsRoot() ? PollRootControl() : PollWorkerControl(); }

bool RankLoop::PollRootControl() {
  bool busy = false;
  std::vector<char> bytes;
  int from = 0;
  Clock::time_point now = Clock::now();
  while (TryReceive(comm_, MPI_ANY_SOURCE, kTagRequest, &bytes, &from)) {
    lastHeard_[size_t(from)] = now;
    OnRequest(from, ValueOf<int32_t>(bytes));
    busy = true;
  }
  while (TryReceive(comm_, MPI_ANY_SOURCE, kTagProgress, &bytes, &from)) {
    lastHeard_[size_t(from)] = now;
    progress_[size_t(from)] = ValueOf<uint64_t>(bytes);
  }
  while (TryReceive(comm_, MPI_ANY_SOURCE, kTagHandedOver, &bytes, &from)) {
    lastHeard_[size_t(from)] = now;
    handed_.insert(from);
  }
  while (TryReceive(comm_, MPI_ANY_SOURCE, kTagEvent, &bytes, &from)) {
    lastHeard_[size_t(from)] = now;
    std::string text(bytes.begin() + std::min<size_t>(4, bytes.size()), bytes.end());
    std::string who = "rank " + std::to_string(from);
    if (ValueOf<int32_t>(bytes) == kEventFailed) {
      StopAll(kStopFailure, who + ": " + text);
    } else {
      if (signal_ == 0) signal_ = ValueOf<int32_t>(bytes, sizeof(int32_t));
      StopAll(kStopInterrupt, who + " was interrupted");
    }
    busy = true;
  }
  return busy;
}

bool RankLoop::PollWorkerControl() {
  bool busy = false;
  std::vector<char> bytes;
  int from = 0;
  while (TryReceive(comm_, 0, kTagGrant, &bytes, &from)) {
    lastHeardRoot_ = Clock::now();
    int lane = ValueOf<int32_t>(bytes);
    int32_t leaf = ValueOf<int32_t>(bytes, sizeof(int32_t));
    if (waiting_.erase(lane)) {
      GrantLane(lane, leaf >= 0 ? std::optional<uint32_t>(uint32_t(leaf)) : std::nullopt);
    }
    busy = true;
  }
  while (TryReceive(comm_, 0, kTagStop, &bytes, &from)) {
    lastHeardRoot_ = Clock::now();
    StopLocal(StopReason(ValueOf<int32_t>(bytes)));
    busy = true;
  }
  while (TryReceive(comm_, 0, kTagHeartbeat, &bytes, &from)) lastHeardRoot_ = Clock::now();
  while (TryReceive(comm_, MPI_ANY_SOURCE, kTagWentToRoot, &bytes, &from)) {
    childrenLeft_.erase(from);
    busy = true;
  }
  return busy;
}

void RankLoop::CheckTimers() {
  Clock::time_point now = Clock::now();
  int signal = signalSeen_ ? 0 : stopSignal_();
  if (signal != 0) {
    signalSeen_ = true;
    if (signal_ == 0) signal_ = signal;
    if (IsRoot()) {
      StopAll(kStopInterrupt, "rank 0 was interrupted (a stop signal; mpirun sends SIGTERM "
                              "to every rank when it is interrupted or a rank dies)");
    } else {
      outbox_.SendValue(0, kTagEvent, std::array<int32_t, 2>{kEventInterrupted, signal});
      StopLocal(kStopInterrupt);
    }
  }
  if (IsRoot()) {
    CheckRootTimers(now);
    return;
  }
  if (!handedOver_ && Ms(lastProgress_, now) >= 250.0) {
    outbox_.SendValue(0, kTagProgress, uint64_t(shared_.samples.load()));
    lastProgress_ = now;
  }
  double silent = Ms(lastHeardRoot_, now) / 1000.0;
  if (!handedOver_ && silent > distributed_.rankTimeoutSeconds) {
    throw MpiFailure("rank 0 has not answered for " + std::to_string(int(silent)) + " s");
  }
}

void RankLoop::CheckRootTimers(Clock::time_point now) {
  double limit = distributed_.timeLimitSeconds;
  if (limit > 0.0 && stop_ == kStopNone && Ms(start_, now) >= limit * 1000.0)
    StopAll(kStopTimeLimit, "");  // the normal end of a timed render: no message
  if (onProgress_ && Ms(lastProgress_, now) >= 100.0) {
    uint64_t done = shared_.samples.load();
    for (int r = 1; r < size_; ++r) done += progress_[size_t(r)];
    onProgress_(done, uint64_t(filmWidth_) * filmHeight_ * tree_.Spp());
    lastProgress_ = now;
  }
  if (Ms(lastHeartbeat_, now) >= 1000.0) {
    for (int r = 1; r < size_; ++r)
      if (!lost_.count(r)) outbox_.SendValue(r, kTagHeartbeat, int32_t(0));
    lastHeartbeat_ = now;
  }
  std::set<int> accounted;
  for (const RankReport& r : reports_) accounted.insert(r.rank);
  for (int r = 1; r < size_; ++r) {
    if (accounted.count(r) || handed_.count(r) || lost_.count(r)) continue;
    double silent = Ms(lastHeard_[size_t(r)], now) / 1000.0;
    if (silent > distributed_.rankTimeoutSeconds) {
      lost_.insert(r);
      StopAll(kStopLost, "rank " + std::to_string(r) + " has not answered for " +
                             std::to_string(int(silent)) + " s (hung, or its host is gone)");
    }
  }
}

}  // namespace pt::mpi
