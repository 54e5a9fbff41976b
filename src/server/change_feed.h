// What every page of the preview follows: version counters of the server's state (camera,
// options, display, selection, lighting), of the scene description (objects, materials) and
// of the render's progress; a page's event stream waits here for any of them to move.
#pragma once

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>

namespace pt {

class ChangeFeed {
 public:
  enum Topic { kState = 0, kScene = 1, kProgress = 2 };
  static constexpr int kTopics = 3;
  using Versions = std::array<uint64_t, kTopics>;

  void Bump(Topic topic) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++versions_[topic];
    }
    changed_.notify_all();
  }

  Versions Current() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return versions_;
  }

  // The versions once any differs from `seen`, or when the timeout passes or the feed closes.
  Versions Wait(const Versions& seen, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait_for(lock, timeout, [&] { return closed_ || versions_ != seen; });
    return versions_;
  }

  // Wakes every waiter for good (the server is stopping).
  void Close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    changed_.notify_all();
  }
  bool Closed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closed_;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  Versions versions_{};
  bool closed_ = false;
};

}  // namespace pt
