// A render lane: one thread with its own RenderSession, rendering the chunk-tree leaves its
// process hands it, one at a time. A leaf's film is copied on the device and saved by a
// thread of the lane's own while the lane renders the next leaf. A GPU process runs two
// lanes on its device, whose waves fill each other's idle gaps (the bunny on 2 GPUs: 1.38 s
// with two lanes, 1.42-1.43 s with one).
// Lanes never talk to other processes: they post events to their process's main thread and
// wait for its grants. MPI-free.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "src/distributed/chunk_tree.h"
#include "src/distributed/chunked_render.h"
#include "src/distributed/film_pool.h"

namespace pt {

struct LaneEvent {
  enum Kind { kReady, kWantLeaf, kLeafDone, kFailed, kFinished };
  Kind kind = kReady;
  int lane = 0;
  uint32_t leaf = 0;
  uint64_t samples = 0;    // kLeafDone: samples taken (fewer than the leaf's after a stop)
  FilmState film;          // kLeafDone
  double renderMs = 0.0;   // kLeafDone: RenderRange; saveMs: the film's download
  double saveMs = 0.0;
  std::string message;     // kFailed
  RenderStats stats;       // kFinished: the session's statistics
};

// Events from every lane of a process, in the order posted.
class LaneInbox {
 public:
  void Post(LaneEvent event);
  std::optional<LaneEvent> TryPop();

 private:
  std::mutex mutex_;
  std::deque<LaneEvent> events_;
};

// What the lanes of a process share with its main thread.
struct LaneShared {
  std::atomic<bool> stop{false};         // end the current leaf between waves, take no more
  std::atomic<uint64_t> samples{0};      // samples rendered by every lane, for progress
  LaneInbox inbox;
  FilmPool films;                        // merged-away films whose memory the lanes reuse
};

class RenderLane {
 public:
  // Starts the thread: it makes its session (allocating it and uploading the scene), posts
  // kReady or kFailed, and then asks for leaves. The scene, tree and shared state must outlive
  // the lane.
  RenderLane(int index, SessionMaker make, const Scene& scene, RenderOptions options,
             const ChunkTree& tree, LaneShared& shared);
  ~RenderLane();
  RenderLane(const RenderLane&) = delete;
  RenderLane& operator=(const RenderLane&) = delete;

  // Answers the lane's kWantLeaf: a leaf to render, or nullopt (no more: the lane finishes).
  void Grant(std::optional<uint32_t> leaf);

 private:
  void Run();
  std::optional<uint32_t> WaitForGrant();

  int index_;
  SessionMaker make_;
  const Scene& scene_;
  RenderOptions options_;
  const ChunkTree& tree_;
  LaneShared& shared_;
  std::mutex mutex_;
  std::condition_variable granted_;
  std::optional<std::optional<uint32_t>> grant_;
  std::thread thread_;
};

}  // namespace pt
