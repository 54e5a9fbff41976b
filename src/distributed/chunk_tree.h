// The fixed order in which the films of sample chunks are combined. A render's samples
// [0, spp) are cut into `chunks` leaves of consecutive samples; each leaf is rendered into its
// own film (every pixel's samples in order, Welford), and leaf films are merged pairwise along
// one binary tree that depends only on (spp, chunks): node [a, b) of leaves is the merge of
// [a, m) and [m, b), m = (a + b) / 2, the lower samples always on the left. Which process
// rendered which leaf, and in which order films arrive, cannot change a bit of the result.
#pragma once

#include <cstdint>
#include <vector>

namespace pt {

// A node of the tree: leaves [begin, end).
struct ChunkNode {
  uint32_t begin = 0, end = 0;
  uint32_t Leaves() const { return end - begin; }
  bool IsLeaf() const { return end == begin + 1; }
  bool operator==(const ChunkNode&) const = default;
  bool operator<(const ChunkNode& o) const {
    return begin != o.begin ? begin < o.begin : end < o.end;
  }
};

class ChunkTree {
 public:
  // Throws std::invalid_argument unless 1 <= chunks <= spp.
  ChunkTree(uint32_t spp, uint32_t chunks);

  uint32_t Spp() const { return spp_; }
  uint32_t Chunks() const { return chunks_; }
  ChunkNode Root() const { return {0, chunks_}; }
  static ChunkNode Leaf(uint32_t k) { return {k, k + 1}; }

  // The samples [first, last) a leaf or node covers.
  uint32_t FirstSample(const ChunkNode& node) const;
  uint32_t EndSample(const ChunkNode& node) const;

  static uint32_t Split(const ChunkNode& node) { return node.begin + node.Leaves() / 2; }
  static ChunkNode Left(const ChunkNode& node) { return {node.begin, Split(node)}; }
  static ChunkNode Right(const ChunkNode& node) { return {Split(node), node.end}; }

  // True when node is one of the tree's nodes (not merely a range of leaves).
  bool IsNode(const ChunkNode& node) const;
  // The parent of a node other than the root, and the other child of that parent.
  ChunkNode Parent(const ChunkNode& node) const;
  ChunkNode Sibling(const ChunkNode& node) const;

  // The fewest tree nodes that exactly cover leaves [begin, end), in leaf order.
  std::vector<ChunkNode> Cover(uint32_t begin, uint32_t end) const;

 private:
  uint32_t spp_, chunks_;
};

}  // namespace pt
