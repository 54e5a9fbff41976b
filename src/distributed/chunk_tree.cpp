#include "src/distributed/chunk_tree.h"

#include <stdexcept>
#include <string>

namespace pt {
namespace {

void CoverInto(const ChunkNode& node, uint32_t begin, uint32_t end,
               std::vector<ChunkNode>& out) {
  if (end <= node.begin || begin >= node.end) return;
  if (begin <= node.begin && node.end <= end) {
    out.push_back(node);
    return;
  }
  CoverInto(ChunkTree::Left(node), begin, end, out);
  CoverInto(ChunkTree::Right(node), begin, end, out);
}

}  // namespace

ChunkTree::ChunkTree(uint32_t spp, uint32_t chunks) : spp_(spp), chunks_(chunks) {
  if (chunks < 1 || chunks > spp) {
    throw std::invalid_argument("the sample chunks (" + std::to_string(chunks) +
                                ") must be between 1 and spp (" + std::to_string(spp) + ")");
  }
}

uint32_t ChunkTree::FirstSample(const ChunkNode& node) const {
  return uint32_t(uint64_t(node.begin) * spp_ / chunks_);
}

uint32_t ChunkTree::EndSample(const ChunkNode& node) const {
  return uint32_t(uint64_t(node.end) * spp_ / chunks_);
}

bool ChunkTree::IsNode(const ChunkNode& node) const {
  ChunkNode n = Root();
  while (n.Leaves() >= node.Leaves()) {
    if (n == node) return true;
    if (n.IsLeaf()) return false;
    n = node.begin < Split(n) ? Left(n) : Right(n);
  }
  return false;
}

ChunkNode ChunkTree::Parent(const ChunkNode& node) const {
  if (node == Root() || !IsNode(node)) throw std::logic_error("no parent of this chunk node");
  ChunkNode n = Root();
  for (;;) {
    ChunkNode child = node.begin < Split(n) ? Left(n) : Right(n);
    if (child == node) return n;
    n = child;
  }
}

ChunkNode ChunkTree::Sibling(const ChunkNode& node) const {
  ChunkNode parent = Parent(node);
  return Left(parent) == node ? Right(parent) : Left(parent);
}

std::vector<ChunkNode> ChunkTree::Cover(uint32_t begin, uint32_t end) const {
  std::vector<ChunkNode> out;
  CoverInto(Root(), begin, end, out);
  return out;
}

}  // namespace pt
