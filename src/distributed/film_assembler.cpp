#include "src/distributed/film_assembler.h"

#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>

#include "src/distributed/film_merge.h"

namespace pt {
namespace {

std::string Name(const ChunkNode& n) {
  return "[" + std::to_string(n.begin) + ", " + std::to_string(n.end) + ")";
}

bool Overlap(const ChunkNode& a, const ChunkNode& b) { return a.begin < b.end && b.begin < a.end; }

}  // namespace

FilmState FilmAssembler::Merged(FilmState left, FilmState right) {
  auto t0 = std::chrono::steady_clock::now();
  MergeFilmInto(left, right, mergeThreads_);
  mergeMs_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                  .count();
  if (pool_) pool_->Give(std::move(right));
  return left;
}

void FilmAssembler::Add(const ChunkNode& node, FilmState film) {
  if (!tree_.IsNode(node)) throw std::logic_error("chunk range " + Name(node) + " is no tree node");
  for (const auto& [held, f] : nodes_) {
    if (Overlap(held, node))
      throw std::logic_error("chunk node " + Name(node) + " overlaps " + Name(held) +
                             ", held already");
  }
  ChunkNode n = node;
  while (n != tree_.Root()) {
    auto sibling = nodes_.find(tree_.Sibling(n));
    if (sibling == nodes_.end()) break;
    bool left = n.begin < sibling->first.begin;
    FilmState other = std::move(sibling->second);
    nodes_.erase(sibling);
    film = left ? Merged(std::move(film), std::move(other))
                : Merged(std::move(other), std::move(film));
    n = tree_.Parent(n);
  }
  nodes_.emplace(n, std::move(film));
}

std::vector<std::pair<ChunkNode, FilmState>> FilmAssembler::Take() {
  std::vector<std::pair<ChunkNode, FilmState>> out;
  for (auto& [node, film] : nodes_) out.emplace_back(node, std::move(film));
  nodes_.clear();
  return out;
}

std::optional<FilmState> FilmAssembler::TakeRoot() {
  // The same merges Add makes, with missing nodes as identities.
  auto build = [&](auto& self, const ChunkNode& node) -> std::optional<FilmState> {
    auto held = nodes_.find(node);
    if (held != nodes_.end()) {
      FilmState f = std::move(held->second);
      nodes_.erase(held);
      return f;
    }
    if (node.IsLeaf()) return std::nullopt;
    std::optional<FilmState> left = self(self, ChunkTree::Left(node));
    std::optional<FilmState> right = self(self, ChunkTree::Right(node));
    if (left && right) return Merged(std::move(*left), std::move(*right));
    return left ? std::move(left) : std::move(right);
  };
  return build(build, tree_.Root());
}

FilmState FilmAssembler::Finish(FilmState empty) {
  std::optional<FilmState> root = TakeRoot();
  return root ? std::move(*root) : std::move(empty);
}

uint32_t FilmAssembler::LeavesHeld() const {
  uint32_t leaves = 0;
  for (const auto& [node, film] : nodes_) leaves += node.Leaves();
  return leaves;
}

}  // namespace pt
