// The live preview on the CUDA backend: it converges, a camera edit restarts the film and its
// first frame comes, and the flags switch live. Skips without a GPU or without the server.
#include <gtest/gtest.h>

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
#else
TEST(ServeGpu, SkippedWithoutTheServer) { GTEST_SKIP() << "built without cpp-httplib"; }
#endif

}  // namespace
}  // namespace pt::test
