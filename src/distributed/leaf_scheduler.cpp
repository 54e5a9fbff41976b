#include "src/distributed/leaf_scheduler.h"

#include <stdexcept>

namespace pt {

LeafScheduler::LeafScheduler(uint32_t leaves, const std::vector<int>& weights) {
  if (weights.empty()) throw std::invalid_argument("leaf scheduler: no ranks");
  uint64_t total = 0;
  for (int w : weights) {
    if (w <= 0) throw std::invalid_argument("leaf scheduler: a rank weight must be positive");
    total += uint64_t(w);
  }
  ranges_.resize(weights.size());
  uint64_t before = 0;
  for (size_t r = 0; r < weights.size(); ++r) {
    ranges_[r].next = uint32_t(before * leaves / total);
    before += uint64_t(weights[r]);
    ranges_[r].end = uint32_t(before * leaves / total);
  }
}

std::optional<uint32_t> LeafScheduler::Next(int rank) {
  Range& own = ranges_.at(size_t(rank));
  if (own.Left() == 0) {
    // Steal the upper half (rounded up) of the range with the most leaves left.
    size_t victim = 0;
    for (size_t r = 1; r < ranges_.size(); ++r)
      if (ranges_[r].Left() > ranges_[victim].Left()) victim = r;
    Range& v = ranges_[victim];
    if (v.Left() == 0) return std::nullopt;
    uint32_t take = (v.Left() + 1) / 2;
    own.next = v.end - take;
    own.end = v.end;
    v.end -= take;
    ++steals_;
  }
  return own.next++;
}

void LeafScheduler::Close() {
  for (Range& r : ranges_) r.next = r.end;
}

uint32_t LeafScheduler::LeavesLeft() const {
  uint32_t left = 0;
  for (const Range& r : ranges_) left += r.Left();
  return left;
}

}  // namespace pt
