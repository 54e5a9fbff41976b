// Bad media input: each rule names the file and the field, and the app exits 2 writing nothing.
// (OpenVDB files without the named grid or with a non-float grid: media_vdb_test.cpp.)
#include <gtest/gtest.h>

#include <filesystem>

#include "src/io/scene_loader.h"
#include "tests/cli_test_util.h"

namespace pt {
namespace {

std::string MediaScene(const std::string& media, const std::string& objects,
                       const std::string& extra = "") {
  return R"({"render": {"width": 4, "height": 4, "spp": 1, "max_depth": 2},
    "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov_y": 45},
    "materials": {"white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "media": {)" + media + R"(},
    "objects": [)" + objects + "]" + extra + "}";
}

const char* kFog = R"("fog": {"type": "homogeneous", "sigma_a": [0, 0, 0], "sigma_s": [1, 1, 1]})";
const char* kFogBox =
    R"({"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1], "material": "interface", "interior": "fog"})";

std::string MediaErrorOf(const std::string& text, const std::string& baseDir = ".") {
  try {
    LoadSceneFromString(text, "scenes/media.json", baseDir);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

void ExpectMediaError(const std::string& text, const std::string& field,
                      const std::string& detail, const std::string& baseDir = ".") {
  std::string message = MediaErrorOf(text, baseDir);
  EXPECT_EQ(message.rfind("scenes/media.json: ", 0), 0u) << message;
  EXPECT_NE(message.find(field), std::string::npos) << "field '" << field << "' in: " << message;
  EXPECT_NE(message.find(detail), std::string::npos) << "'" << detail << "' in: " << message;
}

TEST(MediaErrors, ValidMediaSceneLoads) {
  EXPECT_EQ(MediaErrorOf(MediaScene(kFog, kFogBox, R"(, "medium": "vacuum")")), "(no error)");
}

TEST(MediaErrors, Coefficients) {
  ExpectMediaError(MediaScene(R"("fog": {"type": "homogeneous", "sigma_a": [-1, 0, 0],
                                "sigma_s": [1, 1, 1]})", kFogBox),
                   "media.fog.sigma_a[0]", "must be >= 0");
  ExpectMediaError(MediaScene(R"("fog": {"type": "homogeneous", "sigma_a": [0, 0, 0],
                                "sigma_s": [1, NaN, 1]})", kFogBox),
                   "media.fog.sigma_s[1]", "not a finite number");
  ExpectMediaError(MediaScene(R"("fog": {"type": "homogeneous", "sigma_a": [0, 0, 0]})", kFogBox),
                   "media.fog.sigma_s", "missing required field");
  ExpectMediaError(MediaScene(R"("fog": {"type": "homogeneous", "sigma_a": [0, 0, 0],
                                "sigma_s": [1, 1, 1], "scale": -2})", kFogBox),
                   "media.fog.scale", "must be >= 0");
  ExpectMediaError(MediaScene(R"("fog": {"type": "homogeneous", "sigma_a": [0, 0, 0],
                                "sigma_s": [1e30, 1, 1], "scale": 1e30})", kFogBox),
                   "media.fog.scale", "too large");
}

TEST(MediaErrors, AsymmetryOutsideMinusOneToOne) {
  for (const char* g : {"1", "-1", "1.5"})
    ExpectMediaError(MediaScene(std::string(R"("fog": {"type": "homogeneous", "sigma_a": [0, 0, 0],
                                   "sigma_s": [1, 1, 1], "g": )") + g + "}", kFogBox),
                     "media.fog.g", "is outside (-1, 1)");
}

TEST(MediaErrors, TypesNamesAndReferences) {
  ExpectMediaError(MediaScene(R"("fog": {"type": "smoke", "sigma_a": [0, 0, 0], "sigma_s": [1, 1, 1]})",
                              kFogBox),
                   "media.fog.type", "unknown medium type");
  ExpectMediaError(MediaScene(kFog, kFogBox, R"(, "medium": "mist")"), "medium",
                   "undefined medium \"mist\" (the top-level \"media\" defines: fog)");
  ExpectMediaError(MediaScene(std::string(kFog) + R"(, "vacuum": {"type": "homogeneous",
                                "sigma_a": [0, 0, 0], "sigma_s": [1, 1, 1]})", kFogBox),
                   "media.vacuum", "reserved");
  ExpectMediaError(R"({"render": {"width": 4, "height": 4, "spp": 1, "max_depth": 2},
    "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov_y": 45},
    "materials": {"interface": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
    "objects": []})", "materials.interface", "reserved");
}

TEST(MediaErrors, InteriorsAndInterfaces) {
  ExpectMediaError(MediaScene(kFog, R"({"type": "sphere", "center": [0, 0, 0], "radius": 1,
                                       "material": "interface"})"),
                   "objects[0].material", "give the object an \"interior\"");
  ExpectMediaError(MediaScene(kFog, R"({"type": "sphere", "center": [0, 0, 0], "radius": 1,
                                       "material": "white", "exterior": "fog"})"),
                   "objects[0].exterior", "needs an \"interior\"");
  ExpectMediaError(MediaScene(kFog, R"({"type": "quad", "origin": [0, 0, 0], "u": [1, 0, 0],
                                       "v": [0, 1, 0], "material": "interface", "interior": "fog"})"),
                   "objects[0].interior", "a quad encloses no volume");
  ExpectMediaError(MediaScene(kFog, R"({"type": "quad", "origin": [0, 0, 0], "u": [1, 0, 0],
                                       "v": [0, 1, 0], "material": "interface"})"),
                   "objects[0].material", "a quad encloses no volume");
  ExpectMediaError(MediaScene(kFog, R"({"type": "volume", "medium": "fog"})"),
                   "objects[0].medium", "a volume object bounds a grid medium");
  ExpectMediaError(MediaScene(kFog, R"({"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1],
                                       "material": "interface", "interior": "smog"})"),
                   "objects[0].interior", "undefined medium \"smog\"");
}

TEST(MediaErrors, GridSources) {
  ExpectMediaError(MediaScene(R"("c": {"type": "grid", "sigma_a": [0, 0, 0], "sigma_s": [1, 1, 1]})",
                              "[]"),
                   "media.c", "either \"file\" (a .vdb) or \"procedural\", not neither");
  ExpectMediaError(MediaScene(R"("c": {"type": "grid", "file": "a.vdb", "procedural": {"shape": "cloud"},
                                "sigma_a": [0, 0, 0], "sigma_s": [1, 1, 1]})", "[]"),
                   "media.c", "not both");
  ExpectMediaError(MediaScene(R"("c": {"type": "grid", "file": "no_such.vdb",
                                "sigma_a": [0, 0, 0], "sigma_s": [1, 1, 1]})", "[]"),
                   "media.c.file", "no_such.vdb\": no such file");
  ExpectMediaError(MediaScene(R"("c": {"type": "grid", "procedural": {"shape": "cloud"},
                                "emission": [1, 1, 1], "emission_grid": "temperature",
                                "sigma_a": [1, 1, 1], "sigma_s": [1, 1, 1]})", "[]"),
                   "media.c.emission_grid", "this medium is procedural");
  ExpectMediaError(MediaScene(R"("c": {"type": "homogeneous", "emission": [1, -1, 1],
                                "sigma_a": [1, 1, 1], "sigma_s": [1, 1, 1]})", "[]"),
                   "media.c.emission[1]", "must be >= 0");
  ExpectMediaError(MediaScene(R"("c": {"type": "grid", "procedural": {"shape": "torus"},
                                "sigma_a": [0, 0, 0], "sigma_s": [1, 1, 1]})", "[]"),
                   "media.c.procedural.shape", "unknown procedural grid");
}

// An open mesh cannot bound a medium; a closed one can, either winding.
TEST(MediaErrors, InteriorOnAnOpenMesh) {
  std::string dir = test::TempDir();
  test::WriteText(dir + "/open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n");
  test::WriteText(dir + "/closed.obj",
                  "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  std::string open = MediaScene(kFog, R"({"type": "mesh", "file": "open.obj",
                                         "material": "interface", "interior": "fog"})");
  ExpectMediaError(open, "objects[0].interior", "the mesh is not closed (3 edges", dir);
  EXPECT_EQ(MediaErrorOf(MediaScene(kFog, R"({"type": "mesh", "file": "closed.obj",
                                             "material": "interface", "interior": "fog"})"),
                         dir),
            "(no error)");
  // The app: exit status 2, the file and field named, nothing written.
  std::string scene = test::WriteText(dir + "/open_interior.json", open);
  test::ExpectRefusedWritingNothing(scene, "", dir);
  for (const char* f : {"/open.obj", "/closed.obj", "/open_interior.json"})
    std::filesystem::remove(dir + f);
}

TEST(MediaErrors, BadFogAndTransmittanceOptions) {
  std::string out;
  EXPECT_EQ(test::RunPathtracer("--fog -1 x.json", &out), 1) << out;
  EXPECT_NE(out.find("--fog must be greater than 0"), std::string::npos) << out;
  EXPECT_EQ(test::RunPathtracer("--transmittance exact x.json", &out), 1) << out;
  EXPECT_NE(out.find("--transmittance"), std::string::npos) << out;
}

}  // namespace
}  // namespace pt
