#include "src/distributed/render_lane.h"

#include <chrono>
#include <exception>
#include <functional>
#include <new>
#include <utility>

namespace pt {
void LaneInbox::Post(LaneEvent event) {
  std::lock_guard<std::mutex> lock(mutex_);
  events_.push_back(std::move(event));
}

std::optional<LaneEvent> LaneInbox::TryPop() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (events_.empty()) return std::nullopt;
  LaneEvent event = std::move(events_.front());
  events_.pop_front();
  return event;
}

RenderLane::RenderLane(int index, SessionMaker make, const Scene& scene,
                       RenderOptions options, const ChunkTree& tree, LaneShared& shared)
    : index_(index), make_(std::move(make)), scene_(scene), options_(options), tree_(tree),
      shared_(shared) {
  thread_ = std::thread([this] { Run(); });
}

RenderLane::~RenderLane() {
  Grant(std::nullopt);  // a lane still waiting ends
  if (thread_.joinable()) thread_.join();
}

void RenderLane::Grant(std::optional<uint32_t> leaf) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    grant_ = leaf;
  }
  granted_.notify_one();
}

std::optional<uint32_t> RenderLane::WaitForGrant() {
  std::unique_lock<std::mutex> lock(mutex_);
  granted_.wait(lock, [&] { return grant_.has_value(); });
  std::optional<uint32_t> leaf = *grant_;
  grant_.reset();
  return leaf;
}

namespace {

// The previous leaf's save, on a thread of its own while the lane renders the next leaf: the
// GPU does not wait for the download and the widening.
class LeafSaver {
 public:
  LeafSaver() = default;
  LeafSaver(const LeafSaver&) = delete;
  LeafSaver& operator=(const LeafSaver&) = delete;
  ~LeafSaver() {
    if (thread_.joinable()) thread_.join();
  }
  // Waits for the save in flight; rethrows what it threw.
  void Wait() {
    if (thread_.joinable()) thread_.join();
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }
  void Start(std::function<void()> save) {
    Wait();
    thread_ = std::thread([this, save = std::move(save)] {
      try {
        save();
      } catch (...) {
        error_ = std::current_exception();
      }
    });
  }

 private:
  std::thread thread_;
  std::exception_ptr error_;
};

}  // namespace

void RenderLane::Run() {
  using Clock = std::chrono::steady_clock;
  auto post = [&](LaneEvent e) {
    e.lane = index_;
    shared_.inbox.Post(std::move(e));
  };
  auto event = [](LaneEvent::Kind kind, std::string message = "") {
    LaneEvent e;
    e.kind = kind;
    e.message = std::move(message);
    return e;
  };
  try {
    uint64_t reported = 0;  // samples of the current leaf already counted
    RenderCallbacks callbacks;
    callbacks.shouldStop = [this] { return shared_.stop.load(std::memory_order_relaxed); };
    callbacks.onProgress = [this, &reported](uint64_t done, uint64_t) {
      shared_.samples += done - reported;
      reported = done;
    };
    std::unique_ptr<RenderSession> session = make_(scene_, options_, callbacks);
    // Stats() allocates and uploads the scene now: start-up, not render time.
    LaneEvent ready = event(LaneEvent::kReady);
    ready.stats = session->Stats();  // names the backend and device
    post(std::move(ready));
    LeafSaver saver;  // declared after the session: done with it before it goes
    while (!shared_.stop.load()) {
      post(event(LaneEvent::kWantLeaf));
      std::optional<uint32_t> leaf = WaitForGrant();
      if (!leaf) break;
      reported = 0;
      LeafRender rendered = RenderLeafSamples(*session, tree_, *leaf);
      saver.Wait();  // the previous leaf's save still reads the snapshot
      session->SnapshotFilm();
      saver.Start([&, leaf = *leaf, rendered] {
        Clock::time_point s0 = Clock::now();
        LaneEvent done = event(LaneEvent::kLeafDone);
        done.film = shared_.films.Take();
        session->SaveSnapshotInto(done.film);
        done.leaf = leaf;
        done.samples = rendered.samples;
        done.renderMs = rendered.renderMs;
        done.saveMs = Ms(s0, Clock::now());
        post(std::move(done));
      });
    }
    saver.Wait();
    LaneEvent finished = event(LaneEvent::kFinished);
    finished.stats = session->Stats();
    post(std::move(finished));
  } catch (const std::bad_alloc&) {
    post(event(LaneEvent::kFailed, "out of memory"));
  } catch (const std::exception& e) {
    post(event(LaneEvent::kFailed, e.what()));
  }
}

}  // namespace pt
