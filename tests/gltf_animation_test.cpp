// glTF animation (src/io/gltf_animation.h, src/io/gltf_deform.h) on hand-made files whose
// poses are computed by hand: a node translated by LINEAR, STEP and CUBICSPLINE samplers, a
// rotation slerped the short way, a two-joint skin bending a strip, a morph target at weight
// 0.5 (static, node and animated weights), an animated camera, animated instances, and the
// bad inputs: a time outside the clip (clamped, said once), a skin with more joints than
// inverse bind matrices, an unknown animation, a malformed sampler.
#include <gtest/gtest.h>

#include "src/io/scene_loader.h"
#include "tests/cli_parse_util.h"
#include "tests/cli_test_util.h"
#include "tests/gltf_scene_writer.h"
#include "tests/test_util.h"

namespace pt {
namespace {

using nlohmann::json;

// The triangle (0,0,0) (1,0,0) (0,1,0) as mesh 0 of the writer.
int AnimTriangle(test::GltfSceneWriter& w) {
  return w.AddMesh({vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)}, {0, 1, 2});
}

// A sampler of `interpolation` over times and flat output values; returns its index in anim.
int AnimSampler(test::GltfSceneWriter& w, json& anim, const std::vector<float>& times,
                const std::vector<float>& values, const char* type, int components,
                const char* interpolation = "LINEAR") {
  int input = w.AddAccessor(times.data(), times.size(), 4, 5126, "SCALAR");
  w.doc["accessors"][input]["min"] = {times.front()};
  w.doc["accessors"][input]["max"] = {times.back()};
  int output = w.AddAccessor(values.data(), values.size() / size_t(components), 4 * size_t(components),
                             5126, type);
  anim["samplers"].push_back({{"input", input}, {"output", output}, {"interpolation", interpolation}});
  return int(anim["samplers"].size()) - 1;
}

void AnimChannel(json& anim, int sampler, int node, const char* path) {
  anim["channels"].push_back({{"sampler", sampler}, {"target", {{"node", node}, {"path", path}}}});
}

SceneDesc LoadAt(const std::string& path, std::optional<double> time, const std::string& animation = "") {
  LoadOptions options;
  options.time = time;
  options.animation = animation;
  return LoadScene(path, options);
}

void ExpectNear(vec3 a, vec3 b, float tol, const std::string& what) {
  EXPECT_NEAR(a.x, b.x, tol) << what;
  EXPECT_NEAR(a.y, b.y, tol) << what;
  EXPECT_NEAR(a.z, b.z, tol) << what;
}

// One translated node per sampler type: LINEAR and STEP over (0,0,0) (2,0,0) (2,4,0) at t = 0,
// 1, 2; CUBICSPLINE from (0,0,0) to (1,0,0) over t = 0..2 with out-tangent (3,0,0) and
// in-tangent (0,-1,0).
std::string WriteTranslated(const std::string& dir) {
  test::GltfSceneWriter w;
  int mesh = AnimTriangle(w);
  json anim = {{"name", "move"}};
  std::vector<float> times = {0, 1, 2}, values = {0, 0, 0, 2, 0, 0, 2, 4, 0};
  AnimChannel(anim, AnimSampler(w, anim, times, values, "VEC3", 3), w.AddNode({{"mesh", mesh}}), "translation");
  AnimChannel(anim, AnimSampler(w, anim, times, values, "VEC3", 3, "STEP"), w.AddNode({{"mesh", mesh}}),
              "translation");
  // in-tangent, value, out-tangent per keyframe
  std::vector<float> cubic = {0, 0, 0, 0, 0, 0, 3, 0, 0, 0, -1, 0, 1, 0, 0, 0, 0, 0};
  AnimChannel(anim, AnimSampler(w, anim, {0, 2}, cubic, "VEC3", 3, "CUBICSPLINE"),
              w.AddNode({{"mesh", mesh}}), "translation");
  w.doc["animations"] = {anim};
  return w.Write(dir, "translated");
}

// The translation of each of the three nodes (their triangle's first corner; a mesh the three
// share is instanced: its instances' transforms).
std::vector<vec3> NodeOffsets(const SceneDesc& s) {
  std::vector<vec3> out;
  for (const InstanceDesc& i : s.instances) out.push_back(vec3(i.toWorld[3]));
  return out;
}

TEST(GltfAnimation, SamplersInterpolateLinearStepAndCubicSpline) {
  std::string path = WriteTranslated(test::TempDir());
  std::vector<vec3> rest = NodeOffsets(LoadAt(path, std::nullopt));
  ASSERT_EQ(rest.size(), 3u);
  for (vec3 p : rest) ExpectNear(p, vec3(0.0f), 0.0f, "static pose");
  std::vector<vec3> a = NodeOffsets(LoadAt(path, 0.25));
  ExpectNear(a[0], vec3(0.5f, 0, 0), 1e-6f, "LINEAR at 0.25");
  ExpectNear(a[1], vec3(0, 0, 0), 0.0f, "STEP at 0.25");
  // Hermite at u = 1/8 (dt = 2): h10 = u^3 - 2u^2 + u, h01 = -2u^3 + 3u^2, h11 = u^3 - u^2.
  double u = 0.125, h10 = u * u * u - 2 * u * u + u, h01 = -2 * u * u * u + 3 * u * u, h11 = u * u * u - u * u;
  ExpectNear(a[2], vec3(float(h10 * 2 * 3 + h01), float(h11 * 2 * -1), 0), 1e-6f, "CUBICSPLINE at 0.25");
  std::vector<vec3> b = NodeOffsets(LoadAt(path, 1.5));
  ExpectNear(b[0], vec3(2, 2, 0), 1e-6f, "LINEAR at 1.5");
  ExpectNear(b[1], vec3(2, 0, 0), 0.0f, "STEP at 1.5");
  std::vector<vec3> c = NodeOffsets(LoadAt(path, 1.0));  // u = 1/2: 0.75 + 0.5, y: -0.125 * 2 * -1
  ExpectNear(c[2], vec3(1.25f, 0.25f, 0), 1e-6f, "CUBICSPLINE at 1");
  ExpectNear(c[1], vec3(2, 0, 0), 0.0f, "STEP on its keyframe");
}

// A rotation from 0 to 170 degrees about z: slerp at u = 1/4 turns 42.5 degrees (normalised
// linear interpolation would give 35.8); the second keyframe negated takes the same short way.
TEST(GltfAnimation, RotationsSlerpTheShortWay) {
  for (float sign : {1.0f, -1.0f}) {
    test::GltfSceneWriter w;
    int node = w.AddNode({{"mesh", AnimTriangle(w)}});
    json anim;
    float h = float(85.0 * test::kDeg);
    std::vector<float> q = {0, 0, 0, 1, 0, 0, sign * std::sin(h), sign * std::cos(h)};
    AnimChannel(anim, AnimSampler(w, anim, {0, 4}, q, "VEC4", 4), node, "rotation");
    w.doc["animations"] = {anim};
    SceneDesc s = LoadAt(w.Write(test::TempDir(), "rotated"), 1.0);
    ASSERT_EQ(s.triangles.size(), 1u);
    float angle = float(42.5 * test::kDeg);
    ExpectNear(s.triangles[0].p1, vec3(std::cos(angle), std::sin(angle), 0), 1e-6f, "sign " + std::to_string(sign));
  }
}

// A strip along x (x = 0, 1, 2; y = +-0.5) on joints J0 (the origin) and J1 (J0's child at x = 1):
// x = 0 follows J0, x = 2 follows J1, x = 1 half of each. J1 turns 90 degrees about z from t =
// 0 to t = 1. The mesh's node is moved by (100, 0, 0), which a skin ignores.
std::string WriteSkinnedStrip(const std::string& dir, int inverseBindMatrices = 2) {
  test::GltfSceneWriter w;
  std::vector<vec3> p = {vec3(0, -0.5f, 0), vec3(0, 0.5f, 0), vec3(1, -0.5f, 0),
                         vec3(1, 0.5f, 0),  vec3(2, -0.5f, 0), vec3(2, 0.5f, 0)};
  int mesh = w.AddMesh(p, {0, 2, 3, 0, 3, 1, 2, 4, 5, 2, 5, 3});
  std::vector<uint16_t> joints = {0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0};
  std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 0.5f, 0.5f, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0};
  json& prim = w.doc["meshes"][mesh]["primitives"][0];
  prim["attributes"]["JOINTS_0"] = w.AddAccessor(joints.data(), 6, 8, 5123, "VEC4");
  prim["attributes"]["WEIGHTS_0"] = w.AddAccessor(weights.data(), 6, 16, 5126, "VEC4");
  std::vector<float> ibm = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,
                            1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1};
  int ibms = w.AddAccessor(ibm.data(), size_t(inverseBindMatrices), 64, 5126, "MAT4");
  int j1 = w.AddNode({{"translation", {1, 0, 0}}}, false);
  int j0 = w.AddNode({{"children", {j1}}});
  w.AddNode({{"mesh", mesh}, {"skin", 0}, {"translation", {100, 0, 0}}});
  w.doc["skins"] = {{{"joints", {j0, j1}}, {"inverseBindMatrices", ibms}}};
  json anim;
  float h = float(45.0 * test::kDeg);
  AnimChannel(anim, AnimSampler(w, anim, {0, 1}, {0, 0, 0, 1, 0, 0, std::sin(h), std::cos(h)}, "VEC4", 4), j1,
              "rotation");
  w.doc["animations"] = {anim};
  return w.Write(dir, "strip");
}

// The loaded position nearest `p` among the triangles' corners.
vec3 NearestCorner(const SceneDesc& s, vec3 p) {
  vec3 best(INFINITY);
  for (const Triangle& t : s.triangles)
    for (vec3 c : {t.p0, t.p1, t.p2})
      if (glm::length(c - p) < glm::length(best - p)) best = c;
  return best;
}

TEST(GltfAnimation, TwoJointSkinBendsAStrip) {
  std::string path = WriteSkinnedStrip(test::TempDir());
  SceneDesc rest = LoadAt(path, std::nullopt);  // the bind pose, where the node is ignored
  for (vec3 p : {vec3(0, -0.5f, 0), vec3(1, 0.5f, 0), vec3(2, 0.5f, 0)}) {
    ExpectNear(NearestCorner(rest, p), p, 1e-6f, "bind pose");
  }
  SceneDesc bent = LoadAt(path, 1.0);
  ASSERT_EQ(bent.triangles.size(), 4u);
  // J1 = T(1,0,0) Rz(90) T(-1,0,0): (2, -0.5) -> (1.5, 1), (2, 0.5) -> (0.5, 1); x = 1 averages
  // J1's (1.5, 0) and (0.5, 0) with J0's (1, -0.5) and (1, 0.5).
  std::vector<std::pair<vec3, vec3>> expected = {
      {vec3(0, -0.5f, 0), vec3(0, -0.5f, 0)}, {vec3(0, 0.5f, 0), vec3(0, 0.5f, 0)},
      {vec3(1.25f, -0.25f, 0), vec3(1.25f, -0.25f, 0)}, {vec3(0.75f, 0.25f, 0), vec3(0.75f, 0.25f, 0)},
      {vec3(1.5f, 1, 0), vec3(1.5f, 1, 0)}, {vec3(0.5f, 1, 0), vec3(0.5f, 1, 0)}};
  for (const auto& [p, want] : expected) ExpectNear(NearestCorner(bent, p), want, 1e-5f, "bent");
  for (const Triangle& t : bent.triangles) {
    for (vec3 c : {t.p0, t.p1, t.p2}) EXPECT_LT(c.x, 3.0f) << "the skinned mesh's node moved it";
  }
}

TEST(GltfAnimation, MoreJointsThanInverseBindMatricesIsRefused) {
  std::string dir = test::TempDir();
  std::string path = WriteSkinnedStrip(dir, 1);
  try {
    LoadAt(path, std::nullopt);
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": skins[0].inverseBindMatrices: accessor "),
              std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(" holds 1 matrix for 2 joints"), std::string::npos) << e.what();
  }
  test::ExpectRefusedWritingNothing(path, "--time 0.5", dir);
}

// A square (y = 0) whose one morph target lifts every vertex by (0, 2, 0).
std::string WriteMorphed(const std::string& dir, json meshWeights, json nodeWeights, bool animate) {
  test::GltfSceneWriter w;
  int mesh = w.AddFloor(1.0f);
  std::vector<vec3> delta(4, vec3(0, 2, 0));
  w.doc["meshes"][mesh]["primitives"][0]["targets"] = {{{"POSITION", w.AddAccessor(delta.data(), 4, 12, 5126, "VEC3")}}};
  if (!meshWeights.is_null()) w.doc["meshes"][mesh]["weights"] = meshWeights;
  json node = {{"mesh", mesh}};
  if (!nodeWeights.is_null()) node["weights"] = nodeWeights;
  int n = w.AddNode(node);
  if (animate) {
    json anim;
    AnimChannel(anim, AnimSampler(w, anim, {0, 1}, {0, 1}, "SCALAR", 1), n, "weights");
    w.doc["animations"] = {anim};
  }
  return w.Write(dir, "morphed");
}

float MaxY(const SceneDesc& s) {
  float y = -INFINITY;
  for (const Triangle& t : s.triangles) y = std::max({y, t.p0.y, t.p1.y, t.p2.y});
  return y;
}

TEST(GltfAnimation, MorphTargetsFollowMeshNodeAndAnimatedWeights) {
  std::string dir = test::TempDir();
  EXPECT_FLOAT_EQ(MaxY(LoadAt(WriteMorphed(dir, json::array({0.5}), nullptr, false), std::nullopt)), 1.0f);
  EXPECT_FLOAT_EQ(MaxY(LoadAt(WriteMorphed(dir, json::array({0.5}), json::array({0.25}), false), std::nullopt)), 0.5f);
  EXPECT_FLOAT_EQ(MaxY(LoadAt(WriteMorphed(dir, nullptr, nullptr, false), std::nullopt)), 0.0f);
  std::string animated = WriteMorphed(dir, json::array({0.5}), nullptr, true);
  EXPECT_FLOAT_EQ(MaxY(LoadAt(animated, 0.5)), 1.0f);
  EXPECT_FLOAT_EQ(MaxY(LoadAt(animated, 0.125)), 0.25f);
  EXPECT_FLOAT_EQ(MaxY(LoadAt(animated, std::nullopt)), 1.0f);  // static: the mesh's weights
}

TEST(GltfAnimation, AnimatedCameraAndInstances) {
  test::GltfSceneWriter w;
  int mesh = AnimTriangle(w);
  int moving = w.AddNode({{"mesh", mesh}});
  w.AddNode({{"mesh", mesh}, {"translation", {0, 3, 0}}});
  int camera = w.AddNode({{"camera", w.AddCamera(test::GltfSceneWriter::Perspective(0.8))},
                          {"translation", {0, 0, 5}}});
  json anim;
  AnimChannel(anim, AnimSampler(w, anim, {0, 2}, {0, 0, 5, 0, 0, 9}, "VEC3", 3), camera, "translation");
  AnimChannel(anim, AnimSampler(w, anim, {0, 2}, {0, 0, 0, 4, 0, 0}, "VEC3", 3), moving, "translation");
  w.doc["animations"] = {anim};
  std::string path = w.Write(test::TempDir(), "camera");
  SceneDesc s = LoadAt(path, 1.0);
  ExpectNear(s.camera.position, vec3(0, 0, 7), 1e-6f, "camera");
  ASSERT_EQ(s.meshes.size(), 1u);  // still one mesh, placed twice
  ASSERT_EQ(s.instances.size(), 2u);
  ExpectNear(vec3(s.instances[0].toWorld[3]), vec3(2, 0, 0), 1e-6f, "animated instance");
  ExpectNear(vec3(s.instances[1].toWorld[3]), vec3(0, 3, 0), 0.0f, "still instance");
  ExpectNear(LoadAt(path, std::nullopt).camera.position, vec3(0, 0, 5), 0.0f, "static camera");
}

TEST(GltfAnimation, TimeOutsideTheClipIsClampedAndSaidOnce) {
  std::string dir = test::TempDir();
  std::string path = WriteTranslated(dir);
  SceneDesc late = LoadAt(path, 7.5), end = LoadAt(path, 2.0);
  EXPECT_EQ(NodeOffsets(late)[0], NodeOffsets(end)[0]);
  std::string output;
  int status = test::RunPathtracer(path + " --time 7.5 -o " + dir + "/late.png --width 8 --height 8 --spp 1 "
                                   "--backend cpu --threads 1 --quiet", &output);
  EXPECT_EQ(status, 0) << output;
  std::string line = "time 7.5 s lies outside animation 0 \"move\" (0 s to 2 s): posed at its end, 2 s";
  size_t first = output.find(line);
  EXPECT_NE(first, std::string::npos) << output;
  EXPECT_EQ(output.find(line, first + 1), std::string::npos) << "said twice: " << output;
}

TEST(GltfAnimation, UnknownAnimationAndMalformedSamplersAreRefused) {
  std::string dir = test::TempDir();
  std::string path = WriteTranslated(dir);
  try {
    LoadAt(path, 1.0, "jump");
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": no animation \"jump\" in the file (animations: 0 \"move\")");
  }
  test::ExpectRefusedWritingNothing(path, "--animation 3", dir);
  json doc = json::parse(test::ReadText(path));
  doc["animations"][0]["samplers"][0]["output"] = doc["animations"][0]["samplers"][2]["output"];
  std::ofstream(path) << doc.dump();
  try {
    LoadAt(path, 1.0);
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": animations[0].samplers[0].output: 6 elements for 3 "
                                                "keyframes (expected 3)"), std::string::npos) << e.what();
  }
}

TEST(GltfAnimation, JsonSceneIncludesTakeTimeAndAnimation) {
  std::string dir = test::TempDir();
  WriteTranslated(dir);
  std::string json = R"({"render": {"width": 1, "height": 1, "spp": 1, "max_depth": 1},
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 40}, "materials": {},
      "objects": [{"type": "mesh", "file": "translated.gltf", "animation": "move", "time": 0.25}]})";
  SceneDesc s = LoadSceneFromString(json, "anim.json", dir);
  ExpectNear(NodeOffsets(s)[0], vec3(0.5f, 0, 0), 1e-6f, "the include's time");
  LoadOptions cli;
  cli.time = 1.5;
  ExpectNear(NodeOffsets(LoadSceneFromString(json, "anim.json", dir, cli))[0], vec3(2, 2, 0), 1e-6f,
             "--time replaces it");
}

TEST(GltfAnimation, CommandLineTakesTimeAndAnimation) {
  CliOptions o = test::Parse({"s.glb", "-o", "x.png", "--time", "-0.5", "--animation=Run"});
  ASSERT_TRUE(o.time.has_value());
  EXPECT_EQ(*o.time, -0.5);  // before the clip: clamped by the loader, not refused here
  EXPECT_EQ(o.animation, "Run");
  EXPECT_FALSE(test::Parse({"s.glb", "-o", "x.png", "--time-limit", "3"}).time.has_value());
  EXPECT_EQ(test::ParseError({"s.glb", "-o", "x.png", "--time", "soon"}),
            "bad number for --time: 'soon' (expected seconds)");
  EXPECT_EQ(test::ParseError({"s.glb", "-o", "x.png", "--time", "inf"}),
            "bad number for --time: 'inf' (expected seconds)");
  EXPECT_EQ(test::ParseError({"s.glb", "-o", "x.png", "--animation="}),
            "empty animation for --animation (an index or a name)");
}

}  // namespace
}  // namespace pt
