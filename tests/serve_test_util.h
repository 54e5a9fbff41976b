// The live preview served on 127.0.0.1 for tests (only in a build with the server).
#pragma once

#if defined(PT_HAVE_SERVER)
#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "src/integrator/render_api.h"
#include "src/io/image_io.h"
#include "src/io/model_scene.h"
#include "src/io/scene_loader.h"
#include "src/server/http_server.h"
#include "src/server/live_render.h"
#include "tests/test_util.h"

namespace pt::test {

using Clock = std::chrono::steady_clock;

// A served scene (of the repository unless an absolute path; the Cornell box unless named; a
// model file as the JSON scene that includes it), side x side at `spp` samples, on two CPU
// threads (or the session `make` makes), with the server on a free port of 127.0.0.1 and a
// client of it. `tweak` changes the preview's settings before it starts.
class Served {
 public:
  explicit Served(int spp, MakeSessionFn make = &MakeCpuSession, int side = 48,
                  const std::string& scene = "scenes/cornell_box.json",
                  const std::function<void(LiveSettings&)>& tweak = nullptr) {
    std::string path = scene.rfind('/', 0) == 0 ? scene : SourcePath(scene);
    SceneDesc desc = LoadScene(path);
    desc.render.width = side;
    desc.render.height = side;
    desc.render.spp = spp;
    SceneDocument document = IsModelFile(path) ? SceneDocument::ForModel(path, desc, LoadOptions{})
                                               : SceneDocument(path, desc.render);
    LiveSettings settings;
    settings.options.threads = 2;
    settings.framesPerSecond = 50;
    if (tweak) tweak(settings);
    live_ = std::make_unique<LiveRender>(std::move(document), BuildScene(std::move(desc)),
                                         std::move(make), settings);
    HttpServerConfig config;
    config.port = 0;
    config.threads = 16;
    server_ = StartHttpServer(*live_, config);
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->Port());
    client_->set_read_timeout(10, 0);
  }
  ~Served() {
    server_->Stop();
    live_->Stop();
  }

  LiveRender& Live() { return *live_; }
  httplib::Client& Client() { return *client_; }
  int Port() const { return server_->Port(); }

  httplib::Result Post(const std::string& path, const std::string& body) {
    return client_->Post(path.c_str(), body, "application/json");
  }
  Json PostJson(const std::string& path, const std::string& body, int status = 200) {
    auto r = Post(path, body);
    EXPECT_TRUE(r) << path;
    if (!r) return Json();
    EXPECT_EQ(r->status, status) << path << " " << body << ": " << r->body;
    return Json::parse(r->body, nullptr, false);
  }
  Json GetJson(const std::string& path) {
    auto r = client_->Get(path.c_str());
    EXPECT_TRUE(r && r->status == 200) << path;
    return r ? Json::parse(r->body, nullptr, false) : Json();
  }

  struct Frame {
    uint64_t id = 0, generation = 0;
    uint32_t spp = 0;
    int width = 0;
    std::string kind;  // coarse, render, display
    std::string jpeg;
  };
  // Long-polls frames until one of at least `generation` with at least `spp` samples.
  Frame WaitFrame(uint64_t generation, uint32_t spp) {
    Frame f;
    auto deadline = Clock::now() + std::chrono::seconds(60);
    while (Clock::now() < deadline) {
      auto r = client_->Get(("/api/frame?after=" + std::to_string(f.id)).c_str());
      if (!r) break;
      if (r->status != 200) continue;
      f.id = std::stoull(r->get_header_value("X-Frame-Id"));
      f.generation = std::stoull(r->get_header_value("X-Generation"));
      f.spp = uint32_t(std::stoul(r->get_header_value("X-Spp")));
      f.width = std::stoi(r->get_header_value("X-Width"));
      f.kind = r->get_header_value("X-Frame-Kind");
      f.jpeg = r->body;
      if (f.generation >= generation && f.spp >= spp) return f;
    }
    ADD_FAILURE() << "no frame of generation " << generation << " with " << spp << " spp";
    return f;
  }

 private:
  std::unique_ptr<LiveRender> live_;
  std::unique_ptr<HttpServer> server_;
  std::unique_ptr<httplib::Client> client_;
};

// The saved scene is what the preview rendered: after the edits (POSTs of path and body), the
// CPU renders the scene /api/scene.json saves to the very film the preview shows, bit for bit.
inline void ExpectSavedSceneRendersTheShownFilm(
    const std::vector<std::pair<std::string, std::string>>& edits, IntegratorMode integrator,
    const std::string& scene = "scenes/cornell_box.json") {
  SCOPED_TRACE(scene + ", first edit " + (edits.empty() ? "none" : edits[0].first + " " + edits[0].second));
  Served s(3, &MakeCpuSession, 48, scene);
  s.WaitFrame(0, 1);
  Json g;
  for (const auto& [path, body] : edits) g = s.PostJson(path, body);
  s.WaitFrame(g["generation"], 3);
  std::shared_ptr<const FilmImage> shown = s.Live().LatestImage();
  ASSERT_TRUE(shown);
  std::string path = TempDir() + "/edited.json";
  WriteFileAtomic(path, s.Client().Get("/api/scene.json")->body);
  Scene edited = BuildScene(LoadScene(path));
  std::remove(path.c_str());
  RenderOptions options;
  options.threads = 2;
  options.integrator = integrator;
  RenderResult again = RenderCpu(edited, options);
  ASSERT_EQ(again.image.rgb.size(), shown->rgb.size());
  EXPECT_EQ(std::memcmp(again.image.rgb.data(), shown->rgb.data(), shown->rgb.size() * sizeof(float)), 0);
}

}  // namespace pt::test
#endif
