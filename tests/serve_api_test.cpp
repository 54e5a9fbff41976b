// The live preview's HTTP API through a real socket: httplib's client on 127.0.0.1 against the
// server of src/server/ rendering a small Cornell box on the CPU. Skips in a build without
// cpp-httplib (the server is optional).
#include <gtest/gtest.h>

#if defined(PT_HAVE_SERVER)
#include <httplib.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

#include "src/io/image_io.h"
#include "src/io/scene_loader.h"
#include "tests/cli_test_util.h"
#include "tests/serve_test_util.h"

namespace pt::test {
namespace {

bool IsJpeg(const std::string& b) { return b.size() > 4 && uint8_t(b[0]) == 0xFF && uint8_t(b[1]) == 0xD8; }

TEST(ServeApi, ServesThePageAndConvergesToTheTargetSpp) {
  Served s(6);
  auto page = s.Client().Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("<script src=\"/app.js\""), std::string::npos);
  EXPECT_EQ(page->get_header_value("X-Frame-Options"), "DENY");
  Served::Frame f = s.WaitFrame(0, 6);
  EXPECT_EQ(f.spp, 6u);
  EXPECT_TRUE(IsJpeg(f.jpeg));
  Json stats = s.GetJson("/api/stats");
  EXPECT_EQ(stats["spp"], 6);
  EXPECT_GT(stats["samples_per_s"].get<double>(), 0.0);
  EXPECT_GT(stats["rays_per_s"].get<double>(), 0.0);
  EXPECT_GT(stats["stage_ms"]["intersect"].get<double>(), 0.0);
  // Converged: no newer frame comes (the long poll answers 204 after its wait).
  auto idle = s.Client().Get(("/api/frame?after=" + std::to_string(f.id)).c_str());
  ASSERT_TRUE(idle);
  EXPECT_EQ(idle->status, 204);
}

TEST(ServeApi, CameraEditRestartsTheAccumulation) {
  Served s(1000000);
  Served::Frame before = s.WaitFrame(0, 64);
  Json g = s.PostJson("/api/camera", R"({"fov_y": 25, "position": [0.3, 1.1, 3.9]})");
  ASSERT_TRUE(g.contains("generation"));
  uint64_t generation = g["generation"];
  EXPECT_GE(generation, 1u);
  Served::Frame after = s.WaitFrame(generation, 1);
  EXPECT_LT(after.spp, before.spp);  // the accumulation started over
  EXPECT_NE(after.jpeg, before.jpeg);
  Json scene = s.GetJson("/api/scene");
  EXPECT_FLOAT_EQ(scene["camera"]["fov_y"].get<float>(), 25.0f);
  EXPECT_FLOAT_EQ(scene["camera"]["position"][0].get<float>(), 0.3f);
  // A camera the loader refuses (fov out of range) is answered 422 and changes nothing.
  s.PostJson("/api/camera", R"({"fov_y": 500})", 422);
  EXPECT_FLOAT_EQ(s.GetJson("/api/scene")["camera"]["fov_y"].get<float>(), 25.0f);
}

TEST(ServeApi, PickMoveAndSaveTheEditedScene) {
  Served s(2);
  s.WaitFrame(0, 1);
  // The tall box (object 6) stands left of the centre; the pixel ray hits it.
  Json hit = s.PostJson("/api/pick", R"({"x": 18, "y": 30})");
  ASSERT_EQ(hit["object"], 6) << hit.dump();
  Json g = s.PostJson("/api/objects/6/move", R"({"translate": [0.7, 0, 0]})");
  s.WaitFrame(g["generation"], 1);
  Json moved = s.PostJson("/api/pick", R"({"x": 18, "y": 30})");
  EXPECT_NE(moved["object"], 6) << moved.dump();  // the box left that pixel
  // The saved scene loads, and has the box where it was moved to.
  auto text = s.Client().Get("/api/scene.json");
  ASSERT_TRUE(text && text->status == 200);
  Json doc = Json::parse(text->body, nullptr, false);
  ASSERT_FALSE(doc.is_discarded());
  std::string path = TempDir() + "/edited.json";
  WriteFileAtomic(path, text->body);
  EXPECT_NO_THROW(LoadScene(path));
  std::remove(path.c_str());
  // The tall box's translation went from -0.33 to +0.37.
  EXPECT_NEAR(doc["objects"][6]["transform"]["translate"][0].get<double>(), 0.37, 1e-5);
  // Bad moves: no such object, not three numbers.
  s.PostJson("/api/objects/99/move", R"({"translate": [1, 0, 0]})", 404);
  s.PostJson("/api/objects/6/move", R"({"translate": [1, 0]})", 400);
  s.PostJson("/api/objects/x/move", R"({"translate": [1, 0, 0]})", 404);
}

// After each kind of edit (one with a scene rebuild, one of the render settings alone).
TEST(ServeApi, TheSavedSceneRendersWhatThePreviewShows) {
  ExpectSavedSceneRendersTheShownFilm(
      {{"/api/camera", R"({"fov_y": 33, "position": [0.2, 1.1, 3.7]})"},
       {"/api/materials/0", R"({"albedo": [0.5, 0.6, 0.7]})"},
       {"/api/objects/7/move", R"({"translate": [-0.1, 0.05, 0.1]})"},
       {"/api/options", R"({"max_depth": 4, "integrator": "nee"})"}},
      IntegratorMode::kNee);
  ExpectSavedSceneRendersTheShownFilm({{"/api/options", R"({"max_depth": 1})"}},
                                      IntegratorMode::kMis);
  ExpectSavedSceneRendersTheShownFilm({{"/api/materials/3", R"({"radiance": [3, 9, 3]})"}},
                                      IntegratorMode::kMis);
}

TEST(ServeApi, MaterialEditsAreCheckedByTheLoader) {
  Served s(2);
  s.WaitFrame(0, 1);
  Json g = s.PostJson("/api/materials/3", R"({"radiance": [1, 1, 1]})");  // the lamp, dimmer
  s.WaitFrame(g["generation"], 1);
  Json doc = Json::parse(s.Client().Get("/api/scene.json")->body, nullptr, false);
  ASSERT_FALSE(doc.is_discarded());
  EXPECT_EQ(doc["materials"]["lamp"]["radiance"], Json::array({1, 1, 1}));
  EXPECT_EQ(doc["materials"]["lamp"]["type"], "emissive");
  s.PostJson("/api/materials/0", R"({"albedo": [2, 0, 0, 7]})", 422);
  s.PostJson("/api/materials/42", R"({"albedo": [0.5, 0.5, 0.5]})", 404);
}

TEST(ServeApi, FlagsChangeLive) {
  Served s(3);
  s.WaitFrame(0, 1);
  Json g = s.PostJson("/api/options", R"({"compact": "off", "integrator": "bsdf"})");
  s.WaitFrame(g["generation"], 3);
  Json stats = s.GetJson("/api/stats");
  EXPECT_EQ(stats["compact_used"], false);
  EXPECT_EQ(s.GetJson("/api/scene")["options"]["integrator"], "bsdf");
  g = s.PostJson("/api/options", R"({"compact": "on", "max_depth": 2, "specialize": false})");
  s.WaitFrame(g["generation"], 3);
  EXPECT_EQ(s.GetJson("/api/stats")["compact_used"], true);
  EXPECT_EQ(s.GetJson("/api/scene")["render"]["max_depth"], 2);
  g = s.PostJson("/api/options", R"({"light_sampler": "bvh"})");  // allocates receiver normals
  s.WaitFrame(g["generation"], 3);
  EXPECT_EQ(s.GetJson("/api/stats")["light_sampler"], "bvh");
  EXPECT_EQ(s.GetJson("/api/scene")["options"]["light_sampler"], "bvh");
  EXPECT_EQ(s.GetJson("/api/stats")["sampler"], "independent");
  g = s.PostJson("/api/options", R"({"sampler": "sobol"})");
  s.WaitFrame(g["generation"], 3);
  EXPECT_EQ(s.GetJson("/api/stats")["sampler"], "sobol");
  EXPECT_EQ(s.GetJson("/api/scene")["options"]["sampler"], "sobol");
  s.PostJson("/api/options", R"({"sampler": "halton"})", 400);
  s.PostJson("/api/options", R"({"light_sampler": "random"})", 400);
  s.PostJson("/api/options", R"({"compact": "sometimes"})", 400);
  s.PostJson("/api/options", R"({"warp": 9})", 400);
  s.PostJson("/api/options", R"({"max_depth": -3})", 422);
}

TEST(ServeApi, BadRequestsAreAnswered4xxAndTheRenderGoesOn) {
  Served s(1000000);
  Served::Frame first = s.WaitFrame(0, 1);
  EXPECT_EQ(s.Post("/api/camera", "{not json")->status, 400);
  EXPECT_EQ(s.Client().Post("/api/camera", "{}", "text/plain")->status, 415);
  EXPECT_EQ(s.Client().Get("/api/nothing")->status, 404);
  EXPECT_EQ(s.Client().Get("/etc/passwd")->status, 404);
  EXPECT_EQ(s.Client().Get("/../CMakeLists.txt")->status, 404);
  EXPECT_EQ(s.Client().Get("/api/frame?after=-1")->status, 400);
  EXPECT_EQ(s.Client().Put("/api/camera", "{}", "application/json")->status, 405);
  EXPECT_EQ(s.Post("/api/pick", R"({"x": 4000, "y": 1})")->status, 400);
  EXPECT_EQ(s.Post("/api/display", R"({"exposure": 1e30})")->status, 400);
  // Oversize: a body past the limit is refused before it is read whole.
  std::string huge(kMaxRequestBodyBytes + 1, ' ');
  auto big = s.Post("/api/camera", "{\"fov_y\": 30" + huge + "}");
  ASSERT_TRUE(big);
  EXPECT_EQ(big->status, 413);
  // Host header: a DNS name other than localhost (rebinding) is refused; an IP literal works.
  httplib::Headers evil = {{"Host", "evil.example:" + std::to_string(s.Port())}};
  EXPECT_EQ(s.Client().Get("/api/scene", evil)->status, 403);
  httplib::Headers wrongPort = {{"Host", "127.0.0.1:1"}};
  EXPECT_EQ(s.Client().Get("/", wrongPort)->status, 403);
  httplib::Headers local = {{"Host", "localhost:" + std::to_string(s.Port())}};
  EXPECT_EQ(s.Client().Get("/api/scene", local)->status, 200);
  // A POST from another page's origin is refused.
  httplib::Headers origin = {{"Origin", "http://evil.example"}};
  EXPECT_EQ(s.Client().Post("/api/camera", origin, "{}", "application/json")->status, 403);
  // Still rendering.
  Served::Frame later = s.WaitFrame(0, first.spp + 1);
  EXPECT_GT(later.spp, first.spp);
}

TEST(ServeApi, ManyClientsWatchAtOnce) {
  Served s(1000000);
  s.WaitFrame(0, 1);
  std::atomic<int> ok{0};
  std::vector<std::thread> clients;
  for (int i = 0; i < 8; ++i) {
    clients.emplace_back([&] {
      httplib::Client c("127.0.0.1", s.Port());
      c.set_read_timeout(10, 0);
      uint64_t last = 0;
      int frames = 0;
      for (int k = 0; k < 3; ++k) {
        auto r = c.Get(("/api/frame?after=" + std::to_string(last)).c_str());
        if (r && r->status == 200) {
          last = std::stoull(r->get_header_value("X-Frame-Id"));
          ++frames;
        }
      }
      if (frames == 3) ++ok;
    });
  }
  for (auto& t : clients) t.join();
  EXPECT_EQ(ok.load(), 8);
}

TEST(ServeApi, ImageDownloads) {
  Served s(2);
  s.WaitFrame(0, 2);
  auto png = s.Client().Get("/api/image.png");
  ASSERT_TRUE(png && png->status == 200);
  EXPECT_EQ(png->body.substr(1, 3), "PNG");
  EXPECT_NE(png->get_header_value("Content-Disposition").find("preview.png"), std::string::npos);
  auto exr = s.Client().Get("/api/image.exr");
  ASSERT_TRUE(exr && exr->status == 200);
  EXPECT_EQ(exr->body.substr(0, 4), std::string("\x76\x2f\x31\x01", 4));
}

TEST(ServeHost, OnlyNamesNoRebindingCanFake) {
  EXPECT_TRUE(HostAllowed("127.0.0.1:8765", "127.0.0.1", 8765));
  EXPECT_TRUE(HostAllowed("LOCALHOST:8765", "127.0.0.1", 8765));
  EXPECT_TRUE(HostAllowed("[::1]:8765", "::1", 8765));
  EXPECT_FALSE(HostAllowed("127.0.0.1", "127.0.0.1", 8765));
  EXPECT_FALSE(HostAllowed("attacker.example:8765", "127.0.0.1", 8765));
  EXPECT_FALSE(HostAllowed("10.0.0.5:8765", "127.0.0.1", 8765));
  EXPECT_TRUE(HostAllowed("10.0.0.5:8765", "10.0.0.5", 8765));
  EXPECT_TRUE(HostAllowed("10.0.0.5:8765", "0.0.0.0", 8765));
  EXPECT_FALSE(HostAllowed("myhost.lan:8765", "0.0.0.0", 8765));
  EXPECT_TRUE(OriginAllowed("", "127.0.0.1:8765"));
  EXPECT_TRUE(OriginAllowed("http://127.0.0.1:8765", "127.0.0.1:8765"));
  EXPECT_FALSE(OriginAllowed("http://evil.example", "127.0.0.1:8765"));
}

TEST(ServeCli, StartsStopsAndRefusesWhatItCannotServe) {
  std::string dir = TempDir();
  std::string scene = WriteText(dir + "/tiny.json", kTinyScene);
  std::string log = dir + "/log.txt";
  // SIGTERM ends the preview cleanly (exit 0) once it serves.
  std::string out;
  int status = RunCommand("(" + BinaryPath("pathtracer") + " " + scene + " --serve 0 --threads 1 2>" +
                              log + " & pid=$!; i=0; while ! grep -q serving " + log +
                              " && [ $i -lt 600 ]; do sleep 0.05; i=$((i+1)); done;" +
                              " kill -TERM $pid; wait $pid)",
                          &out);
  std::string text = ReadText(log);
  EXPECT_EQ(status, 0) << text;
  EXPECT_NE(text.find("on http://127.0.0.1:"), std::string::npos) << text;
  EXPECT_NE(text.find("the preview stopped"), std::string::npos) << text;
  // An address of no interface here (TEST-NET-3): exit 3 with the reason.
  EXPECT_EQ(RunPathtracer(scene + " --serve 0 --bind 203.0.113.7", &out), 3) << out;
  EXPECT_NE(out.find("cannot listen on 203.0.113.7"), std::string::npos) << out;
  // A bad scene: exit 2, as a render would.
  std::string bad = WriteText(dir + "/bad.json", "{\"render\": {\"width\": -1}}");
  EXPECT_EQ(RunPathtracer(bad + " --serve 0", &out), 2) << out;
  std::remove(scene.c_str());
  std::remove(bad.c_str());
  std::remove(log.c_str());
}

}  // namespace
}  // namespace pt::test

#else

#include "tests/cli_test_util.h"

// Without cpp-httplib the rest builds, and --serve is a clear error (exit 3).
TEST(ServeCli, RefusedWithoutTheServer) {
  std::string dir = pt::test::TempDir();
  std::string scene = pt::test::WriteText(dir + "/tiny.json", pt::test::kTinyScene);
  std::string out;
  EXPECT_EQ(pt::test::RunPathtracer(scene + " --serve", &out), 3) << out;
  EXPECT_NE(out.find("this build has no preview server"), std::string::npos) << out;
  std::remove(scene.c_str());
}

#endif
