// The live preview's one state (issue 33): pushed to every page as server-sent events, lowered
// target spp, rejected values naming their field, coarse frames while the view moves, model
// files, the selection's outline and framing, the environment picker, and the binary's Ctrl-C.
#include <gtest/gtest.h>

#if defined(PT_HAVE_SERVER)
#include <httplib.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>

#include "src/server/api.h"
#include "tests/cli_test_util.h"
#include "tests/gltf_scene_writer.h"
#include "tests/serve_test_util.h"

namespace pt::test {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;

// The data of the last event `name` in server-sent events text, parsed; null when none.
Json LastEvent(const std::string& text, const std::string& name) {
  Json found;
  std::string marker = "event: " + name + "\ndata: ";
  for (size_t at = text.find(marker); at != std::string::npos; at = text.find(marker, at + 1)) {
    size_t begin = at + marker.size();
    found = Json::parse(text.substr(begin, text.find('\n', begin) - begin));
  }
  return found;
}

// Events for a page until one `name` event satisfies `ok` (or 20 s pass).
Json WaitEvent(LiveRender& live, EventCursor& cursor, const std::string& name,
               const std::function<bool(const Json&)>& ok) {
  auto deadline = Clock::now() + std::chrono::seconds(20);
  while (Clock::now() < deadline) {
    Json j = LastEvent(NextEvents(live, cursor, milliseconds(200)), name);
    if (!j.is_null() && ok(j)) return j;
  }
  ADD_FAILURE() << "no " << name << " event as expected";
  return Json();
}

Json ProgressWhen(Served& s, const std::function<bool(const Json&)>& ok) {
  auto deadline = Clock::now() + std::chrono::seconds(20);
  Json p;
  while (Clock::now() < deadline) {
    p = s.GetJson("/api/progress");
    if (ok(p)) return p;
    std::this_thread::sleep_for(milliseconds(20));
  }
  ADD_FAILURE() << "progress never as expected: " << p.dump();
  return p;
}

TEST(ServeState, EveryPageGetsTheWholeStateThenEachChange) {
  Served s(1000000);
  s.WaitFrame(0, 1);
  EventCursor pageA, pageB;
  std::string first = NextEvents(s.Live(), pageA, milliseconds(0));
  for (const char* name : {"scene", "state", "progress"}) {
    EXPECT_FALSE(LastEvent(first, name).is_null()) << name << " missing from " << first;
  }
  NextEvents(s.Live(), pageB, milliseconds(0));
  // Page A changes the camera, a flag and the display; both pages see each change.
  s.PostJson("/api/camera", R"({"position": [0.25, 1.0, 3.5]})");
  s.PostJson("/api/options", R"({"compact": "off"})");
  s.PostJson("/api/display", R"({"exposure": 2, "tone_mapping": "agx"})");
  for (EventCursor* page : {&pageA, &pageB}) {
    Json state = WaitEvent(s.Live(), *page, "state", [](const Json& j) {
      return j["display"]["exposure"] == 2.0 && j["options"]["compact"] == "off";
    });
    EXPECT_FLOAT_EQ(state["camera"]["position"][0].get<float>(), 0.25f) << state.dump();
    EXPECT_EQ(state["display"]["tone_mapping"], "agx");
    EXPECT_TRUE(state["camera_choice"].is_null());  // moved: no offered camera
  }
  // A page loaded now (a reload, a second tab) starts from what the render uses.
  EventCursor reload;
  Json state = LastEvent(NextEvents(s.Live(), reload, milliseconds(0)), "state");
  EXPECT_EQ(state["display"]["exposure"], 2.0);
  EXPECT_EQ(state["options"]["compact"], "off");
  // Over the socket: the stream's first events are the whole state.
  std::string streamed;
  s.Client().Get("/api/events", [&](const char* data, size_t n) {
    streamed.append(data, n);
    return LastEvent(streamed, "progress").is_null();  // stop reading after the third
  });
  EXPECT_EQ(LastEvent(streamed, "state")["display"]["tone_mapping"], "agx") << streamed;
  // Back to the scene's camera, by its index in the offered list.
  s.PostJson("/api/camera", R"({"choose": 0})");
  EXPECT_EQ(WaitEvent(s.Live(), pageB, "state", [](const Json& j) {
              return j["camera_choice"] == 0;
            })["camera"]["position"][0], 0.0);
  s.PostJson("/api/camera", R"({"choose": 5})", 404);
}

TEST(ServeState, LoweredTargetSppEndsTheRenderAtTheCurrentCount) {
  Served s(1000000);
  s.WaitFrame(0, 6);
  Json answer = s.PostJson("/api/options", R"({"spp": 2})");
  EXPECT_EQ(answer["restarts"], false);
  Json p = ProgressWhen(s, [](const Json& j) { return j.value("state", "") == "stopped"; });
  uint32_t ended = p["spp"];
  EXPECT_GE(ended, 6u);
  EXPECT_EQ(p["target_spp"], 2);
  EXPECT_NE(p["message"].get<std::string>().find("ends at " + std::to_string(ended) + " spp"),
            std::string::npos) << p.dump();
  // The last frame is the film at that count, and no other comes.
  std::shared_ptr<const PreviewFrame> last = s.Live().LatestFrame();
  EXPECT_EQ(last->spp, ended);
  auto idle = s.Client().Get(("/api/frame?after=" + std::to_string(last->id)).c_str());
  ASSERT_TRUE(idle);
  EXPECT_EQ(idle->status, 204);
  // Raised again: the render goes on from there to the new target.
  s.PostJson("/api/options", "{\"spp\": " + std::to_string(ended + 2) + "}");
  Json done = ProgressWhen(s, [&](const Json& j) { return j["spp"] == ended + 2; });
  EXPECT_EQ(done["state"], "done") << done.dump();
}

TEST(ServeState, RejectedValuesNameTheirFieldAndChangeNothing) {
  Served s(4);
  s.WaitFrame(0, 1);
  Json before = s.GetJson("/api/state");
  auto field = [&](const std::string& path, const std::string& body, int status) {
    return s.PostJson(path, body, status).value("field", "");
  };
  EXPECT_EQ(field("/api/options", R"({"max_depth": -1})", 422), "max_depth");
  EXPECT_EQ(field("/api/options", R"({"spp": 0})", 422), "spp");
  EXPECT_EQ(field("/api/options", R"({"sort": "fast"})", 400), "sort");
  EXPECT_EQ(field("/api/display", R"({"exposure": "bright"})", 400), "exposure");
  EXPECT_EQ(field("/api/display", R"({"tone_mapping": "aces"})", 400), "tone_mapping");
  EXPECT_EQ(field("/api/lighting", R"({"strength": -1})", 422), "strength");
  EXPECT_EQ(field("/api/lighting", R"({"map": "nowhere.exr"})", 404), "map");
  EXPECT_EQ(field("/api/options", R"({"denoise": true})", 422), "denoise");  // no denoiser here
  s.PostJson("/api/materials/0", R"({"albedo": [-5, 0.5, 0.5]})", 422);
  EXPECT_EQ(s.GetJson("/api/state"), before);
  EXPECT_NE(s.GetJson("/api/scene.json")["materials"]["white"]["albedo"][0], -5);
}

// A full-resolution sample slower than the coarse budget: each restart first shows a frame
// at reduced resolution, then refines at full resolution when the edits stop.
TEST(ServeState, CoarseFramesWhileTheViewMoves) {
  Served s(1000000, &MakeCpuSession, 96, "scenes/cornell_box.json",
           [](LiveSettings& l) { l.coarseFrameMs = 0.02; });
  s.WaitFrame(0, 2);
  std::atomic<bool> moving{true};
  std::thread drag([&] {
    httplib::Client c("127.0.0.1", s.Port());
    for (int i = 0; i < 40 && moving; ++i) {
      std::string body = "{\"position\": [" + std::to_string(0.01 * i) + ", 1, 3.9]}";
      c.Post("/api/camera", body, "application/json");
      std::this_thread::sleep_for(milliseconds(33));
    }
    moving = false;
  });
  int coarse = 0, full = 0;
  Served::Frame f;
  while (moving) {
    auto r = s.Client().Get(("/api/frame?after=" + std::to_string(f.id)).c_str());
    if (!r || r->status != 200) continue;
    f.id = std::stoull(r->get_header_value("X-Frame-Id"));
    if (r->get_header_value("X-Frame-Kind") == "coarse") {
      ++coarse;
      EXPECT_LT(std::stoi(r->get_header_value("X-Width")), 96);
    } else {
      ++full;
    }
  }
  drag.join();
  EXPECT_GE(coarse, 5) << full << " full frames";
  Served::Frame refined = s.WaitFrame(s.PostJson("/api/camera", R"({"fov_y": 30})")["generation"], 1);
  EXPECT_EQ(refined.width, 96);
  EXPECT_EQ(refined.kind, "render");
}

// Edits that come faster than one full-resolution sample (a drag on a busy machine) would drop
// every full pass and show nothing, however fast a sample is said to be: the preview shows
// coarse frames instead, and once the edits stop, the edit's first full frame is one sample.
TEST(ServeState, EditsFasterThanASampleShowCoarseFramesThenOneSample) {
  Served s(1000000, &MakeCpuSession, 256, "scenes/cornell_box.json", [](LiveSettings& l) {
    l.coarseFrameMs = 1e6;  // a sample is never "slow" by the budget alone
    l.framesPerSecond = 0.5;
    l.options.threads = 1;
  });
  s.WaitFrame(0, 1);
  std::atomic<bool> moving{true};
  std::thread drag([&] {
    httplib::Client c("127.0.0.1", s.Port());
    auto end = Clock::now() + milliseconds(1500);
    for (int i = 0; Clock::now() < end; ++i) {
      std::string body = "{\"position\": [" + std::to_string(0.001 * (i % 100)) + ", 1, 3.9]}";
      c.Post("/api/camera", body, "application/json");
      std::this_thread::sleep_for(milliseconds(3));
    }
    moving = false;
  });
  int coarse = 0, full = 0;
  uint64_t after = 0;
  while (moving) {
    auto r = s.Client().Get(("/api/frame?after=" + std::to_string(after)).c_str());
    if (!r || r->status != 200) continue;
    after = std::stoull(r->get_header_value("X-Frame-Id"));
    (r->get_header_value("X-Frame-Kind") == "coarse" ? coarse : full) += 1;
  }
  drag.join();
  EXPECT_GE(coarse, 5) << full << " full frames";
  Served::Frame refined = s.WaitFrame(s.PostJson("/api/camera", R"({"fov_y": 30})")["generation"], 1);
  EXPECT_EQ(refined.kind, "render");
  EXPECT_EQ(refined.width, 256);
  EXPECT_EQ(refined.spp, 1u);
}

// RenderCoarse is a render at the coarse size: the same pixels as a film of that size.
TEST(ServeState, ACoarseImageIsTheRenderAtItsSize) {
  SceneDesc desc = LoadScene(SourcePath("scenes/cornell_box.json"));
  desc.render.width = desc.render.height = 32;
  desc.render.spp = 1;
  Scene scene = BuildScene(desc);
  RenderOptions options;
  options.threads = 2;
  std::unique_ptr<RenderSession> session = MakeCpuSession(scene, options, RenderCallbacks{});
  session->ResetFilm();
  ASSERT_EQ(session->RenderCoarse(16, 16, 0, 1), 256u);
  FilmImage coarse = session->Image();
  desc.render.width = desc.render.height = 16;
  RenderResult small = RenderCpu(BuildScene(desc), options);
  ASSERT_EQ(small.image.rgb.size(), 16u * 16u * 3u);
  EXPECT_EQ(std::memcmp(coarse.rgb.data(), small.image.rgb.data(), small.image.rgb.size() * 4), 0);
  EXPECT_THROW(session->RenderCoarse(64, 64, 0, 1), std::invalid_argument);
}

TEST(ServeState, OutlineFrameAndDeselect) {
  Served s(1000000);
  s.WaitFrame(0, 1);
  EXPECT_EQ(s.Client().Get("/api/outline.png")->status, 204);  // nothing selected
  s.PostJson("/api/camera", R"({"frame": "selection"})", 409);
  Json hit = s.PostJson("/api/select", R"({"x": 18.5, "y": 30.5})");  // the tall box
  ASSERT_EQ(hit["object"], 6) << hit.dump();
  EXPECT_EQ(s.GetJson("/api/state")["selection"]["object"], 6);
  auto png = s.Client().Get("/api/outline.png?max=48");
  ASSERT_TRUE(png && png->status == 200);
  EXPECT_EQ(png->body.substr(1, 3), "PNG");
  // Framed: the camera looks at the box's centre, closer than the room's view.
  Json before = s.GetJson("/api/state")["camera"];
  s.PostJson("/api/camera", R"({"frame": "selection"})");
  Json after = s.GetJson("/api/state")["camera"];
  EXPECT_NE(after["look_at"], before["look_at"]);
  s.PostJson("/api/select", R"({"object": null})");
  EXPECT_TRUE(s.GetJson("/api/state")["selection"]["object"].is_null());
  EXPECT_EQ(s.Client().Get("/api/outline.png")->status, 204);
}

TEST(ServeState, EnvironmentPickerListsAndAppliesMaps) {
  std::string dir = TempDir() + "/serve_maps";
  fs::create_directories(dir);
  FilmImage sky;
  sky.width = 8;
  sky.height = 4;
  sky.rgb.assign(8 * 4 * 3, 0.5f);
  WriteImage(dir + "/sky.pfm", sky, false);
  WriteText(dir + "/notes.txt", "not a map");
  Served s(1000000, &MakeCpuSession, 48, "scenes/cornell_box.json",
           [&](LiveSettings& l) { l.environmentFolder = dir; });
  s.WaitFrame(0, 1);
  EXPECT_EQ(s.GetJson("/api/scene")["maps"], Json::array({"sky.pfm"}));
  Json g = s.PostJson("/api/lighting", R"({"map": "sky.pfm", "strength": 2, "rotation": 90})");
  EXPECT_TRUE(g["restarts"].get<bool>());
  s.WaitFrame(g["generation"], 1);
  Json env = s.GetJson("/api/scene.json")["environment"];
  EXPECT_EQ(env["file"], dir + "/sky.pfm");
  EXPECT_EQ(env["strength"], 2.0);
  EXPECT_EQ(env["rotate"][1], 90.0);
  EXPECT_EQ(s.GetJson("/api/state")["lighting"]["map"], "sky.pfm");
  s.PostJson("/api/lighting", R"({"map": "none"})");
  EXPECT_FALSE(s.GetJson("/api/scene.json").contains("environment"));
  fs::remove_all(dir);
}

// A glTF file served directly: the document is a JSON scene that includes it, with its camera.
TEST(ServeState, AModelFileIsServedAsTheSceneThatIncludesIt) {
  std::string dir = TempDir() + "/serve_model";
  fs::create_directories(dir);
  GltfSceneWriter w;
  int floor = w.AddFloor(1.0f);
  w.AddNode({{"mesh", floor}});
  int cam = w.AddCamera(GltfSceneWriter::Perspective(0.8, 1.0, "overview"));
  w.AddNode({{"camera", cam}, {"translation", {0.0, 1.0, 3.0}}});
  std::string glb = w.Write(dir, "floor", true);
  Served s(1000000, &MakeCpuSession, 32, glb);
  s.WaitFrame(0, 1);
  Json saved = s.GetJson("/api/scene.json");
  ASSERT_EQ(saved["objects"].size(), 1u);
  EXPECT_EQ(saved["objects"][0]["file"], fs::absolute(glb).lexically_normal().string());
  EXPECT_FLOAT_EQ(saved["camera"]["position"][2].get<float>(), 3.0f);
  // Unlit: the default environment, as -o has it.
  SceneDesc loaded = LoadScene(glb);
  std::string path = dir + "/saved.json";
  WriteText(path, saved.dump());
  SceneDesc again = LoadScene(path);
  EXPECT_EQ(again.triangles.size(), loaded.triangles.size());
  EXPECT_EQ(again.environment.strength, loaded.environment.strength);
  EXPECT_EQ(again.background, loaded.background);
  // Edits merge into the file's camera.
  s.PostJson("/api/camera", R"({"fov_y": 20})");
  EXPECT_FLOAT_EQ(s.GetJson("/api/state")["camera"]["position"][2].get<float>(), 3.0f);
  fs::remove_all(dir);
}

// The binary: a .glb and a bare relative path are served; Ctrl-C writes -o (as displayed) and
// says so, or says that nothing is written.
TEST(ServeCli, ModelFilesBarePathsAndCtrlCSaves) {
  std::string dir = TempDir() + "/serve_cli";
  fs::create_directories(dir);
  WriteText(dir + "/tiny.json", kTinyScene);
  GltfSceneWriter w;
  w.AddNode({{"mesh", w.AddFloor(1.0f)}});
  w.AddNode({{"camera", w.AddCamera(GltfSceneWriter::Perspective(0.8))},
             {"translation", {0.0, 1.0, 3.0}}});
  w.Write(dir, "floor", true);
  std::string log = dir + "/log.txt";
  auto serve = [&](const std::string& args) {
    std::string out;
    int status = RunCommand("(cd " + dir + " && " + BinaryPath("pathtracer") + " " + args +
                                " --serve 0 --threads 1 --width 16 --height 16 2>" + log +
                                " & pid=$!; i=0; while ! grep -q serving " + log +
                                " && [ $i -lt 600 ]; do sleep 0.05; i=$((i+1)); done; sleep 0.5;" +
                                " kill -INT $pid; wait $pid)",
                            &out);
    std::string text = ReadText(log);
    EXPECT_EQ(status, 0) << args << ": " << text;
    return text;
  };
  std::string bare = serve("tiny.json");
  EXPECT_NE(bare.find("nothing is written"), std::string::npos) << bare;
  std::string model = serve("floor.glb -o saved.png --exposure 1 --tonemap agx");
  EXPECT_NE(model.find("wrote saved.png"), std::string::npos) << model;
  EXPECT_NE(model.find("agx"), std::string::npos) << model;
  EXPECT_EQ(ReadText(dir + "/saved.png").substr(1, 3), "PNG");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pt::test

#endif
