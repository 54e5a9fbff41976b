// Moving instances in the live preview: picked through the two-level traversal, re-placed
// through the top level alone (no scene rebuild), saved as the transform the preview renders.
// httplib's client on 127.0.0.1 against scenes/instanced_shapes.json on the CPU.
#include <gtest/gtest.h>

#if defined(PT_HAVE_SERVER)
#include <algorithm>
#include <cmath>
#include <fstream>
#include <utility>
#include <vector>

#include "tests/gltf_scene_writer.h"
#include "tests/serve_test_util.h"

namespace pt::test {
namespace {

constexpr const char* kScene = "scenes/instanced_shapes.json";
constexpr int kSide = 48;
constexpr int kStep = 2;  // the pick grid: every other pixel

// Picks pixel (x, y)'s centre through the API.
Json PickThroughApi(Served& s, std::pair<int, int> pixel) {
  return s.PostJson("/api/pick", Json{{"x", pixel.first + 0.5}, {"y", pixel.second + 0.5}}.dump());
}

// The pixels of the grid (centres) whose pick names `object`.
std::vector<std::pair<int, int>> PixelsOf(LiveRender& live, int object) {
  std::vector<std::pair<int, int>> pixels;
  for (int y = 0; y < kSide; y += kStep) {
    for (int x = 0; x < kSide; x += kStep) {
      if (live.Pick(x + 0.5f, y + 0.5f).object == object) pixels.emplace_back(x, y);
    }
  }
  return pixels;
}

double MeanX(const std::vector<std::pair<int, int>>& pixels) {
  double sum = 0.0;
  for (const auto& p : pixels) sum += p.first;
  return pixels.empty() ? 0.0 : sum / double(pixels.size());
}

// Mean absolute difference of two films over the given pixels.
double MeanDifference(const FilmImage& a, const FilmImage& b,
                      const std::vector<std::pair<int, int>>& pixels) {
  double sum = 0.0;
  for (const auto& [x, y] : pixels) {
    size_t i = (size_t(y) * size_t(a.width) + size_t(x)) * 3;
    for (int c = 0; c < 3; ++c) sum += std::fabs(double(a.rgb[i + c]) - double(b.rgb[i + c]));
  }
  return pixels.empty() ? 0.0 : sum / double(pixels.size());
}

bool HasPixel(const std::vector<std::pair<int, int>>& pixels, std::pair<int, int> p) {
  return std::find(pixels.begin(), pixels.end(), p) != pixels.end();
}

TEST(ServeInstances, PickNamesTheInstanceObjectAndTheWorldsOwn) {
  Served s(1, &MakeCpuSession, kSide, kScene);
  s.WaitFrame(0, 1);
  Json scene = s.GetJson("/api/scene");
  ASSERT_EQ(scene["objects"][3]["type"], "instance");
  EXPECT_EQ(scene["objects"][3]["mesh"], "shapes");
  // Each placed instance is seen somewhere (the mirrored one and the small lamps included),
  // and so are the world's own quads (the floor, object 0, and the back wall, object 1).
  for (int object : {0, 1, 3, 4, 5}) {
    EXPECT_FALSE(PixelsOf(s.Live(), object).empty()) << "object " << object;
  }
  std::vector<std::pair<int, int>> red = PixelsOf(s.Live(), 4);
  ASSERT_FALSE(red.empty());
  Json hit = PickThroughApi(s, red[0]);
  EXPECT_EQ(hit["object"], 4) << hit.dump();
  // The instance's material override ("red", material 1) is what the pixel sees.
  EXPECT_EQ(hit["material"], 1) << hit.dump();
}

TEST(ServeInstances, MovingAnInstanceRebuildsTheTopLevelOnly) {
  Served s(2, &MakeCpuSession, kSide, kScene);
  Served::Frame first = s.WaitFrame(0, 2);
  std::shared_ptr<const FilmImage> before = s.Live().LatestImage();
  ASSERT_TRUE(before);
  std::vector<std::pair<int, int>> was = PixelsOf(s.Live(), 3);
  ASSERT_GT(was.size(), 4u);
  Json hit = PickThroughApi(s, was[0]);
  ASSERT_EQ(hit["object"], 3) << hit.dump();

  // To the left (the camera looks down -z): world x -0.5.
  Json g = s.PostJson("/api/objects/3/move", R"({"translate": [-0.5, 0, 0]})");
  ASSERT_TRUE(g.contains("generation")) << g.dump();
  s.WaitFrame(g["generation"], 2);
  std::shared_ptr<const FilmImage> after = s.Live().LatestImage();
  ASSERT_TRUE(after);
  Json stats = s.GetJson("/api/stats");
  EXPECT_EQ(stats["rebuilds"]["top_level"], 1) << stats.dump();
  EXPECT_EQ(stats["rebuilds"]["scene"], 0) << stats.dump();
  EXPECT_GE(stats["rebuilds"]["last_ms"].get<double>(), 0.0);

  // The instance is seen further left, and the pixels it left show something else now.
  std::vector<std::pair<int, int>> now = PixelsOf(s.Live(), 3);
  ASSERT_FALSE(now.empty());
  EXPECT_LT(MeanX(now), MeanX(was) - 2.0);
  std::vector<std::pair<int, int>> left, arrived;
  for (const auto& p : was) if (!HasPixel(now, p)) left.push_back(p);
  for (const auto& p : now) if (!HasPixel(was, p)) arrived.push_back(p);
  ASSERT_FALSE(left.empty());
  ASSERT_FALSE(arrived.empty());
  EXPECT_GT(MeanDifference(*before, *after, left), 0.02);
  EXPECT_GT(MeanDifference(*before, *after, arrived), 0.02);
  EXPECT_NE(first.jpeg, s.WaitFrame(g["generation"], 2).jpeg);

  // The saved scene holds the composed transform: translate x -0.4 - 0.5, the rest unchanged.
  Json doc = Json::parse(s.Client().Get("/api/scene.json")->body, nullptr, false);
  ASSERT_FALSE(doc.is_discarded());
  const Json& t = doc["objects"][3]["transform"];
  EXPECT_NEAR(t["translate"][0].get<double>(), -0.9, 1e-6);
  EXPECT_NEAR(t["translate"][1].get<double>(), 0.2, 1e-6);
  EXPECT_EQ(t["rotate"], Json::array({0, 35, 10}));

  // A quad (object 2, the lamp) still moves by a scene rebuild.
  g = s.PostJson("/api/objects/2/move", R"({"translate": [0, -0.1, 0]})");
  s.WaitFrame(g["generation"], 1);
  stats = s.GetJson("/api/stats");
  EXPECT_EQ(stats["rebuilds"]["scene"], 1) << stats.dump();
  EXPECT_EQ(stats["rebuilds"]["top_level"], 1) << stats.dump();
}

TEST(ServeInstances, AnInstanceMoveTheLoaderRefusesIsAnswered422) {
  Served s(1, &MakeCpuSession, kSide, kScene);
  s.WaitFrame(0, 1);
  // Finite in float, but the inverse of the placement is not: the loader's check refuses it.
  Json refused = s.PostJson("/api/objects/4/move", R"({"translate": [3e38, 0, 0]})", 422);
  EXPECT_NE(refused.dump().find("objects[4].transform"), std::string::npos) << refused.dump();
  s.PostJson("/api/objects/4/move", R"({"translate": [1, 0]})", 400);
  s.PostJson("/api/objects/8/move", R"({"translate": [1, 0, 0]})", 404);
  // Nothing changed, and the preview renders on.
  Json doc = Json::parse(s.Client().Get("/api/scene.json")->body, nullptr, false);
  EXPECT_EQ(doc["objects"][4]["transform"]["translate"], Json::array({0.7, 0.1, -0.5}));
  Json g = s.PostJson("/api/objects/4/move", R"({"translate": [0.1, 0, 0]})");
  s.WaitFrame(g["generation"], 1);
}

TEST(ServeInstances, TheSavedSceneRendersWhatThePreviewShows) {
  // Instance moves alone: the top-level path.
  ExpectSavedSceneRendersTheShownFilm(
      {{"/api/objects/3/move", R"({"translate": [-0.3, 0.1, 0.2]})"},
       {"/api/objects/3/move", R"({"translate": [0.1, 0, 0]})"}},
      IntegratorMode::kMis, kScene);
  ExpectSavedSceneRendersTheShownFilm(
      {{"/api/objects/7/move", R"({"translate": [0.2, -0.4, 0]})"}},  // a lamp instance
      IntegratorMode::kMis, kScene);
  // With a material edit and a quad's move (the full rebuild) in between.
  ExpectSavedSceneRendersTheShownFilm(
      {{"/api/objects/5/move", R"({"translate": [0, 0.2, -0.1]})"},
       {"/api/materials/1", R"({"albedo": [0.2, 0.7, 0.3]})"},
       {"/api/objects/1/move", R"({"translate": [0, 0, -0.2]})"},
       {"/api/objects/4/move", R"({"translate": [-0.2, 0, 0]})"},
       {"/api/options", R"({"integrator": "nee"})"}},
      IntegratorMode::kNee, kScene);
}

// A mesh object whose glTF file uses one mesh from two nodes: the loader stores the mesh once
// and places it twice (instances of the mesh object, not instance objects). A hit in either
// placement names the mesh object; moving it rebuilds the scene with both placements moved.
class TwoPlacementsScene {
 public:
  TwoPlacementsScene() {
    GltfSceneWriter gltf;
    int square = gltf.AddMesh({vec3(-0.4f, -0.4f, 0.0f), vec3(0.4f, -0.4f, 0.0f),
                               vec3(0.4f, 0.4f, 0.0f), vec3(-0.4f, 0.4f, 0.0f)},
                              {0, 1, 2, 0, 2, 3});
    gltf.AddNode({{"mesh", square}, {"translation", {-0.6, 0.0, 0.0}}});
    gltf.AddNode({{"mesh", square}, {"translation", {0.6, 0.0, 0.0}}});
    gltf.Write(folder_.Path(), "twice", true);
    path_ = folder_.Path() + "/twice.json";
    std::ofstream(path_) << R"({
      "format": 1,
      "render": {"width": 48, "height": 48, "spp": 4, "max_depth": 3},
      "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov_y": 40},
      "background": [0.3, 0.3, 0.3],
      "materials": {"white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
                    "lamp": {"type": "emissive", "radiance": [4, 4, 4]}},
      "objects": [
        {"type": "quad", "origin": [-1, 1.5, -1], "u": [2, 0, 0], "v": [0, 0, 2],
         "material": "lamp"},
        {"type": "mesh", "file": "twice.glb", "material": "white"}]})";
  }
  const std::string& Path() const { return path_; }

 private:
  TempFolder folder_;
  std::string path_;
};

TEST(ServeInstances, AMeshFilesOwnPlacementsNameAndMoveTheirObject) {
  TwoPlacementsScene scene;
  ASSERT_EQ(LoadScene(scene.Path()).instances.size(), 2u);  // the file's reuse, as instances
  {
    Served s(1, &MakeCpuSession, kSide, scene.Path());
    s.WaitFrame(0, 1);
    // The squares' centres: x = -0.6 and 0.6 at y = 0 (pixels 11 and 37 of row 24).
    EXPECT_EQ(s.Live().Pick(11.5f, 24.5f).object, 1);
    EXPECT_EQ(s.Live().Pick(36.5f, 24.5f).object, 1);
    EXPECT_EQ(s.Live().Pick(24.5f, 24.5f).object, -1);  // between them: the background
    Json g = s.PostJson("/api/objects/1/move", R"({"translate": [0, 0.5, 0]})");
    s.WaitFrame(g["generation"], 1);
    EXPECT_EQ(s.GetJson("/api/stats")["rebuilds"]["scene"], 1);
    for (float x : {11.5f, 36.5f}) {  // both placements went up by 11 pixels
      EXPECT_EQ(s.Live().Pick(x, 24.5f).object, -1) << x;
      EXPECT_EQ(s.Live().Pick(x, 13.5f).object, 1) << x;
    }
  }
  ExpectSavedSceneRendersTheShownFilm({{"/api/objects/1/move", R"({"translate": [0.1, 0.3, 0]})"}},
                                      IntegratorMode::kMis, scene.Path());
}

}  // namespace
}  // namespace pt::test
#endif
