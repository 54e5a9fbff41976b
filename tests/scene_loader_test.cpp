// The scene loader: defaults, fields, transforms, shapes, and the project's and shared meshes.
#include "src/io/scene_loader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "src/io/mesh_common.h"
#include "src/scene/transform.h"
#include "tests/test_util.h"

namespace pt {
namespace {

const char* kWhite = R"("white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]})";

std::string SceneText(const std::string& objects, const std::string& materials = kWhite,
                  const std::string& extra = "") {
  return R"({"render": {"width": 4, "height": 2, "spp": 1, "max_depth": 1},
             "camera": {"position": [0, 0, 0], "look_at": [0, 0, -2], "fov_y": 45},
             "materials": {)" + materials + R"(}, "objects": [)" + objects + "]" + extra + "}";
}

SceneDesc Load(const std::string& text, const std::string& baseDir = test::SourcePath("scenes")) {
  return LoadSceneFromString(text, "test.json", baseDir);
}

void ExpectNear(vec3 a, vec3 b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

vec3 Apply(const glm::mat4& m, vec3 p) { return vec3(m * vec4(p, 1.0f)); }

std::string RowMajor(const glm::mat4& m) {
  std::string s;
  char buf[32];
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) {
      std::snprintf(buf, sizeof(buf), "%.9g", m[col][row]);
      s += (s.empty() ? "" : ", ") + std::string(buf);
    }
  }
  return "[" + s + "]";
}

bool AnyWarningContains(const SceneDesc& s, const std::string& text) {
  for (const std::string& w : s.warnings) {
    if (w.find(text) != std::string::npos) return true;
  }
  return false;
}

int MaterialNamed(const SceneDesc& s, const std::string& suffix) {
  for (size_t i = 0; i < s.materialNames.size(); ++i) {
    const std::string& n = s.materialNames[i];
    if (n.size() >= suffix.size() && n.compare(n.size() - suffix.size(), suffix.size(), suffix) == 0) {
      return int(i);
    }
  }
  return -1;
}

// Interpolated normals must agree with the geometric normal (same transform for both).
void ExpectNormalsAgree(const SceneDesc& s) {
  ASSERT_EQ(s.triangleNormals.size(), s.triangles.size());
  for (size_t i = 0; i < s.triangles.size(); ++i) {
    const Triangle& t = s.triangles[i];
    vec3 g = glm::normalize(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
    const TriangleNormals& n = s.triangleNormals[i];
    ASSERT_NEAR(glm::length(n.n0), 1.0f, 1e-4f) << "triangle " << i;
    ASSERT_GT(glm::dot(g, n.n0 + n.n1 + n.n2), 0.5f) << "triangle " << i;
  }
}

TEST(SceneLoader, Defaults) {
  SceneDesc s = Load(SceneText(""));
  EXPECT_EQ(s.path, "test.json");
  EXPECT_EQ(s.render.width, 4);
  EXPECT_EQ(s.render.height, 2);
  EXPECT_EQ(s.render.seed, 0u);
  EXPECT_EQ(s.render.russianRouletteDepth, 3);
  EXPECT_FALSE(s.render.adaptive.enabled);
  ExpectNear(s.camera.up, vec3(0, 1, 0));
  EXPECT_EQ(s.camera.apertureRadius, 0.0f);
  EXPECT_FLOAT_EQ(s.camera.focusDistance, 2.0f);  // distance to look_at
  ExpectNear(s.background, vec3(0.0f));
  EXPECT_TRUE(s.pointLights.empty());
  EXPECT_TRUE(s.warnings.empty());
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materialNames[0], "white");
}

TEST(SceneLoader, RenderAndCameraFields) {
  SceneDesc s = Load(R"({
    // comments are allowed
    "format": 1, /* block comments too */
    "render": {"width": 640, "height": 480, "spp": 256, "max_depth": 0, "seed": 4294967295,
               "russian_roulette_depth": 5,
               "adaptive": {"tolerance": 0.02, "min_spp": 8, "batch": 32}},
    "camera": {"position": [1, 2, 3], "look_at": [1, 2, 0], "up": [0, 0.5, 0], "fov_y": 30,
               "aperture_radius": 0.1, "focus_distance": 2.5},
    "background": [0.1, 0.2, 0.3], "materials": {}, "objects": [],
    "lights": [{"type": "point", "position": [0, 1.9, 0], "intensity": [5, 4, 3]}]})");
  EXPECT_EQ(s.render.spp, 256);
  EXPECT_EQ(s.render.maxDepth, 0);
  EXPECT_EQ(s.render.seed, 4294967295u);
  EXPECT_EQ(s.render.russianRouletteDepth, 5);
  EXPECT_TRUE(s.render.adaptive.enabled);
  EXPECT_FLOAT_EQ(s.render.adaptive.tolerance, 0.02f);
  EXPECT_EQ(s.render.adaptive.minSpp, 8);
  EXPECT_EQ(s.render.adaptive.batch, 32);
  ExpectNear(s.camera.position, vec3(1, 2, 3));
  ExpectNear(s.camera.lookAt, vec3(1, 2, 0));
  ExpectNear(s.camera.up, vec3(0, 0.5f, 0));
  EXPECT_FLOAT_EQ(s.camera.fovY, 30.0f);
  EXPECT_FLOAT_EQ(s.camera.apertureRadius, 0.1f);
  EXPECT_FLOAT_EQ(s.camera.focusDistance, 2.5f);
  ExpectNear(s.background, vec3(0.1f, 0.2f, 0.3f));
  ASSERT_EQ(s.pointLights.size(), 1u);
  ExpectNear(s.pointLights[0].intensity, vec3(5, 4, 3));
}

TEST(SceneLoader, MaterialsInFileOrderWithDefaults) {
  SceneDesc s = Load(SceneText(R"({"type": "sphere", "center": [0, 0, -3], "radius": 1, "material": "lamp"})",
                           R"("zeta": {"type": "diffuse", "albedo": [1, 0, 0.5]},
                              "lamp": {"type": "emissive", "radiance": [17, 12, 4], "two_sided": true},
                              "mirror": {"type": "conductor", "albedo": [0.9, 0.9, 0.9], "roughness": 0},
                              "glass": {"type": "dielectric", "ior": 1.33, "absorption": [0.1, 0.2, 0]},
                              "alpha": {"type": "emissive", "radiance": [1, 1, 1]})"));
  ASSERT_EQ(s.materialNames, (std::vector<std::string>{"zeta", "lamp", "mirror", "glass", "alpha"}));
  EXPECT_EQ(s.materials[0].type, MaterialType::kDiffuse);
  EXPECT_EQ(s.materials[1].type, MaterialType::kEmissive);
  EXPECT_EQ(s.materials[1].twoSided, 1u);
  EXPECT_EQ(s.materials[4].twoSided, 0u);
  ExpectNear(s.materials[1].radiance, vec3(17, 12, 4));
  EXPECT_EQ(s.materials[2].type, MaterialType::kConductor);
  EXPECT_EQ(s.materials[2].roughness, 0.0f);
  EXPECT_EQ(s.materials[3].type, MaterialType::kDielectric);
  EXPECT_FLOAT_EQ(s.materials[3].ior, 1.33f);
  ExpectNear(s.materials[3].absorption, vec3(0.1f, 0.2f, 0));
  EXPECT_EQ(s.sphereMaterials, (std::vector<uint32_t>{1}));
}

TEST(SceneTransform, RotationOrderIsXThenYThenZ) {
  // Rx(90) takes +y to +z; Ry(90) then takes +z to +x. The reverse order would give +z.
  ExpectNear(Apply(TrsMatrix(vec3(1), vec3(90, 90, 0), vec3(0)), vec3(0, 1, 0)), vec3(1, 0, 0));
  ExpectNear(Apply(TrsMatrix(vec3(1), vec3(0, 0, 90), vec3(0)), vec3(1, 0, 0)), vec3(0, 1, 0));
  // Scale, then rotate, then translate.
  ExpectNear(Apply(TrsMatrix(vec3(2), vec3(0, 0, 90), vec3(1, 2, 3)), vec3(1, 0, 0)), vec3(1, 4, 3));
  // Multiples of 90 degrees are exact.
  glm::mat4 m = TrsMatrix(vec3(1), vec3(0, 90, 0), vec3(0));
  EXPECT_EQ(Apply(m, vec3(0, 0, 1)), vec3(1, 0, 0));
}

TEST(SceneTransform, MatrixFormAndTrsFormGiveTheSamePoints) {
  glm::mat4 trs = TrsMatrix(vec3(1, 2, 3), vec3(10, 20, 30), vec3(0.5f, -1, 2));
  std::string quad = R"({"type": "quad", "origin": [0.1, 0.2, 0.3], "u": [1, 0, 0], "v": [0, 1, 0.5],
                         "material": "white", "transform": )";
  SceneDesc s = Load(SceneText(quad + R"({"scale": [1, 2, 3], "rotate": [10, 20, 30],
                                      "translate": [0.5, -1, 2]}},)" +
                           quad + R"({"matrix": )" + RowMajor(trs) + "}}"));
  ASSERT_EQ(s.quads.size(), 2u);
  ExpectNear(s.quads[0].origin, s.quads[1].origin);
  ExpectNear(s.quads[0].u, s.quads[1].u);
  ExpectNear(s.quads[0].v, s.quads[1].v);
  ExpectNear(s.quads[0].origin, Apply(trs, vec3(0.1f, 0.2f, 0.3f)));
}

TEST(SceneTransform, MatrixIsRowMajorWithTranslationAt3_7_11) {
  SceneDesc s = Load(SceneText(R"({"type": "quad", "origin": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0],
      "material": "white", "transform": {"matrix": [2,0,0,5, 0,3,0,6, 0,0,4,7, 0,0,0,1]}})"));
  ASSERT_EQ(s.quads.size(), 1u);
  ExpectNear(s.quads[0].origin, vec3(5, 6, 7));
  ExpectNear(s.quads[0].u, vec3(2, 0, 0));  // vectors take no translation
  ExpectNear(s.quads[0].v, vec3(0, 3, 0));
}

TEST(SceneLoader, BoxGivesSixOutwardQuads) {
  SceneDesc s = Load(SceneText(R"({"type": "box", "min": [-1, -2, -3], "max": [1, 2, 3], "material": "white",
      "transform": {"rotate": [0, 30, 0], "translate": [5, 0, 0]}})"));
  ASSERT_EQ(s.quads.size(), 6u);
  ASSERT_EQ(s.quadMaterials.size(), 6u);
  vec3 center(5, 0, 0);
  float area = 0;
  for (const Quad& q : s.quads) {
    vec3 n = glm::cross(q.u, q.v);
    area += glm::length(n);
    EXPECT_GT(glm::dot(q.origin + 0.5f * (q.u + q.v) - center, n), 0.0f);
  }
  EXPECT_NEAR(area, 2 * (2 * 4 + 2 * 6 + 4 * 6), 1e-3);
}

TEST(SceneLoader, SphereScaledByUniformScale) {
  SceneDesc s = Load(SceneText(R"({"type": "sphere", "center": [1, 0, 0], "radius": 0.5, "material": "white",
        "transform": {"scale": 2, "rotate": [0, 0, 90], "translate": [0, 1, 0]}},
      {"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": "white",
        "transform": {"scale": [-3, -3, -3]}},
      {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white",
        "transform": {"matrix": [0,-2,0,1, 2,0,0,0, 0,0,2,0, 0,0,0,1]}})"));
  ASSERT_EQ(s.spheres.size(), 3u);
  ExpectNear(s.spheres[0].center, vec3(0, 3, 0));
  EXPECT_FLOAT_EQ(s.spheres[0].radius, 1.0f);
  EXPECT_FLOAT_EQ(s.spheres[1].radius, 1.5f);  // |scale|
  ExpectNear(s.spheres[2].center, vec3(1, 0, 0));
  EXPECT_NEAR(s.spheres[2].radius, 2.0f, 1e-6f);
}

TEST(SceneLoader, DegenerateTriangleTest) {
  vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_FALSE(IsDegenerateTriangle(a, b, c));
  EXPECT_FALSE(IsDegenerateTriangle(a * 1e-4f, b * 1e-4f, c * 1e-4f));  // tiny is not degenerate
  EXPECT_FALSE(IsDegenerateTriangle(a * 1e5f, b * 1e5f, c * 1e5f));
  EXPECT_TRUE(IsDegenerateTriangle(a, a, c));                                  // repeated
  EXPECT_TRUE(IsDegenerateTriangle(a, b, vec3(0.3f, 0, 0)));                   // collinear
  EXPECT_TRUE(IsDegenerateTriangle(vec3(0.25f, 0.5f, 0.125f), vec3(0.75f, 2.0f, 0.875f),
                                   vec3(1.25f, 3.5f, 1.625f)));  // collinear, not axis-aligned
  EXPECT_TRUE(IsDegenerateTriangle(a, b, vec3(NAN, 0, 0)));
  EXPECT_TRUE(IsDegenerateTriangle(a, b, vec3(0, INFINITY, 0)));
}

// ---- Meshes ----------------------------------------------------------------------------------

TEST(SceneGltf, GeneratedGlbThroughMeshScene) {
  SceneDesc s = LoadScene(test::SourcePath("scenes/mesh_scene.json"));
  ASSERT_EQ(s.triangles.size(), 2624u);  // torus 48 x 24 x 2 + icosphere 320
  EXPECT_EQ(s.skippedDegenerateTriangles, 0);
  ExpectNormalsAgree(s);
  int gold = MaterialNamed(s, ":gold");
  ASSERT_GE(gold, 0);
  EXPECT_EQ(s.materials[gold].type, MaterialType::kConductor);
  ExpectNear(s.materials[gold].albedo, vec3(1.0f, 0.766f, 0.336f));
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  // The icosphere (last 320 triangles): node scale 0.3 at (0.42, 0.305, 0.4), parent z -0.1.
  for (size_t i = 2304; i < s.triangles.size(); ++i) {
    float d = glm::length(s.triangles[i].p0 - vec3(0.42f, 0.305f, 0.3f));
    ASSERT_GT(d, 0.29f);
    ASSERT_LT(d, 0.3001f);
  }
  // The torus stands on the floor: lowest point 0.002 above it.
  float minY = 1e9f;
  for (size_t i = 0; i < 2304; ++i) minY = std::min(minY, s.triangles[i].p0.y);
  EXPECT_NEAR(minY, 0.002f, 2e-3f);
}

TEST(SceneGltf, MaterialOverrideAndObjectTransform) {
  std::string mesh = R"({"type": "mesh", "file": "meshes/smooth_shapes.glb")";
  SceneDesc plain = Load(SceneText(mesh + "}"));
  SceneDesc moved = Load(SceneText(mesh + R"(, "material": "white", "transform": {"translate": [0, 1, 0]}})"));
  ASSERT_EQ(plain.triangles.size(), moved.triangles.size());
  EXPECT_EQ(moved.materials.size(), 1u);  // no glTF materials added
  for (uint32_t m : moved.triangleMaterials) ASSERT_EQ(m, 0u);
  for (size_t i = 0; i < plain.triangles.size(); i += 97) {
    ExpectNear(moved.triangles[i].p1, plain.triangles[i].p1 + vec3(0, 1, 0));
  }
}

TEST(SceneGltf, KhronosBoxWithNodeTransform) {
  if (!test::HaveShared()) GTEST_SKIP() << "../shared is not present (a user's clone)";
  std::string file = test::SharedPath("assets/khronos/Box/glTF-Binary/Box.glb");
  SceneDesc s = Load(SceneText(R"({"type": "mesh", "file": ")" + file +
                           R"(", "transform": {"scale": [1, 2, 3]}})"));
  ASSERT_EQ(s.triangles.size(), 12u);
  vec3 lo(1e9f), hi(-1e9f);
  for (const Triangle& t : s.triangles) {
    for (vec3 p : {t.p0, t.p1, t.p2}) lo = glm::min(lo, p), hi = glm::max(hi, p);
  }
  ExpectNear(lo, vec3(-0.5f, -1.0f, -1.5f));
  ExpectNear(hi, vec3(0.5f, 1.0f, 1.5f));
  ExpectNormalsAgree(s);  // the node's y/z swap reaches positions and normals alike
  int red = MaterialNamed(s, ":Red");
  ASSERT_GE(red, 0);
  EXPECT_EQ(s.materials[red].type, MaterialType::kGltfPbr);  // metallic 0: coated diffuse
  EXPECT_FLOAT_EQ(s.materials[red].metallic, 0.0f);
  EXPECT_FLOAT_EQ(s.materials[red].ior, 1.5f);
  EXPECT_FLOAT_EQ(s.materials[red].roughness, 1.0f);  // glTF default roughness
  ExpectNear(s.materials[red].albedo, vec3(0.8f, 0, 0));
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();  // nothing approximated
}

TEST(SceneGltf, BunnyNpmTriangleCount) {
  if (!test::HaveShared()) GTEST_SKIP() << "../shared is not present (a user's clone)";
  SceneDesc s = Load(SceneText(R"({"type": "mesh", "material": "white", "file": ")" +
                           test::SharedPath("assets/bunny-npm/bunny_npm.glb") + "\"}"));
  EXPECT_EQ(s.triangles.size() + s.skippedDegenerateTriangles, 3674u);
  EXPECT_EQ(s.triangleNormals.size(), s.triangles.size());
  EXPECT_EQ(s.triangleNormals[0].n0, vec3(0.0f));  // the file has no normals
}

TEST(SceneGltf, TransmissionMaterialsMapWithTheirTints) {
  if (!test::HaveShared()) GTEST_SKIP() << "../shared is not present (a user's clone)";
  SceneDesc s = Load(SceneText(R"({"type": "mesh", "file": ")" +
      test::SharedPath("assets/khronos/GlassHurricaneCandleHolder/glTF-Binary/"
                       "GlassHurricaneCandleHolder.glb") + "\"}"));
  EXPECT_EQ(s.triangles.size() + s.skippedDegenerateTriangles, 4126u);
  int glass = MaterialNamed(s, ":GlassHurricaneCandleHolder-glass");
  ASSERT_GE(glass, 0);
  const Material& g = s.materials[glass];
  EXPECT_EQ(g.type, MaterialType::kGltfPbr);
  EXPECT_FLOAT_EQ(g.transmission, 1.0f);
  EXPECT_FLOAT_EQ(g.ior, 1.5f);
  EXPECT_EQ(g.roughness, 1.0f);  // glTF default roughness 1, scaled by the texture's G
  EXPECT_GE(g.baseColorTexture, 0);  // the tint of transmission is honoured
  EXPECT_GE(g.metallicRoughnessTexture, 0);
  EXPECT_FALSE(g.flags & kMaterialThinWalled);  // thicknessFactor 0.1: a volume
  EXPECT_FALSE(g.flags & kMaterialCullBack);    // rays inside must meet its back faces
  ExpectNear(g.absorption, vec3(-std::log(0.8f) / 0.001f, -std::log(0.95f) / 0.001f, 0), 1e-2f);
  // One summary line: only the occlusion textures (of both materials) are not honoured.
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("materials: occlusionTexture ignored (2 materials)"),
            std::string::npos) << s.warnings[0];
  EXPECT_EQ(s.warnings[0].find("thicknessTexture"), std::string::npos) << s.warnings[0];
  int opaque = MaterialNamed(s, ":GlassHurricaneCandleHolder-opaque");
  ASSERT_GE(opaque, 0);
  EXPECT_EQ(s.materials[opaque].type, MaterialType::kGltfPbr);  // a textured metallic 1
  EXPECT_EQ(s.materials[opaque].roughness, 1.0f);
  EXPECT_GE(s.materials[opaque].baseColorTexture, 0);
  EXPECT_EQ(s.triangleUvs.size(), s.triangles.size());

  SceneDesc iors = Load(SceneText(R"({"type": "mesh", "file": ")" +
      test::SharedPath("assets/khronos/TransmissionRoughnessTest/glTF-Binary/"
                       "TransmissionRoughnessTest.glb") + "\"}"));
  for (auto [name, ior] : {std::pair{":Mat_IOR_1.0", 1.0f}, {":Mat_IOR_1.33", 1.33f},
                           {":Mat_IOR_1.50", 1.5f}, {":Mat_IOR_2.42", 2.42f}}) {
    int m = MaterialNamed(iors, name);
    ASSERT_GE(m, 0) << name;
    EXPECT_EQ(iors.materials[m].type, MaterialType::kGltfPbr) << name;
    EXPECT_FLOAT_EQ(iors.materials[m].transmission, 1.0f) << name;
    EXPECT_FLOAT_EQ(iors.materials[m].ior, ior) << name;
    ExpectNear(iors.materials[m].albedo, vec3(0.5f, 0.7f, 0.9f));  // the tint
  }
}

TEST(SceneObj, CornellBoxOriginalMeshes) {
  if (!test::HaveShared()) GTEST_SKIP() << "../shared is not present (a user's clone)";
  std::string objects;
  for (const char* part : {"floor", "ceiling", "back", "greenwall", "redwall", "largebox",
                           "smallbox", "luminaire"}) {
    objects += std::string(objects.empty() ? "" : ",") + R"({"type": "mesh", "file": ")" +
               test::SharedPath("assets/cornell-box-original/meshes/cbox_") + part + ".obj\"}";
  }
  SceneDesc s = Load(SceneText(objects));
  EXPECT_EQ(s.triangles.size(), 38u);
  EXPECT_EQ(s.skippedDegenerateTriangles, 0);
  vec3 lo(1e9f), hi(-1e9f);
  for (const Triangle& t : s.triangles) {
    for (vec3 p : {t.p0, t.p1, t.p2}) lo = glm::min(lo, p), hi = glm::max(hi, p);
  }
  ExpectNear(lo, vec3(0, 0, 0), 1e-3f);
  EXPECT_NEAR(hi.y, 548.8f, 1e-3f);  // millimetres
  // No .mtl: one default grey diffuse per file; the boxes' vn normals are kept.
  for (uint32_t m : s.triangleMaterials) {
    ASSERT_EQ(s.materials[m].type, MaterialType::kDiffuse);
    ExpectNear(s.materials[m].albedo, vec3(0.8f));
  }
  EXPECT_GT(glm::length(s.triangleNormals[12].n0), 0.0f);  // the first of cbox_largebox
  EXPECT_EQ(s.triangleNormals[0].n0, vec3(0.0f));          // the floor has no vn
}

TEST(SceneObj, MtlMaterialsAndDegenerateFaces) {
  std::string dir = test::TempDir();
  std::ofstream(dir + "/m.mtl") << "newmtl hot\nKd 1.5 0.5 0.25\nnewmtl light\nKe 4 3 2\n";
  std::ofstream(dir + "/m.obj")
      << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n"
         "usemtl hot\nf 1 2 3 4\nusemtl light\nf 1 2 3\nf 1 1 3\nf 1 2 5\n";
  SceneDesc s = Load(SceneText(R"({"type": "mesh", "file": "m.obj"})"), dir);
  ASSERT_EQ(s.triangles.size(), 3u);  // the quad's two and one lit triangle
  EXPECT_EQ(s.skippedDegenerateTriangles, 2);
  EXPECT_TRUE(AnyWarningContains(s, "skipped 2 degenerate triangles"));
  EXPECT_TRUE(AnyWarningContains(s, "Kd clamped"));
  const Material& hot = s.materials[s.triangleMaterials[0]];
  EXPECT_EQ(hot.type, MaterialType::kDiffuse);
  ExpectNear(hot.albedo, vec3(1.0f, 0.5f, 0.25f));
  const Material& light = s.materials[s.triangleMaterials[2]];
  EXPECT_EQ(light.type, MaterialType::kEmissive);
  ExpectNear(light.radiance, vec3(4, 3, 2));
  EXPECT_EQ(s.triangleNormals[0].n0, vec3(0.0f));  // no vn: zero normals
}

TEST(SceneFiles, ProjectScenesLoad) {
  SceneDesc box = LoadScene(test::SourcePath("scenes/cornell_box.json"));
  EXPECT_EQ(box.render.width, 512);
  EXPECT_EQ(box.render.spp, 64);
  EXPECT_EQ(box.render.maxDepth, 8);
  EXPECT_EQ(box.quads.size(), 6u + 12u);
  EXPECT_TRUE(box.warnings.empty());
  SceneDesc glass = LoadScene(test::SourcePath("scenes/cornell_glass_mirror.json"));
  EXPECT_EQ(glass.spheres.size(), 2u);
  for (const char* name : {"cornell_box.json", "cornell_glass_mirror.json", "mesh_scene.json"}) {
    std::ifstream in(test::SourcePath(std::string("scenes/") + name));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(text.find("shared"), std::string::npos) << name << " must be self-contained";
  }
  if (!test::HaveShared()) GTEST_SKIP() << "../shared is not present: bunny_cornell.json skipped";
  SceneDesc bunny = LoadScene(test::SourcePath("benchmarks/scenes/bunny_cornell.json"));
  EXPECT_EQ(bunny.triangles.size() + bunny.skippedDegenerateTriangles, 69451u);
  EXPECT_EQ(bunny.render.width, 1920);
  EXPECT_EQ(bunny.render.height, 1080);
  float minY = 1e9f;
  for (const Triangle& t : bunny.triangles) minY = std::min({minY, t.p0.y, t.p1.y, t.p2.y});
  EXPECT_NEAR(minY, 0.0f, 2e-3f);  // resting on the floor
}

}  // namespace
}  // namespace pt
