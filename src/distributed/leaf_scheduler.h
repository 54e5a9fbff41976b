// Rank 0's hand-out of chunk-tree leaves. Each rank starts with a contiguous range of
// leaves in proportion to its weight (its render lanes), so that most merges happen inside a
// rank; a lane asks for one leaf at a time. A rank whose range is used up takes the upper
// half of what is left of the range with most leaves left (work stealing), so ranks of
// unequal speed finish within about one leaf of each other. Leaves are handed out one at a
// time by this one object, so no leaf is ever given twice. Pure logic: no MPI.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace pt {

class LeafScheduler {
 public:
  // weights[r] > 0: rank r's share of the first split (its lanes).
  LeafScheduler(uint32_t leaves, const std::vector<int>& weights);

  // The next leaf for one of rank r's lanes; nullopt when no leaf is left anywhere.
  std::optional<uint32_t> Next(int rank);
  // No further leaves are handed out (a stop).
  void Close();

  uint32_t LeavesLeft() const;
  uint32_t Steals() const { return steals_; }

 private:
  struct Range {
    uint32_t next = 0, end = 0;
    uint32_t Left() const { return end - next; }
  };
  std::vector<Range> ranges_;
  uint32_t steals_ = 0;
};

}  // namespace pt
