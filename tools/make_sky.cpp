// Writes the analytic sky (src/lights/sky.h: Preetham et al. 1999, the sun attenuated by
// Rayleigh and aerosol scattering) to an equirectangular map in the renderer's convention
// (centre column towards -Z, top row +Y), optionally with the sun's disk painted into the
// texels it covers, so that the environment-map path can be used and tested on a real
// sun-and-sky image without shipping one.
//
//   make_sky -o OUT.exr|OUT.pfm [--elevation DEG] [--azimuth DEG] [--turbidity T]
//            [--width W] [--ground-albedo A] [--strength S] [--sun on|off]
//
// Exit status: 0 written, 1 bad command line, 3 the file cannot be written.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "src/io/image_io.h"
#include "src/lights/sky.h"

namespace {

struct Options {
  std::string output;
  double elevation = 30.0, azimuth = 0.0, turbidity = 3.0, groundAlbedo = 0.3, strength = 1.0;
  int width = 1024;
  bool sun = true;
};

constexpr const char* kUsage =
    "usage: make_sky -o OUT.exr|OUT.pfm [--elevation DEG] [--azimuth DEG] [--turbidity T]\n"
    "                [--width W] [--ground-albedo A] [--strength S] [--sun on|off]\n"
    "Writes the analytic sky (Preetham et al. 1999) as an equirectangular map (W x W/2,\n"
    "centre column towards -Z, top row +Y) for --env or an environment's \"file\".\n"
    "  --elevation DEG      sun elevation above the horizon, 0..90 (default 30)\n"
    "  --azimuth DEG        sun azimuth from -Z towards +X (default 0)\n"
    "  --turbidity T        haze, 1.7..10 (default 3)\n"
    "  --width W            map width in texels, 8..16384 (default 1024)\n"
    "  --ground-albedo A    albedo of the ground below the horizon, 0..1 (default 0.3)\n"
    "  --strength S         radiance scale (default 1)\n"
    "  --sun on|off         paint the sun's disk into the map (default on)\n"
    "  -h, --help           this text\n"
    "Exit status: 0 written, 1 bad command line, 3 the file cannot be written.\n";

[[noreturn]] void Usage(const std::string& problem) {
  std::fprintf(stderr, "make_sky: %s\n%s", problem.c_str(), kUsage);
  std::exit(1);
}

double Number(const std::string& option, const char* text, double lo, double hi) {
  char* end = nullptr;
  double v = std::strtod(text, &end);
  if (*text == '\0' || *end != '\0' || !std::isfinite(v) || v < lo || v > hi)
    Usage("bad value for " + option + ": '" + text + "'");
  return v;
}

Options Parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    }
    if (i + 1 >= argc) Usage("missing value for " + a);
    const char* v = argv[++i];
    if (a == "-o") o.output = v;
    else if (a == "--elevation") o.elevation = Number(a, v, 0.0, 90.0);
    else if (a == "--azimuth") o.azimuth = Number(a, v, -1e6, 1e6);
    else if (a == "--turbidity") o.turbidity = Number(a, v, 1.7, 10.0);
    else if (a == "--width") o.width = int(Number(a, v, 8, 16384));
    else if (a == "--ground-albedo") o.groundAlbedo = Number(a, v, 0.0, 1.0);
    else if (a == "--strength") o.strength = Number(a, v, 0.0, 1e30);
    else if (a == "--sun" && (std::string(v) == "on" || std::string(v) == "off"))
      o.sun = std::string(v) == "on";
    else Usage("unknown option or value: " + a + " " + v);
  }
  if (o.output.empty()) Usage("missing -o OUT");
  if (o.width % 4 != 0) Usage("--width must be a multiple of 4");
  pt::ImageFormat format;
  if (!pt::ImageFormatFromPath(o.output, &format) || format == pt::ImageFormat::kPng)
    Usage(o.output + ": the sky is linear HDR: write .exr or .pfm");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  Options o = Parse(argc, argv);
  pt::SkyDesc sky;
  sky.sunDirection = pt::SunDirection(o.elevation, o.azimuth);
  sky.turbidity = float(o.turbidity);
  sky.groundAlbedo = pt::vec3(float(o.groundAlbedo));
  sky.width = o.width;
  uint32_t width = 0, height = 0;
  std::vector<pt::vec3> texels;
  pt::BakeSky(sky, o.sun, &width, &height, &texels);
  pt::FilmImage image;
  image.width = int(width);
  image.height = int(height);
  image.rgb.reserve(texels.size() * 3);
  for (const pt::vec3& t : texels)
    for (int c = 0; c < 3; ++c) image.rgb.push_back(float(t[c] * o.strength));
  try {
    pt::WriteImage(o.output, image);
  } catch (const pt::ImageError& e) {
    std::fprintf(stderr, "make_sky: %s\n", e.what());
    return 3;
  }
  return 0;
}
