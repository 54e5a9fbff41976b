#include "src/io/environment_loader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "src/io/image_io.h"
#include "src/io/scene_json.h"
#include "src/io/scene_loader.h"
#include "src/lights/sky.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

constexpr int64_t kMaxMapHeight = 1 << 15;

// Every texel finite and non-negative; otherwise what is wrong with the first bad one.
std::string CheckTexels(const EnvironmentDesc& env) {
  static const char* kChannel = "RGB";
  for (size_t k = 0; k < env.texels.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      float v = env.texels[k][c];
      if (std::isfinite(v) && v >= 0.0f) continue;
      std::string where = "texel (" + std::to_string(k % env.width) + ", " +
                          std::to_string(k / env.width) + ") channel " + kChannel[c];
      return where + (std::isfinite(v) ? " is negative (" + FormatNumber(v) + ")"
                                       : " is not finite (NaN or infinity)");
    }
  }
  return "";
}

void ParseSky(const JsonObject& sky, EnvironmentDesc& env) {
  sky.AllowOnly({"sun_elevation", "sun_azimuth", "turbidity", "ground_albedo", "sun", "width"},
                "environment.sky");
  SkyDesc& s = env.sky;
  float elevation = sky.Number("sun_elevation", Range::Closed(0.0, 90.0));
  float azimuth = sky.NumberOr("sun_azimuth", 0.0f);
  s.sunDirection = SunDirection(elevation, azimuth);
  s.turbidity = sky.NumberOr("turbidity", 3.0f, Range::Closed(1.7, 10.0));
  s.groundAlbedo = sky.Vec3Or("ground_albedo", vec3(0.3f), Range::Unit());
  s.sun = sky.BoolOr("sun", true);
  s.width = int(sky.IntegerOr("width", 1024, 8, 16384));
  if (s.width % 4 != 0) sky.Fail("width", std::to_string(s.width) + " is not a multiple of 4");
  env.isSky = true;
  BakeSky(s, false, &env.width, &env.height, &env.texels);
}

}  // namespace

void LoadEnvironmentMap(const std::string& path, const std::string& file,
                        const std::string& field, EnvironmentDesc* env) {
  auto fail = [&](const std::string& what) { FailAt(file, field, "\"" + path + "\": " + what); };
  std::string ext = LowerExtension(path);
  if (ext != ".exr" && ext != ".hdr" && ext != ".pfm")
    fail("unsupported environment map format \"" + ext + "\" (expected .exr, .hdr or .pfm)");
  std::error_code ec;
  if (fs::is_directory(path, ec)) fail("is a folder, not an image");
  if (!fs::is_regular_file(path, ec)) fail("cannot open: no such file");
  int width = 0, height = 0;
  std::vector<float> rgb;
  try {
    if (ext == ".exr") ReadExrRgb(path, &width, &height, &rgb);
    else if (ext == ".hdr") ReadHdrRgb(path, &width, &height, &rgb);
    else ReadPfmRgb(path, &width, &height, &rgb);
  } catch (const ImageError& e) {
    FailAt(file, field, e.what());
  }
  std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (width != 2 * height || height < 1)
    fail("is " + size + ": an equirectangular map must be twice as wide as it is high (2:1)");
  if (height > kMaxMapHeight) fail("is " + size + ": larger than this renderer reads");
  env->width = uint32_t(width);
  env->height = uint32_t(height);
  env->texels.resize(size_t(width) * height);
  for (size_t k = 0; k < env->texels.size(); ++k)
    env->texels[k] = vec3(rgb[3 * k], rgb[3 * k + 1], rgb[3 * k + 2]);
  std::string bad = CheckTexels(*env);
  if (!bad.empty()) fail(bad);
  env->file = path;
  env->field = field;
  env->isSky = false;
}

void ParseEnvironment(const JsonObject& e, const std::string& baseDir, SceneDesc& scene) {
  e.AllowOnly({"file", "sky", "radiance", "strength", "rotate", "visible_to_camera",
               "camera_color"},
              "the environment");
  int sources = int(e.Has("file")) + int(e.Has("sky")) + int(e.Has("radiance"));
  if (sources != 1)
    e.FailHere("needs exactly one of \"file\" (an image), \"sky\" or \"radiance\" (a constant)");
  EnvironmentDesc& env = scene.environment;
  env.strength = e.NumberOr("strength", 1.0f, Range::NonNegative());
  env.rotateDegrees = e.Vec3Or("rotate", vec3(0.0f));
  env.visibleToCamera = e.BoolOr("visible_to_camera", true);
  env.cameraColor = e.Vec3Or("camera_color", vec3(0.0f), Range::NonNegative());
  if (e.Has("radiance")) {
    scene.background = e.Vec3("radiance", Range::NonNegative());
  } else if (e.Has("sky")) {
    ParseSky(e.Object("sky"), env);
    if (env.sky.sun) scene.directionalLights.push_back(SkySun(env.sky));
  } else {
    std::string file = e.String("file");
    fs::path resolved = fs::path(file).is_absolute() ? fs::path(file) : fs::path(baseDir) / file;
    LoadEnvironmentMap(resolved.string(), e.File(), e.FieldPath("file"), &env);
  }
}

DirectionalLightDesc ParseDirectionalLight(const JsonObject& l) {
  l.AllowOnly({"type", "direction", "irradiance", "radiance", "angular_radius"},
              "a directional light");
  DirectionalLightDesc d;
  vec3 travel = l.Vec3("direction");
  if (!(glm::length(glm::dvec3(travel)) > 0.0)) l.Fail("direction", "must not be the zero vector");
  d.direction = -glm::normalize(travel);  // stored towards the light
  float degrees = l.NumberOr("angular_radius", 0.0f, Range{0.0, 90.0, false, true});
  d.angularRadius = float(double(degrees) * M_PI / 180.0);
  if (l.Has("irradiance") == l.Has("radiance"))
    l.FailHere("needs exactly one of \"irradiance\" and \"radiance\"");
  if (l.Has("irradiance")) {
    d.irradiance = l.Vec3("irradiance", Range::NonNegative());
  } else {
    if (!(d.angularRadius > 0.0f))
      l.Fail("radiance", "needs an angular_radius > 0 (a delta light has an irradiance)");
    double sinR = std::sin(double(d.angularRadius));
    d.irradiance = l.Vec3("radiance", Range::NonNegative()) * float(M_PI * sinR * sinR);
  }
  return d;
}

void ReplaceEnvironmentMap(const std::string& path, SceneDesc* scene) {
  LoadEnvironmentMap(path, "--env", "", &scene->environment);
  scene->background = vec3(0.0f);
  auto& lights = scene->directionalLights;
  lights.erase(std::remove_if(lights.begin(), lights.end(),
                              [](const DirectionalLightDesc& d) { return d.partOfEnvironment; }),
               lights.end());
}

void RemoveEnvironment(SceneDesc* scene) {
  scene->environment = EnvironmentDesc{};
  scene->background = vec3(0.0f);
  auto& lights = scene->directionalLights;
  lights.erase(std::remove_if(lights.begin(), lights.end(),
                              [](const DirectionalLightDesc& d) { return d.partOfEnvironment; }),
               lights.end());
}

std::string DarkEnvironmentWarning(const SceneDesc& scene) {
  const EnvironmentDesc& env = scene.environment;
  if (!env.HasMap()) return "";
  bool black = env.strength == 0.0f ||
               std::all_of(env.texels.begin(), env.texels.end(), [](vec3 t) { return IsBlack(t); });
  if (!black) return "";
  std::string what = env.isSky ? "the sky" : "the environment map \"" + env.file + "\"";
  return what + " emits no light (" +
         (env.strength == 0.0f ? "strength 0" : "every texel is black") +
         "): the environment is dark";
}

}  // namespace pt
