// Textures: the software lookup (wrap modes, bilinear weights), the sRGB decode, and an
// end-to-end render of a textured glTF square under a uniform white environment.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <vector>

#include "src/geometry/shapes.h"
#include "src/materials/resolve.h"
#include "src/materials/texture.h"
#include "src/materials/texture_pyramid.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"
#include "tests/gltf_writer.h"
#include "tests/texture_test_util.h"

namespace pt {
namespace {

// A 4 x 2 texture whose texel (x, y) holds the linear codes (60 x, 60 y, 60, 255): scaled by
// 255 / 60, every tap reads (x, y, 1) and is identifiable.
struct TinyTexture {
  std::vector<Texture> textures;
  std::vector<uint32_t> texels;
  SceneView view;

  explicit TinyTexture(TextureWrap wrapS, TextureWrap wrapT = TextureWrap::kRepeat) {
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 4; ++x) texels.push_back(PackRgba8(60 * x, 60 * y, 60, 255));
    Texture t;
    t.width = 4;
    t.height = 2;
    t.wrapS = wrapS;
    t.wrapT = wrapT;
    textures.push_back(t);
    view.textures = textures.data();
    view.texels = texels.data();
  }
  vec3 At(vec2 uv) const { return vec3(SampleTexture(view, 0, uv)) * (255.0f / 60.0f); }
  // The texel coordinate x (column, continuous; centres at integers) on row 0, as u.
  vec3 AtColumn(float x) const { return At(vec2((x + 0.5f) / 4.0f, 0.25f)); }
};

void ExpectVec(vec3 got, vec3 want, const char* what) {
  EXPECT_NEAR(got.x, want.x, 2e-6f) << what;
  EXPECT_NEAR(got.y, want.y, 2e-6f) << what;
  EXPECT_NEAR(got.z, want.z, 2e-6f) << what;
}

TEST(TextureSample, TexelCentresAndBilinearWeights) {
  TinyTexture t(TextureWrap::kClampToEdge, TextureWrap::kClampToEdge);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      vec2 uv((x + 0.5f) / 4.0f, (y + 0.5f) / 2.0f);  // v runs down the image's rows
      ExpectVec(t.At(uv), vec3(x, y, 1), "texel centre");
    }
  // A quarter of a texel right of column 1 and down from row 0: weights 3/4, 1/4 on each axis.
  vec3 v = t.At(vec2((1.25f + 0.5f) / 4.0f, (0.25f + 0.5f) / 2.0f));
  ExpectVec(v, vec3(0.75f * 1 + 0.25f * 2, 0.75f * 0 + 0.25f * 1, 1), "bilinear");
  ExpectVec(t.AtColumn(2.5f), vec3(2.5f, 0, 1), "halfway");
}

TEST(TextureSample, RepeatWrapsAroundBothEdges) {
  TinyTexture t(TextureWrap::kRepeat);
  ExpectVec(t.AtColumn(-0.5f), vec3(0.5f * 3 + 0.5f * 0, 0, 1), "u = 0 blends the last and first");
  ExpectVec(t.AtColumn(3.25f), vec3(0.75f * 3 + 0.25f * 0, 0, 1), "past the right edge");
  ExpectVec(t.AtColumn(1.0f + 4.0f * 7), vec3(1, 0, 1), "seven periods on");
  ExpectVec(t.AtColumn(1.0f - 4.0f * 3), vec3(1, 0, 1), "three periods back");
  ExpectVec(t.At(vec2(1.0e6f + 0.125f, 0.25f)), vec3(0, 0, 1), "u = 1e6 + 1/8");
  // Rows: v = 0 sits between row 0 and row 1 (repeat), at half weight each.
  ExpectVec(t.At(vec2(0.125f, 0.0f)), vec3(0, 0.5f, 1), "v = 0");
}

TEST(TextureSample, ClampHoldsTheEdgeTexels) {
  TinyTexture t(TextureWrap::kClampToEdge);
  ExpectVec(t.AtColumn(-0.5f), vec3(0, 0, 1), "u = 0");
  ExpectVec(t.AtColumn(-40.0f), vec3(0, 0, 1), "far left");
  ExpectVec(t.AtColumn(3.5f), vec3(3, 0, 1), "u = 1");
  ExpectVec(t.AtColumn(1.0e9f), vec3(3, 0, 1), "far right");
  ExpectVec(t.AtColumn(2.75f), vec3(2.75f, 0, 1), "inside still bilinear");
}

TEST(TextureSample, MirroredRepeatReflectsEachPeriod) {
  TinyTexture t(TextureWrap::kMirroredRepeat);
  // Columns continue 3, 2, 1, 0 past the right edge and 0, 1, 2 past the left, period 8.
  ExpectVec(t.AtColumn(4.0f), vec3(3, 0, 1), "first mirrored column");
  ExpectVec(t.AtColumn(5.0f), vec3(2, 0, 1), "second mirrored column");
  ExpectVec(t.AtColumn(3.5f), vec3(3, 0, 1), "u = 1: column 3 twice");
  ExpectVec(t.AtColumn(4.5f), vec3(2.5f, 0, 1), "between mirrored columns");
  ExpectVec(t.AtColumn(-1.0f), vec3(0, 0, 1), "left of u = 0");
  ExpectVec(t.AtColumn(-2.0f), vec3(1, 0, 1), "two left of u = 0");
  ExpectVec(t.AtColumn(1.0f + 8.0f * 5), vec3(1, 0, 1), "five periods on");
  ExpectVec(t.AtColumn(6.0f - 8.0f * 2), vec3(1, 0, 1), "column 6 mirrors to 1, two periods back");
}

TEST(TextureSample, NonFiniteCoordinatesStayFinite) {
  for (TextureWrap w : {TextureWrap::kRepeat, TextureWrap::kClampToEdge, TextureWrap::kMirroredRepeat}) {
    TinyTexture t(w, w);
    for (float bad : {NAN, INFINITY, -INFINITY, 3.0e38f}) {
      vec3 v = t.At(vec2(bad, bad));
      EXPECT_TRUE(IsFinite(v)) << "wrap " << int(w) << " coordinate " << bad;
    }
  }
}

// A non-glTF material with a base colour texture (on a quad, whose texture coordinates are its
// (s, t) parameters): the texture multiplies the factor; without one the factor stands.
TEST(TextureSample, ResolveMaterialMultipliesTheFactor) {
  TinyTexture t(TextureWrap::kClampToEdge);
  Material m;
  m.albedo = vec3(0.5f, 0.25f, 1.0f);
  m.baseColorTexture = 0;
  Material plain = m;
  plain.baseColorTexture = -1;
  std::vector<Material> materials = {m, plain};
  std::vector<TextureRef> refs(1);
  refs[0].texture = 0;
  std::vector<Quad> quads = {Quad{vec3(0.0f), vec3(1, 0, 0), vec3(0, 1, 0)}};
  t.view.materials = materials.data();
  t.view.textureRefs = refs.data();
  t.view.quads = quads.data();
  PrimRef ref{PrimRef::Pack(ShapeType::kQuad, 0), 0, -1};
  SurfaceInteraction si;
  si.material = 0;
  si.uv = vec2(2.5f / 4.0f, 1.5f / 2.0f);  // texel (2, 1): codes (120, 60, 60)
  ExpectVec(ResolveMaterial(t.view, ref, &si).albedo * (255.0f / 60.0f),
            vec3(0.5f * 2, 0.25f * 1, 1.0f), "textured");
  si.material = 1;
  ExpectVec(ResolveMaterial(t.view, ref, &si).albedo, plain.albedo, "untextured");
}

// Level 1 of a 4 x 2 sRGB image averages each 2 x 2 block in linear light (then encodes it with
// rounding); alpha averages linearly; a 3 x 3 level has one texel of all nine, weighted alike.
TEST(TexturePyramid, BoxFiltersInLinearLight) {
  std::vector<uint32_t> level0;
  for (int i = 0; i < 8; ++i) level0.push_back(PackRgba8(30 * i, 255 - 20 * i, 7 * i, 10 * i));
  uint32_t levels = 0;
  std::vector<uint32_t> p = BuildTexturePyramid(4, 2, level0, true, &levels);
  ASSERT_EQ(levels, 3u);  // 4 x 2, 2 x 1, 1 x 1
  ASSERT_EQ(p.size(), 8u + 2u + 1u);
  EXPECT_EQ(PyramidTexelCount(4, 2, nullptr), p.size());
  auto code = [](uint32_t t, int c) { return int((t >> (8 * c)) & 0xffu); };
  for (int x = 0; x < 2; ++x) {
    int block[4] = {2 * x, 2 * x + 1, 4 + 2 * x, 5 + 2 * x};
    for (int c = 0; c < 4; ++c) {
      double mean = 0;
      for (int i : block) mean += c < 3 ? SrgbToLinear(code(level0[i], c) / 255.0) : code(level0[i], c) / 255.0;
      mean /= 4;
      int want = int(std::lround((c < 3 ? LinearToSrgb(mean) : mean) * 255.0));
      EXPECT_EQ(code(p[8 + x], c), want) << x << " " << c;
    }
  }
  std::vector<uint32_t> nine;
  for (int i = 0; i < 9; ++i) nine.push_back(PackRgba8(i * 25, 0, 0, 255));
  std::vector<uint32_t> q = BuildTexturePyramid(3, 3, nine, false, &levels);
  ASSERT_EQ(levels, 2u);
  EXPECT_EQ(code(q[9], 0), 100);  // the mean of 0, 25, ..., 200
  EXPECT_EQ(code(q[9], 3), 255);
}

// Between levels the lookup blends the two bracketing levels' bilinear values; past the last
// level it reads the 1 x 1 level.
TEST(TexturePyramid, TrilinearBlendsTheBracketingLevels) {
  std::vector<uint32_t> level0;
  for (int i = 0; i < 16; ++i) level0.push_back(PackRgba8(i * 16, 255 - i * 16, 128, 255));
  Texture t;
  t.width = t.height = 4;
  std::vector<uint32_t> texels = BuildTexturePyramid(4, 4, level0, false, &t.levels);
  std::vector<Texture> textures = {t};
  SceneView v;
  v.textures = textures.data();
  v.texels = texels.data();
  vec2 uv(0.3f, 0.6f);
  vec4 l0 = SampleLevel(v, t, 0, uv), l1 = SampleLevel(v, t, 1, uv), l2 = SampleLevel(v, t, 2, uv);
  for (int c = 0; c < 4; ++c) {
    EXPECT_EQ(SampleTexture(v, 0, uv, 0.0f)[c], l0[c]);
    EXPECT_EQ(SampleTexture(v, 0, uv, -3.0f)[c], l0[c]);  // magnified: level 0
    EXPECT_FLOAT_EQ(SampleTexture(v, 0, uv, 0.25f)[c], 0.75f * l0[c] + 0.25f * l1[c]);
    EXPECT_EQ(SampleTexture(v, 0, uv, 1.0f)[c], l1[c]);
    EXPECT_EQ(SampleTexture(v, 0, uv, 7.0f)[c], l2[c]);
  }
}

// KHR_texture_transform through the loader: the reference's rows are T R S of the extension
// (offset, rotation, scale) and its texCoord overrides the slot's; a lookup through it equals
// the lookup at the hand-transformed coordinates.
TEST(TextureSample, TextureTransformEqualsTheHandTransformedLookup) {
  test::ScopedTempDir dir;
  test::RgbaImage img(4, 4);
  for (int i = 0; i < 16; ++i) img.Set(i % 4, i / 4, uint8_t(i * 16), uint8_t(200 - i * 9), 77, 255);
  test::GltfWriter w("transformed");
  int tex = w.AddTexture(img);
  w.UseExtension("KHR_texture_transform");
  w.AddMaterial(R"({"pbrMetallicRoughness": {"metallicFactor": 0, "baseColorTexture": {"index": )" +
                std::to_string(tex) + R"(, "texCoord": 0, "extensions": {"KHR_texture_transform":
                {"offset": [0.25, -0.5], "rotation": 0.3, "scale": [2, 3], "texCoord": 1}}}}})");
  test::GltfPrimitive sq = test::Square();
  sq.uvs1 = {vec2(0.1f, 0.2f), vec2(0.9f, 0.3f), vec2(0.7f, 0.8f), vec2(0.2f, 0.6f)};
  w.AddPrimitive(sq);
  std::string json = R"({"render": {"width": 1, "height": 1, "spp": 1, "max_depth": 1},
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 40}, "materials": {},
      "objects": [{"type": "mesh", "file": ")" + w.Write(dir) + "\"}]}";
  Scene scene = BuildScene(LoadSceneFromString(json, "t.json", dir));
  const Material& m = scene.desc.materials[0];
  ASSERT_GE(m.baseColorTexture, 0);
  const TextureRef& r = scene.desc.textureRefs[m.baseColorTexture];
  EXPECT_EQ(r.texCoord, 1u);
  double c = std::cos(0.3), sn = std::sin(0.3);
  EXPECT_NEAR(r.row0.x, 2 * c, 1e-6);
  EXPECT_NEAR(r.row0.y, 3 * sn, 1e-6);
  EXPECT_NEAR(r.row0.z, 0.25, 1e-7);
  EXPECT_NEAR(r.row1.x, -2 * sn, 1e-6);
  EXPECT_NEAR(r.row1.y, 3 * c, 1e-6);
  EXPECT_NEAR(r.row1.z, -0.5, 1e-7);
  ASSERT_EQ(scene.desc.triangleUvs1.size(), 2u);
  SceneView v = HostSceneView(scene);
  for (vec2 uv : {vec2(0.1f, 0.2f), vec2(0.45f, 0.5f), vec2(0.8f, 0.35f)}) {
    TexCoords tc;
    tc.uv[0] = vec2(9.0f);  // TEXCOORD_0 must not be read
    tc.uv[1] = uv;
    tc.width[0] = tc.width[1] = 0.0f;
    vec2 hand(float(2 * c * uv.x + 3 * sn * uv.y + 0.25), float(-2 * sn * uv.x + 3 * c * uv.y - 0.5));
    vec4 want = SampleTexture(v, r.texture, hand), got = SampleTextureRef(v, m.baseColorTexture, tc);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(got[k], want[k], 1e-5f) << uv.x << " " << uv.y;
  }
}

// The normal texture's frame from UV derivatives: tangent along dp/du, bitangent along -dp/dv
// (image up); a mirrored u flips the tangent and keeps the bitangent, so the frame stays the
// image's.
TEST(TextureSample, TangentFrameFollowsTheUvs) {
  std::vector<Triangle> tris = {Triangle{vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)}};
  for (float mirror : {1.0f, -1.0f}) {
    // u grows along +x (or -x), v grows along -y (the image's rows go down the surface).
    std::vector<TriangleUvs> uvs = {TriangleUvs{vec2(0, 1), vec2(mirror, 1), vec2(0, 0)}};
    SceneView v;
    v.triangles = tris.data();
    v.triangleUvs = uvs.data();
    PrimRef ref{PrimRef::Pack(ShapeType::kTriangle, 0), 0, -1};
    vec3 t, b;
    ASSERT_TRUE(TangentFrameAt(v, ref, vec2(0.3f, 0.3f), 0, vec3(0, 0, 1), &t, &b));
    ExpectVec(t, vec3(mirror, 0, 0), "tangent");
    ExpectVec(b, vec3(0, 1, 0), "bitangent: image up");
  }
}

TEST(Srgb, DecodeIsTheExactEotf) {
  EXPECT_EQ(SrgbToLinear(0.0), 0.0);
  EXPECT_DOUBLE_EQ(SrgbToLinear(1.0), 1.0);
  EXPECT_DOUBLE_EQ(SrgbToLinear(0.04045), 0.04045 / 12.92);  // the linear segment's end
  EXPECT_NEAR(SrgbToLinear(0.5), 0.214041140482232, 1e-15);
  EXPECT_NEAR(SrgbToLinear(0.04046), std::pow(0.09546 / 1.055, 2.4), 1e-17);
  // The two pieces meet to within the standard's rounded constants (a 7.5e-7 relative step).
  EXPECT_NEAR(SrgbToLinear(0.0404500001) / SrgbToLinear(0.04045), 1.0, 1e-6);
  EXPECT_EQ(Srgb8ToLinear(0), 0.0f);
  EXPECT_EQ(Srgb8ToLinear(255), 1.0f);
  EXPECT_EQ(Srgb8ToLinear(10), float(10.0 / 255.0 / 12.92));  // 0.0392: the linear piece
  EXPECT_EQ(Srgb8ToLinear(11), float(std::pow((11.0 / 255.0 + 0.055) / 1.055, 2.4)));
  EXPECT_NEAR(Srgb8ToLinear(128), 0.2158605, 1e-7);
  EXPECT_NEAR(Srgb8ToLinear(188), 0.5028865, 1e-7);
  for (int c = 1; c < 256; ++c) {
    ASSERT_GT(Srgb8ToLinear(uint8_t(c)), Srgb8ToLinear(uint8_t(c - 1))) << c;
    ASSERT_EQ(Srgb8ToLinear(uint8_t(c)), float(SrgbToLinear(c / 255.0))) << c;
  }
}

// A square of side 2 at z = 0 facing +z, textured with a 2 x 2 checker of 8 x 8 texels (so
// bilinear blending stays within half a texel of the block edges), fills a 64 x 64 image
// exactly; the environment is uniform white (radiance 1) and the material diffuse with albedo
// factor 1. A Lambertian surface under a uniform environment reflects albedo x 1, so every
// quadrant's pixels must average to its block's linear colour.
TEST(TextureRender, CheckerQuadrantsShowTheirTexelColours) {
  const uint8_t blocks[4][3] = {{255, 128, 0}, {0, 255, 64}, {64, 0, 255}, {200, 200, 200}};
  test::RgbaImage png(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const uint8_t* c = blocks[(y / 4) * 2 + x / 4];  // TL, TR, BL, BR
      png.Set(x, y, c[0], c[1], c[2], 255);
    }
  std::string dir = test::TempDir();
  test::WriteTexturedSquareGltf(dir, png, 33071, 33071);  // CLAMP_TO_EDGE both ways
  const int size = 64;
  const double distance = 4.0, fov = 2.0 * std::atan(1.0 / distance) * 180.0 / M_PI;
  std::string json = R"({"render": {"width": 64, "height": 64, "spp": 64, "max_depth": 2, "seed": 7},
      "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov_y": )" +
      std::to_string(fov) + R"(}, "background": [1, 1, 1], "materials": {},
      "objects": [{"type": "mesh", "file": "square.gltf"}]})";
  SceneDesc desc = LoadSceneFromString(json, "checker.json", dir);
  ASSERT_EQ(desc.materials.size(), 1u);
  ASSERT_GE(desc.materials[0].baseColorTexture, 0);
  desc.materials[0].type = MaterialType::kDiffuse;  // glTF maps to plastic; this test wants Lambert
  desc.materials[0].albedo = vec3(1.0f);
  Scene scene = BuildScene(std::move(desc));
  RenderResult result = test::RenderOnCpu(scene);
  const FilmImage& img = result.image;
  ASSERT_EQ(img.width, size);

  // 12 comparisons (4 quadrants x 3 channels), each at false-alarm probability 1e-4 / 12: the
  // test fails by chance with probability <= 1e-4 (Bonferroni). Windows keep 2 pixels off the
  // image edge and 5 off the centre lines (the blend zone is 2 pixels wide on each side).
  const double z = test::TwoSidedNormalQuantile(1e-4 / 12.0);
  const int lo[2] = {2, size / 2 + 5}, hi[2] = {size / 2 - 5, size - 2};
  for (int q = 0; q < 4; ++q) {
    int qx = q % 2, qy = q / 2;
    for (int c = 0; c < 3; ++c) {
      test::WindowMean w = test::MeanOverWindow(img, c, lo[qx], lo[qy], hi[qx], hi[qy]);
      double expected = Srgb8ToLinear(blocks[q][c]);
      double tolerance = z * std::sqrt(w.varianceOfMean) + 1e-6;  // + float accumulation
      EXPECT_NEAR(w.mean, expected, tolerance) << "quadrant " << q << " channel " << c;
    }
  }
}

}  // namespace
}  // namespace pt
