// Collects films of chunk-tree nodes, in any order and from any process, and merges each
// node with its sibling as soon as both are held, along the ChunkTree: the result depends on
// the tree alone. Each process keeps one; what it holds at the end travels to the next.
#pragma once

#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "src/distributed/chunk_tree.h"
#include "src/distributed/film_pool.h"
#include "src/integrator/render_api.h"

namespace pt {

class FilmAssembler {
 public:
  // Films merged into a sibling go to `pool` (when given) for their memory to be reused.
  explicit FilmAssembler(ChunkTree tree, int mergeThreads = 1, FilmPool* pool = nullptr)
      : tree_(tree), mergeThreads_(mergeThreads), pool_(pool) {}

  const ChunkTree& Tree() const { return tree_; }

  // Adds the film of a tree node and merges upwards while siblings are held. Throws
  // std::logic_error for a range that is no tree node or overlaps one held already.
  void Add(const ChunkNode& node, FilmState film);

  // Hands over every node held (in leaf order) and holds nothing afterwards.
  std::vector<std::pair<ChunkNode, FilmState>> Take();

  // The root film. Nodes never added (an interrupted or failed render) count as films with
  // no samples; nullopt when none was.
  std::optional<FilmState> TakeRoot();
  // The same, with `empty` (a film of the right size and channels) when none was added.
  FilmState Finish(FilmState empty);

  uint32_t LeavesHeld() const;
  size_t NodesHeld() const { return nodes_.size(); }
  // Milliseconds spent merging so far.
  double MergeMs() const { return mergeMs_; }

 private:
  FilmState Merged(FilmState left, FilmState right);

  ChunkTree tree_;
  int mergeThreads_;
  FilmPool* pool_;
  std::map<ChunkNode, FilmState> nodes_;
  double mergeMs_ = 0.0;
};

}  // namespace pt
