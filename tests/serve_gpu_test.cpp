// The live preview on the CUDA backend: it converges, a camera edit restarts the film and its
// first frame comes, the flags switch live, and instances move through the top level. Skips
// without a GPU or without the server.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "src/integrator/render_session.h"
#include "tests/serve_test_util.h"

namespace pt::test {
namespace {

#if defined(PT_HAVE_SERVER)
TEST(ServeGpu, ConvergesAndRestartsOnTheGpu) {
  if (CudaDeviceCount() <= 0) GTEST_SKIP() << "no CUDA GPU here: runs on a GPU machine";
  Served s(1000000, &MakeCudaSession, 256);
  Served::Frame before = s.WaitFrame(0, 64);
  Json stats = s.GetJson("/api/stats");
  EXPECT_EQ(stats["backend"], "cuda");
  Json g = s.PostJson("/api/camera", R"({"fov_y": 30})");
  Served::Frame after = s.WaitFrame(g["generation"], 1);
  EXPECT_LT(after.spp, before.spp);
  EXPECT_NE(after.jpeg, before.jpeg);
  g = s.PostJson("/api/options", R"({"compact": "off", "sort": "material"})");
  s.WaitFrame(g["generation"], 4);
  stats = s.GetJson("/api/stats");
  EXPECT_EQ(stats["compact_used"], false);
  EXPECT_EQ(stats["sort_used"], true);
  g = s.PostJson("/api/objects/6/move", R"({"translate": [0.1, 0, 0]})");
  s.WaitFrame(g["generation"], 4);
  g = s.PostJson("/api/materials/3", R"({"radiance": [4, 4, 4]})");
  EXPECT_GE(s.WaitFrame(g["generation"], 4).spp, 4u);
}

// An instance moved in the GPU preview: the top-level path (no scene rebuild), and the film
// is the GPU render of the saved scene (up to the order of the passes' sums).
TEST(ServeGpu, InstanceMovesReplaceTheTopLevelOnTheGpu) {
  if (CudaDeviceCount() <= 0) GTEST_SKIP() << "no CUDA GPU here: runs on a GPU machine";
  Served s(8, &MakeCudaSession, 64, "scenes/instanced_shapes.json");
  s.WaitFrame(0, 8);
  std::shared_ptr<const FilmImage> before = s.Live().LatestImage();
  Json g = s.PostJson("/api/objects/3/move", R"({"translate": [-0.4, 0.1, 0]})");
  s.PostJson("/api/objects/7/move", R"({"translate": [0.1, -0.3, 0]})");  // a lamp instance
  g = s.PostJson("/api/objects/3/move", R"({"translate": [0.05, 0, 0]})");
  s.WaitFrame(g["generation"], 8);
  Json stats = s.GetJson("/api/stats");
  EXPECT_EQ(stats["backend"], "cuda");
  EXPECT_EQ(stats["rebuilds"]["scene"], 0) << stats.dump();
  EXPECT_GE(stats["rebuilds"]["top_level"], 1) << stats.dump();
  std::shared_ptr<const FilmImage> shown = s.Live().LatestImage();
  ASSERT_TRUE(before && shown);
  std::string path = TempDir() + "/edited_gpu.json";
  WriteFileAtomic(path, s.Client().Get("/api/scene.json")->body);
  Scene edited = BuildScene(LoadScene(path));
  std::remove(path.c_str());
  RenderResult fresh = RenderCuda(edited, RenderOptions{});
  ASSERT_EQ(fresh.image.rgb.size(), shown->rgb.size());
  double diff = 0.0, moved = 0.0, sum = 0.0;
  for (size_t i = 0; i < shown->rgb.size(); ++i) {
    diff += std::fabs(double(fresh.image.rgb[i]) - double(shown->rgb[i]));
    moved += std::fabs(double(before->rgb[i]) - double(shown->rgb[i]));
    sum += std::fabs(double(shown->rgb[i]));
  }
  EXPECT_LT(diff, 1e-4 * sum) << "the preview's film differs from the saved scene's render";
  EXPECT_GT(moved, 1e-2 * sum) << "the move did not change the image";
}
// Coarse frames on the GPU: a coarse image is the GPU render at its size (up to the order of
// sums), and edits arriving faster than full-resolution samples show coarse frames.
TEST(ServeGpu, CoarseFramesOnTheGpu) {
  if (CudaDeviceCount() <= 0) GTEST_SKIP() << "no CUDA GPU here: runs on a GPU machine";
  SceneDesc desc = LoadScene(SourcePath("scenes/cornell_box.json"));
  desc.render.width = desc.render.height = 64;
  desc.render.spp = 1;
  Scene scene = BuildScene(desc);
  std::unique_ptr<RenderSession> session = MakeCudaSession(scene, RenderOptions{}, RenderCallbacks{});
  session->ResetFilm();
  ASSERT_EQ(session->RenderCoarse(32, 32, 0, 1), 1024u);
  FilmImage coarse = session->Image();
  desc.render.width = desc.render.height = 32;
  RenderResult small = RenderCuda(BuildScene(desc), RenderOptions{});
  double diff = 0.0, sum = 0.0;
  for (size_t i = 0; i < small.image.rgb.size(); ++i) {
    diff += std::fabs(double(coarse.rgb[i]) - double(small.image.rgb[i]));
    sum += std::fabs(double(small.image.rgb[i]));
  }
  EXPECT_LT(diff, 1e-4 * sum);
  Served s(1000000, &MakeCudaSession, 256, "scenes/cornell_box.json",
           [](LiveSettings& l) { l.coarseFrameMs = 1e-3; });
  s.WaitFrame(0, 4);
  Json g;
  for (int i = 0; i < 10; ++i) g = s.PostJson("/api/camera", "{\"fov_y\": " + std::to_string(30 + i) + "}");
  Served::Frame f = s.WaitFrame(g["generation"], 0);
  EXPECT_EQ(f.kind, "coarse") << "the first frame after an edit at this budget";
  EXPECT_EQ(s.WaitFrame(g["generation"], 2).width, 256);
}
#else
TEST(ServeGpu, SkippedWithoutTheServer) { GTEST_SKIP() << "built without cpp-httplib"; }
#endif

}  // namespace
}  // namespace pt::test
