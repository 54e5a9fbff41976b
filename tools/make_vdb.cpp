// Writes a procedural density grid (src/media/procedural_volume.h) as an OpenVDB file, so
// that grid media can be rendered, tested and compared with other renderers (Blender Cycles
// reads the same file) without downloading any: a cumulus-like noise cloud or a sphere of
// smoke, fitting the cube [-0.5, 0.5]^3 (scaled by --size).
//
//   make_vdb cloud|smoke -o OUT.vdb [--resolution N] [--seed S] [--size L] [--grid NAME]
//
// Exit status: 0 written, 1 bad command line, 3 the file cannot be written (or this build has
// no OpenVDB).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "src/io/vdb_io.h"
#include "src/media/procedural_volume.h"

namespace {

struct Options {
  std::string shape, output, grid = "density";
  int resolution = 128;
  unsigned seed = 1;
  double size = 1.0;
};

[[noreturn]] void Usage(const std::string& problem) {
  std::fprintf(stderr,
               "make_vdb: %s\nusage: make_vdb cloud|smoke -o OUT.vdb [--resolution N] "
               "[--seed S] [--size L] [--grid NAME]\n",
               problem.c_str());
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
    if (a == "cloud" || a == "smoke") {
      o.shape = a;
      continue;
    }
    if (i + 1 >= argc) Usage("unknown argument or missing value: " + a);
    const char* v = argv[++i];
    if (a == "-o") o.output = v;
    else if (a == "--resolution") o.resolution = int(Number(a, v, 8, 1024));
    else if (a == "--seed") o.seed = unsigned(Number(a, v, 0, 4294967295.0));
    else if (a == "--size") o.size = Number(a, v, 1e-6, 1e6);
    else if (a == "--grid") o.grid = v;
    else Usage("unknown option " + a);
  }
  if (o.shape.empty()) Usage("name a shape: cloud or smoke");
  if (o.output.empty()) Usage("no output file (-o OUT.vdb)");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  Options o = Parse(argc, argv);
  pt::SparseGrid grid = o.shape == "cloud" ? pt::MakeNoiseCloud(o.resolution, o.seed)
                                           : pt::MakeSmokeSphere(o.resolution, o.seed);
  grid.indexToWorld = glm::dmat4(o.size) * grid.indexToWorld;
  grid.indexToWorld[3][3] = 1.0;
  try {
    pt::WriteVdbGrid(o.output, o.grid, grid);
  } catch (const pt::VdbError& e) {
    std::fprintf(stderr, "make_vdb: %s\n", e.what());
    return 3;
  }
  std::printf("make_vdb: wrote %s (%s, %d^3 voxels, %zu bricks)\n", o.output.c_str(),
              o.shape.c_str(), o.resolution, grid.bricks.size());
  return 0;
}
