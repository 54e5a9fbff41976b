// The MPI-free parts of the distributed render: the chunk tree, Chan's merge of Welford films,
// the assembler (whose result must not depend on the order or place of merges), the leaf
// scheduler, the one-process chunked render, and a render lane.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>

#include "src/distributed/chunked_render.h"
#include "src/distributed/film_assembler.h"
#include "src/distributed/film_merge.h"
#include "src/distributed/leaf_scheduler.h"
#include "src/distributed/rank_report.h"
#include "src/distributed/render_lane.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

TEST(ChunkTree, LeavesCoverTheSamplesAndNodesFormOneTree) {
  ChunkTree tree(10, 7);  // uneven leaves: 1 or 2 samples each
  uint32_t next = 0;
  for (uint32_t k = 0; k < 7; ++k) {
    EXPECT_EQ(tree.FirstSample(ChunkTree::Leaf(k)), next);
    next = tree.EndSample(ChunkTree::Leaf(k));
    EXPECT_GT(next, tree.FirstSample(ChunkTree::Leaf(k)));
  }
  EXPECT_EQ(next, 10u);
  EXPECT_EQ(tree.Parent(ChunkTree::Leaf(6)), (ChunkNode{5, 7}));
  EXPECT_EQ(tree.Sibling(ChunkNode{0, 3}), (ChunkNode{3, 7}));
  // [0, 7) splits at 3, [0, 3) at 1: [1, 3) is a node, [0, 2) only a range of leaves.
  EXPECT_TRUE(tree.IsNode(ChunkNode{1, 3}));
  EXPECT_FALSE(tree.IsNode(ChunkNode{0, 2}));
  std::vector<ChunkNode> cover = tree.Cover(1, 6);
  uint32_t covered = 1;
  for (const ChunkNode& n : cover) {
    EXPECT_TRUE(tree.IsNode(n));
    EXPECT_EQ(n.begin, covered);
    covered = n.end;
  }
  EXPECT_EQ(covered, 6u);
  EXPECT_THROW(ChunkTree(4, 5), std::invalid_argument);
  EXPECT_THROW(ChunkTree(4, 0), std::invalid_argument);
}

// A film of `n` pixels holding the Welford statistics of the given samples per pixel.
FilmState WelfordFilm(const std::vector<std::vector<double>>& samples) {
  FilmState f = EmptyFilm(uint32_t(samples.size()), 1, true);
  for (size_t p = 0; p < samples.size(); ++p) {
    double lumMean = 0.0, lumM2 = 0.0;
    for (double x : samples[p]) {
      double k = double(++f.count[p]);
      glm::dvec3 v(x, 2.0 * x, 0.5 * x);
      glm::dvec3 d = v - f.mean[p];
      f.mean[p] += d / k;
      f.m2[p] += d * (v - f.mean[p]);
      double dl = x - lumMean;
      lumMean += dl / k;
      lumM2 += dl * (x - lumMean);
      f.albedoSum[p] += vec3(1.0f);
    }
    f.lumMean[p] = float(lumMean);
    f.lumM2[p] = float(lumM2);
  }
  return f;
}

std::vector<std::vector<double>> RandomSamples(std::mt19937& rng, size_t pixels, int perPixel) {
  std::lognormal_distribution<double> radiance(0.0, 1.5);  // heavy-tailed, like a render's
  std::vector<std::vector<double>> s(pixels);
  for (auto& pixel : s)
    for (int i = 0; i < perPixel; ++i) pixel.push_back(radiance(rng));
  return s;
}

TEST(FilmMerge, EqualsOneWelfordPassOverBothSampleSets) {
  std::mt19937 rng(7);
  auto a = RandomSamples(rng, 64, 13), b = RandomSamples(rng, 64, 29);
  auto both = a;
  for (size_t p = 0; p < both.size(); ++p) both[p].insert(both[p].end(), b[p].begin(), b[p].end());
  FilmState merged = WelfordFilm(a);
  MergeFilmInto(merged, WelfordFilm(b));
  FilmState whole = WelfordFilm(both);
  for (size_t p = 0; p < 64; ++p) {
    ASSERT_EQ(merged.count[p], 42u);
    for (int c = 0; c < 3; ++c) {
      // Both are double-precision computations of the same quantities: rounding only.
      EXPECT_NEAR(merged.mean[p][c], whole.mean[p][c], 1e-12 * std::abs(whole.mean[p][c]));
      EXPECT_NEAR(merged.m2[p][c], whole.m2[p][c], 1e-11 * whole.m2[p][c]);
    }
    EXPECT_NEAR(merged.lumMean[p], whole.lumMean[p], 1e-6 * whole.lumMean[p]);
    EXPECT_NEAR(merged.lumM2[p], whole.lumM2[p], 1e-5 * whole.lumM2[p]);
    EXPECT_EQ(merged.albedoSum[p].x, 42.0f);
  }
}

TEST(FilmMerge, AnEmptySideIsAnExactIdentityAndShapesMustMatch) {
  std::mt19937 rng(3);
  FilmState film = WelfordFilm(RandomSamples(rng, 8, 5));
  FilmState left = film;
  MergeFilmInto(left, EmptyFilm(8, 1, true));
  EXPECT_TRUE(SameFilm(left, film));
  FilmState right = EmptyFilm(8, 1, true);
  MergeFilmInto(right, film);
  EXPECT_TRUE(SameFilm(right, film));
  FilmState other = EmptyFilm(4, 2, true);
  EXPECT_THROW(MergeFilmInto(other, film), std::invalid_argument);
  FilmState noFeatures = EmptyFilm(8, 1, false);
  EXPECT_THROW(MergeFilmInto(noFeatures, film), std::invalid_argument);
}

TEST(FilmMerge, ThreadsDoNotChangeABit) {
  std::mt19937 rng(5);
  auto a = RandomSamples(rng, 200000, 2), b = RandomSamples(rng, 200000, 3);
  FilmState one = WelfordFilm(a), four = WelfordFilm(a), from = WelfordFilm(b);
  MergeFilmInto(one, from, 1);
  MergeFilmInto(four, from, 4);
  EXPECT_TRUE(SameFilm(one, four));
}

TEST(FilmAssembler, TheRootDoesNotDependOnArrivalOrderOrWhereMergesHappen) {
  std::mt19937 rng(11);
  ChunkTree tree(40, 11);
  std::vector<FilmState> leaves;
  for (uint32_t k = 0; k < 11; ++k) leaves.push_back(WelfordFilm(RandomSamples(rng, 16, 3 + k % 4)));
  FilmAssembler inOrder(tree);
  for (uint32_t k = 0; k < 11; ++k) inOrder.Add(ChunkTree::Leaf(k), leaves[k]);
  EXPECT_EQ(inOrder.NodesHeld(), 1u);  // merged up to the root as they came
  FilmState reference = inOrder.Finish(EmptyFilm(16, 1, true));
  for (int trial = 0; trial < 5; ++trial) {
    // Two "ranks" each take a random half of the leaves, merge what they can, and hand
    // their nodes to a third, in random order.
    std::vector<uint32_t> order(11);
    for (uint32_t k = 0; k < 11; ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), rng);
    FilmAssembler a(tree), b(tree), root(tree);
    for (size_t i = 0; i < order.size(); ++i)
      (i % 2 ? a : b).Add(ChunkTree::Leaf(order[i]), leaves[order[i]]);
    auto nodes = a.Take();
    auto more = b.Take();
    nodes.insert(nodes.end(), std::make_move_iterator(more.begin()),
                 std::make_move_iterator(more.end()));
    std::shuffle(nodes.begin(), nodes.end(), rng);
    for (auto& [node, film] : nodes) root.Add(node, std::move(film));
    EXPECT_TRUE(SameFilm(root.Finish(EmptyFilm(16, 1, true)), reference)) << "trial " << trial;
  }
}

TEST(FilmAssembler, MergedAwayFilmsGoToThePoolAndTheRootIsUnchanged) {
  std::mt19937 rng(13);
  ChunkTree tree(8, 4);
  std::vector<FilmState> leaves;
  for (uint32_t k = 0; k < 4; ++k) leaves.push_back(WelfordFilm(RandomSamples(rng, 16, 2)));
  FilmAssembler plain(tree);
  for (uint32_t k = 0; k < 4; ++k) plain.Add(ChunkTree::Leaf(k), leaves[k]);
  FilmPool pool;
  FilmAssembler pooled(tree, 1, &pool);
  FilmState second = leaves[1];
  const glm::dvec3* secondMemory = second.mean.data();
  pooled.Add(ChunkTree::Leaf(0), leaves[0]);
  pooled.Add(ChunkTree::Leaf(1), std::move(second));  // merged into leaf 0's film
  FilmState kept = pool.Take();
  EXPECT_EQ(kept.mean.data(), secondMemory);
  EXPECT_TRUE(pool.Take().mean.empty());  // nothing else was merged away yet
  pooled.Add(ChunkTree::Leaf(2), leaves[2]);
  pooled.Add(ChunkTree::Leaf(3), leaves[3]);  // two merges: leaf 3's film and node [2, 4)'s
  EXPECT_FALSE(pool.Take().mean.empty());
  EXPECT_FALSE(pool.Take().mean.empty());
  EXPECT_TRUE(SameFilm(pooled.Finish(EmptyFilm(16, 1, true)),
                       plain.Finish(EmptyFilm(16, 1, true))));
}

TEST(FilmAssembler, MissingLeavesCountAsEmptyAndOverlapsAreRefused) {
  std::mt19937 rng(2);
  ChunkTree tree(8, 8);
  FilmAssembler partial(tree), withEmpties(tree);
  for (uint32_t k : {0u, 1u, 2u, 5u, 7u}) {
    FilmState f = WelfordFilm(RandomSamples(rng, 4, 2));
    partial.Add(ChunkTree::Leaf(k), f);
    withEmpties.Add(ChunkTree::Leaf(k), f);
  }
  for (uint32_t k : {3u, 4u, 6u}) withEmpties.Add(ChunkTree::Leaf(k), EmptyFilm(4, 1, true));
  EXPECT_EQ(partial.LeavesHeld(), 5u);
  EXPECT_TRUE(SameFilm(partial.Finish(EmptyFilm(4, 1, true)),
                       withEmpties.Finish(EmptyFilm(4, 1, true))));
  FilmAssembler twice(tree);
  twice.Add(ChunkNode{0, 2}, EmptyFilm(4, 1, true));
  EXPECT_THROW(twice.Add(ChunkTree::Leaf(1), EmptyFilm(4, 1, true)), std::logic_error);
  EXPECT_THROW(twice.Add(ChunkNode{2, 5}, EmptyFilm(4, 1, true)), std::logic_error);  // no node
}

TEST(LeafScheduler, EveryLeafOnceWithProportionalStartsAndStealing) {
  LeafScheduler scheduler(37, {1, 2, 1});
  std::vector<int> given(37, 0);
  std::vector<std::vector<uint32_t>> byRank(3);
  // Rank 1 asks twice as often, rank 2 rarely: the others must take over its range.
  std::vector<int> pattern = {0, 1, 1, 0, 1, 1, 2};
  for (size_t i = 0;; ++i) {
    int rank = pattern[i % pattern.size()];
    std::optional<uint32_t> leaf = scheduler.Next(rank);
    if (!leaf) break;
    ++given[*leaf];
    byRank[size_t(rank)].push_back(*leaf);
  }
  for (int g : given) EXPECT_EQ(g, 1);
  EXPECT_EQ(byRank[0].front(), 0u);
  EXPECT_EQ(byRank[1].front(), 9u);   // 37 * 1/4 rounded down
  EXPECT_EQ(byRank[2].front(), 27u);  // 37 * 3/4 rounded down
  EXPECT_GT(scheduler.Steals(), 0u);
  EXPECT_LT(byRank[2].size(), 9u);
  EXPECT_FALSE(scheduler.Next(2).has_value());
  LeafScheduler closed(5, {1});
  closed.Close();
  EXPECT_FALSE(closed.Next(0).has_value());
}

TEST(RankReport, TravelsAsJsonAndGivesTheLoadBalance) {
  RankReport r;
  r.rank = 3;
  r.host = "node7";
  r.backend = "cuda";
  r.device = "NVIDIA H200";
  r.lanes = 2;
  r.leaves = 9;
  r.samples = 123456789012ull;
  r.finishedMs = 2000.0;
  r.saveMs = 12.5;
  r.stats.shadowRays = 77;
  r.stats.stages.shade = 4.25;
  r.stats.specialization = "diffuse";
  RankReport back = RankReportFromJson(RankReportToJson(r));
  EXPECT_EQ(back.rank, 3);
  EXPECT_EQ(back.host, "node7");
  EXPECT_EQ(back.samples, 123456789012ull);
  EXPECT_EQ(back.saveMs, 12.5);
  EXPECT_EQ(back.stats.shadowRays, 77u);
  EXPECT_EQ(back.stats.stages.shade, 4.25);
  EXPECT_EQ(back.stats.device, "NVIDIA H200");
  RankReport early = r;
  early.finishedMs = 1000.0;
  EXPECT_DOUBLE_EQ(LoadBalance({r, early}), 0.75);
}

Scene SmallBox(int spp) { return SmallScene(SourcePath("scenes/cornell_box.json"), 24, 20, spp); }

RenderOptions OneThread() {
  RenderOptions o;
  o.threads = 1;
  return o;
}

TEST(ChunkedRender, OneChunkIsThePlainRenderAndMoreDifferOnlyByRounding) {
  Scene scene = SmallBox(12);
  RenderResult plain = RenderCpu(scene, OneThread());
  RenderResult one = RenderChunked(MakeCpuSession, scene, OneThread(), {}, 1);
  EXPECT_EQ(std::memcmp(plain.image.rgb.data(), one.image.rgb.data(),
                        plain.image.rgb.size() * sizeof(float)),
            0);
  RenderResult five = RenderChunked(MakeCpuSession, scene, OneThread(), {}, 5);
  EXPECT_EQ(five.stats.samples, plain.stats.samples);
  EXPECT_DOUBLE_EQ(five.stats.sppMean, 12.0);
  // Float Welford over n samples errs by at most ~n * eps * (largest sample); a sample is at
  // most |mean| + sqrt(M2) away from zero, with M2 = variance * (n - 1).
  constexpr double kEps = 1.0 / (1 << 24);
  size_t differing = 0;
  for (size_t i = 0; i < plain.image.rgb.size(); ++i) {
    double n = plain.image.samples[i / 3];
    double largest = std::abs(plain.image.rgb[i]) + std::sqrt(plain.image.variance[i] * (n - 1));
    double tolerance = 4.0 * n * kEps * largest;
    EXPECT_LE(std::abs(double(five.image.rgb[i]) - plain.image.rgb[i]), tolerance) << i;
    differing += five.image.rgb[i] != plain.image.rgb[i];
  }
  EXPECT_GT(differing, 0u);  // the merges do round differently: the test can see a change
}

TEST(RenderLane, RendersGrantedLeavesAndReportsAFailedSession) {
  Scene scene = SmallBox(6);
  ChunkTree tree(6, 3);
  LaneShared shared;
  auto next = [&] {
    for (;;)
      if (std::optional<LaneEvent> e = shared.inbox.TryPop()) return std::move(*e);
  };
  {
    RenderLane lane(0, MakeCpuSession, scene, OneThread(), tree, shared);
    EXPECT_EQ(next().kind, LaneEvent::kReady);
    EXPECT_EQ(next().kind, LaneEvent::kWantLeaf);
    // A leaf's film is saved on another thread while the lane asks for the next leaf and
    // renders it: the second leaf is granted as soon as it is asked for, so its render may
    // run beside the first one's save, and must not disturb it.
    lane.Grant(2u);
    std::vector<LaneEvent> done;
    int wants = 0;
    while (wants < 2 || done.size() < 2) {
      LaneEvent e = next();
      if (e.kind == LaneEvent::kLeafDone) done.push_back(std::move(e));
      else ASSERT_EQ(e.kind, LaneEvent::kWantLeaf);
      if (e.kind == LaneEvent::kWantLeaf && ++wants == 1) lane.Grant(0u);
    }
    auto session = MakeCpuSession(scene, OneThread(), {});
    ASSERT_EQ(done.size(), 2u);
    for (size_t k = 0; k < 2; ++k) {
      EXPECT_EQ(done[k].leaf, k == 0 ? 2u : 0u);  // a lane's saves finish in order
      EXPECT_EQ(done[k].samples, 24u * 20u * 2u);
      LeafResult direct = RenderLeaf(*session, tree, done[k].leaf);
      EXPECT_TRUE(SameFilm(done[k].film, direct.film)) << "leaf " << done[k].leaf;
    }
    lane.Grant(std::nullopt);
    EXPECT_EQ(next().kind, LaneEvent::kFinished);
  }
  SessionMaker noGpu = [](const Scene&, const RenderOptions&,
                          const RenderCallbacks&) -> std::unique_ptr<RenderSession> {
    throw BackendUnavailable("no CUDA device");
  };
  RenderLane failing(1, noGpu, scene, OneThread(), tree, shared);
  LaneEvent failed = next();
  EXPECT_EQ(failed.kind, LaneEvent::kFailed);
  EXPECT_EQ(failed.lane, 1);
  EXPECT_EQ(failed.message, "no CUDA device");
}

}  // namespace
}  // namespace pt::test
