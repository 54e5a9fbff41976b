// Each glTF material extension, loaded from a generated file and rendered on the CPU, changes
// the image as its BSDF says, and the image without the extension differs (so a test fails
// when the extension is ignored). Under a uniform white background with max_depth 1 a pixel's
// expectation is the BSDF's directional albedo for the view; under a delta directional light it
// is f cos exactly. Also: the loader's parameters, unlit, variants, energy compensation, and
// the effects and variant the scene runs. False-alarm probability 1e-4 per statistical check.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>

#include "src/scene/effects.h"
#include "tests/albedo_quadrature.h"
#include "tests/cli_test_util.h"
#include "tests/gltf_extensions_scenes.h"
#include "tests/layered_check_util.h"
#include "tests/render_test_util.h"

namespace pt::test {
namespace {

SceneSpec ExtSmall() {
  SceneSpec s;
  s.size = 8;
  s.spp = 64;
  s.maxDepth = 1;
  return s;
}

// The loaded scene's material as the layered BSDF sees it at the square's centre (factors only:
// these scenes have no textures; the square's shading frame is the world's).
LayeredMaterial MaterialOf(const Scene& scene) {
  const SceneDesc& d = scene.desc;
  LayeredMaterial m = MakeLayered(d.materials.at(d.triangleMaterials.at(0)));
  if (m.flags & kMaterialUnlit) m.radiance = m.albedo;
  if (m.ext < 0) return m;
  const GltfMaterialExtension& e = d.materialExtensions.at(size_t(m.ext));
  GltfLayers& x = m.layers;
  x.mask = e.mask;
  x.specular = e.specular;
  x.specularColor = e.specularColor;
  x.clearcoat = e.clearcoat;
  x.clearcoatRoughness = e.clearcoatRoughness;
  x.sheenColor = e.sheenColor;
  x.sheenRoughness = e.sheenRoughness;
  x.iridescence = e.iridescence;
  x.iridescenceIor = e.iridescenceIor;
  x.thickness = e.thicknessMax;
  x.anisotropy = e.anisotropy;
  x.anisotropyDir = vec3(std::cos(e.anisotropyRotation), std::sin(e.anisotropyRotation), 0.0f);
  x.diffuseTransmission = e.diffuseTransmission;
  x.diffuseTransmissionColor = e.diffuseTransmissionColor;
  return m;
}

// The image's mean per channel and its standard error.
struct ImageMean {
  vec3 mean;
  vec3 sigma;
};
ImageMean MeanOf(const FilmImage& img) {
  ImageMean r;
  for (int c = 0; c < 3; ++c) {
    test::WindowMean w = test::MeanOverImage(img, c);
    r.mean[c] = float(w.mean);
    r.sigma[c] = float(std::sqrt(w.varianceOfMean));
  }
  return r;
}

// Renders the scene with and without the extension; the first must match the BSDF's albedo
// for the view (mu), and differ from the second by more than `minChange` in some channel.
void ExpectAlbedoRender(const std::string& what, ExtensionSceneSpec with, ExtensionSceneSpec without,
                        float mu, float minChange) {
  std::string dir = TempDir();
  Scene scene = test::ExtensionScene(dir, with, ExtSmall());
  ImageMean img = MeanOf(RenderOnCpu(scene).image);
  ImageMean control = MeanOf(RenderOnCpu(test::ExtensionScene(dir, without, ExtSmall())).image);
  LayeredMaterial m = MaterialOf(scene);
  float change = 0.0f;
  std::array<test::MeanEstimate, 3> albedo = test::LayeredAlbedoRgb(m, test::View(mu), 77, 200000);
  for (int c = 0; c < 3; ++c) {
    const test::MeanEstimate& expect = albedo[c];
    double tol = test::kZ1e4 * std::sqrt(Sqr(double(img.sigma[c])) + Sqr(expect.stdError));
    EXPECT_NEAR(img.mean[c], expect.mean, tol) << what << " channel " << c;
    change = std::max(change, fabsf(img.mean[c] - control.mean[c]));
  }
  EXPECT_GT(change, minChange) << what << ": the extension changes the image too little";
}

ExtensionSceneSpec ExtSpec(const std::string& name, const std::string& material, double theta = 0.0) {
  ExtensionSceneSpec s;
  s.name = name;
  s.material = material;
  s.camera = test::ObliqueCamera(theta);
  return s;
}

TEST(GltfExtensionsRender, ClearcoatAddsItsReflection) {
  ExpectAlbedoRender("clearcoat", ExtSpec("cc1", test::ClearcoatMaterial(true), 60.0),
                     ExtSpec("cc0", test::ClearcoatMaterial(false), 60.0), 0.5f, 0.03f);
}

TEST(GltfExtensionsRender, SpecularColourRaisesF0) {
  ExpectAlbedoRender("specular", ExtSpec("sp1", test::SpecularMaterial(true)),
                     ExtSpec("sp0", test::SpecularMaterial(false)), 1.0f, 0.05f);
}

TEST(GltfExtensionsRender, SheenReflectsAtGrazingViews) {
  ExpectAlbedoRender("sheen", ExtSpec("sh1", test::SheenMaterial(true), 70.0),
                     ExtSpec("sh0", test::SheenMaterial(false), 70.0), std::cos(70.0f * kPi / 180.0f),
                     0.05f);
}

TEST(GltfExtensionsRender, IridescenceColoursTheReflection) {
  ExpectAlbedoRender("iridescence", ExtSpec("ir1", test::IridescenceMaterial(true)),
                     ExtSpec("ir0", test::IridescenceMaterial(false)), 1.0f, 0.02f);
}

TEST(GltfExtensionsRender, EnergyCompensationBrightensRoughMetal) {
  ExtensionSceneSpec on = ExtSpec("ec1", test::RoughWhiteMetal()), off = ExtSpec("ec0", test::RoughWhiteMetal());
  on.energyCompensation = true;
  ExpectAlbedoRender("energy compensation", on, off, 1.0f, 0.2f);
}

// Under a delta light a pixel is f cos for the light's direction: the anisotropic lobe's,
// stretched along the tangent (x) towards the light, and not when rotated across it.
TEST(GltfExtensionsRender, AnisotropyStretchesTheHighlightAlongItsDirection) {
  std::string dir = TempDir();
  vec3 travel = test::OffNormalLightDirection();
  auto render = [&](const std::string& name, const std::string& material) {
    ExtensionSceneSpec s = ExtSpec(name, material);
    s.extra = test::DirectionalLight(travel);
    Scene scene = test::ExtensionScene(dir, s, ExtSmall());
    return std::make_pair(MeanOf(RenderOnCpu(scene).image), MaterialOf(scene));
  };
  auto [along, m] = render("an1", test::AnisotropyMaterial(true));
  auto [across, unused] = render("an2", test::AnisotropyMaterial(true, 1.5707963f));
  auto [plain, unused2] = render("an0", test::AnisotropyMaterial(false));
  vec3 wi = -travel;
  vec3 expect = EvalLayeredBsdf(m, vec3(0, 0, 1), wi) * wi.z;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(along.mean[c], expect[c], 2e-3f * expect[c] + 1e-5f);
  EXPECT_GT(along.mean.x, 3.0f * plain.mean.x);
  EXPECT_GT(along.mean.x, 3.0f * across.mean.x);
}

// Light from behind reaches the front only through the diffuse transmission, tinted.
TEST(GltfExtensionsRender, DiffuseTransmissionLetsLightThrough) {
  std::string dir = TempDir();
  auto render = [&](const std::string& name, bool with) {
    ExtensionSceneSpec s = ExtSpec(name, test::DiffuseTransmissionMaterial(with));
    s.extra = test::DirectionalLight(vec3(0, 0, 1));
    Scene scene = test::ExtensionScene(dir, s, ExtSmall());
    return std::make_pair(MeanOf(RenderOnCpu(scene).image), MaterialOf(scene));
  };
  auto [through, m] = render("dt1", true);
  auto [opaque, unused] = render("dt0", false);
  vec3 expect = EvalLayeredBsdf(m, vec3(0, 0, 1), vec3(0, 0, -1));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(through.mean[c], expect[c], 2e-3f * expect[c] + 1e-5f);
  EXPECT_GT(through.mean.x, 0.05f);
  EXPECT_EQ(opaque.mean, vec3(0.0f));
}

// Unlit: the base colour, with no light at all; the lit control is black.
TEST(GltfExtensionsRender, UnlitShowsItsBaseColour) {
  std::string dir = TempDir();
  ExtensionSceneSpec with = ExtSpec("ul1", test::UnlitMaterial(true)), without = ExtSpec("ul0", test::UnlitMaterial(false));
  with.extra = without.extra = "";
  ImageMean img = MeanOf(RenderOnCpu(test::ExtensionScene(dir, with, ExtSmall())).image);
  ImageMean dark = MeanOf(RenderOnCpu(test::ExtensionScene(dir, without, ExtSmall())).image);
  vec3 base(0.2f, 0.6f, 0.9f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(img.mean[c], base[c], 1e-5f);
  EXPECT_EQ(dark.mean, vec3(0.0f));
}

// ---- Variants ----

// A square with material 0 (red) by default; variant "green" maps it to material 1.
std::string VariantFile(const std::string& dir) {
  test::GltfWriter w("variants");
  w.AddMaterial(R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1], "metallicFactor": 0},
                    "extensions": {"KHR_materials_unlit": {}}})");
  w.AddMaterial(R"({"pbrMetallicRoughness": {"baseColorFactor": [0, 1, 0, 1], "metallicFactor": 0},
                    "extensions": {"KHR_materials_unlit": {}}})");
  w.AddPrimitive(test::Square());
  std::string file = w.Write(dir);
  nlohmann::json doc;
  std::ifstream(dir + "/" + file) >> doc;
  doc["extensionsUsed"] = {"KHR_materials_variants", "KHR_materials_unlit"};
  doc["extensions"]["KHR_materials_variants"]["variants"] = {{{"name", "red"}}, {{"name", "green"}}};
  doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"] = {
      {{"material", 1}, {"variants", {1}}}, {{"material", 0}, {"variants", {0}}}};
  std::ofstream(dir + "/" + file) << doc.dump(1);
  return file;
}

TEST(GltfExtensionsRender, VariantSelectsTheMappedMaterial) {
  std::string dir = TempDir();
  std::string file = VariantFile(dir);
  for (const char* variant : {"", "red", "green"}) {
    LoadOptions o;
    o.variant = variant;
    SceneDesc d = LoadScene(dir + "/" + file, o);
    vec3 base = d.materials.at(d.triangleMaterials.at(0)).albedo;
    EXPECT_EQ(base, std::string(variant) == "green" ? vec3(0, 1, 0) : vec3(1, 0, 0)) << variant;
  }
  std::string json = R"({"render": {"width": 4, "height": 4, "spp": 1, "max_depth": 1},
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 40}, "materials": {},
      "objects": [{"type": "mesh", "file": ")" + file + R"(", "variant": "green"}]})";
  SceneDesc d = LoadSceneFromString(json, "v.json", dir);  // the JSON scene's "variant" field
  EXPECT_EQ(d.materials.at(d.triangleMaterials.at(0)).albedo, vec3(0, 1, 0));
}

TEST(GltfExtensionsRender, UnknownVariantNamesTheFileFieldAndVariants) {
  std::string dir = TempDir();
  std::string file = VariantFile(dir);
  LoadOptions o;
  o.variant = "blue";
  try {
    LoadScene(dir + "/" + file, o);
    ADD_FAILURE() << "an unknown variant loaded";
  } catch (const SceneError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find(file), std::string::npos) << m;
    EXPECT_NE(m.find("--variant"), std::string::npos) << m;
    EXPECT_NE(m.find("\"red\", \"green\""), std::string::npos) << m;
  }
  std::string json = R"({"render": {"width": 4, "height": 4, "spp": 1, "max_depth": 1},
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 40}, "materials": {},
      "objects": [{"type": "mesh", "file": ")" + file + R"(", "variant": "blue"}]})";
  try {
    LoadSceneFromString(json, "v.json", dir);
    ADD_FAILURE() << "an unknown variant loaded";
  } catch (const SceneError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("objects[0].variant"), std::string::npos) << m;
    EXPECT_NE(m.find("\"red\", \"green\""), std::string::npos) << m;
  }
}

// The command line: an unknown --variant is exit 2 naming the file, the field and the
// variants, with nothing written; a known one renders; --energy-compensation takes off|on.
TEST(GltfExtensionsRender, CommandLineVariantAndEnergyCompensation) {
  std::string dir = TempDir();
  std::string file = dir + "/" + VariantFile(dir);
  ExpectRefusedWritingNothing(file, "--variant blue", dir);
  std::string output;
  RunPathtracer("'" + file + "' --variant blue --backend cpu -o " + dir + "/v.png", &output);
  EXPECT_NE(output.find("--variant"), std::string::npos) << output;
  EXPECT_NE(output.find("\"red\", \"green\""), std::string::npos) << output;
  EXPECT_EQ(RunPathtracer("'" + file + "' --variant green --energy-compensation on --width 8 "
                          "--height 8 --spp 1 --backend cpu --quiet -o " + dir + "/v.png", &output),
            0) << output;
  EXPECT_NE(RunPathtracer("'" + file + "' --energy-compensation maybe -o " + dir + "/v.png", &output), 0);
}

// ---- Effects and the variant that runs ----

TEST(GltfExtensionsRender, ExtensionsNameTheirEffectsAndRunTheLayeredVariant) {
  std::string dir = TempDir();
  struct Case {
    std::string material;
    uint32_t effect;
  } cases[] = {{test::ClearcoatMaterial(true), kEffectClearcoat},
               {test::SpecularMaterial(true), kEffectSpecular},
               {test::SheenMaterial(true), kEffectSheen},
               {test::IridescenceMaterial(true), kEffectIridescence},
               {test::AnisotropyMaterial(true), kEffectAnisotropy},
               {test::DiffuseTransmissionMaterial(true), kEffectDiffuseTransmission},
               {test::UnlitMaterial(true), kEffectUnlit}};
  int k = 0;
  for (const Case& c : cases) {
    Scene s = test::ExtensionScene(dir, ExtSpec("fx" + std::to_string(k++), c.material), ExtSmall());
    uint32_t e = AnalyzeEffects(s);
    EXPECT_TRUE(e & c.effect) << c.material;
    EXPECT_EQ(ChooseFeatureClass(e), FeatureClass::kLayered) << c.material;
  }
  Scene plain = test::ExtensionScene(dir, ExtSpec("fxp", test::ClearcoatMaterial(false)), ExtSmall());
  EXPECT_EQ(AnalyzeEffects(plain) & kLayeredEffects, 0u);
  EXPECT_EQ(ChooseFeatureClass(AnalyzeEffects(plain)), FeatureClass::kGeneral);
}

// A plain glTF material shades bit for bit the same in the layered kernels (a scene that also
// holds an extension material, out of every ray's way behind the square) as in the general ones.
TEST(GltfExtensionsRender, LayeredVariantShadesPlainMaterialsIdentically) {
  std::string dir = TempDir();
  test::GltfWriter plain("plain"), coated("coated");
  plain.AddMaterial(test::AnisotropyMaterial(false));
  plain.AddPrimitive(test::Square());
  coated.AddMaterial(test::ClearcoatMaterial(true));
  coated.AddPrimitive(test::Square(1.0f, -100.0f));
  std::string a = plain.Write(dir), b = coated.Write(dir);
  auto scene = [&](bool both) {
    std::string objects = R"({"type": "mesh", "file": ")" + a + "\"}";
    if (both) objects += R"(, {"type": "mesh", "file": ")" + b + "\"}";
    std::string json = R"({"render": {"width": 8, "height": 8, "spp": 16, "max_depth": 1},
        "camera": )" + test::ObliqueCamera(30.0) + R"(, "materials": {}, "background": [1, 1, 1],
        "objects": [)" + objects + "]}";
    return BuildScene(LoadSceneFromString(json, "same.json", dir));
  };
  Scene general = scene(false), layered = scene(true);
  ASSERT_EQ(ChooseFeatureClass(AnalyzeEffects(general)), FeatureClass::kGeneral);
  ASSERT_EQ(ChooseFeatureClass(AnalyzeEffects(layered)), FeatureClass::kLayered);
  EXPECT_TRUE(test::SameImage(RenderOnCpu(general).image, RenderOnCpu(layered).image));
}

}  // namespace
}  // namespace pt::test
