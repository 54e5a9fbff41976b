// Compares two linear images (.exr or .pfm) of the same size: how many values are
// bit-identical, the largest absolute and relative differences, and relMSE of B against A.
// EXR files also compare their variance and sample channels when both have them. Used to
// check that a distributed render equals a one-process one (docs/distributed.md).
//
//   image_compare A B                 exit 0 when every value is bit-identical, 1 otherwise
//   image_compare A B --max-rel R     exit 0 when |a - b| <= R * max(|a|, |b|, 1e-3) everywhere
//
// Exit 2 when a file cannot be read or the sizes differ.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "src/integrator/render_api.h"
#include "src/io/image_io.h"

namespace {

struct Diff {
  size_t values = 0, identical = 0;
  double maxAbs = 0.0, maxRel = 0.0;
};

// Relative to the larger magnitude, floored at 1e-3 so that near-black values compare
// absolutely.
Diff Compare(const std::vector<float>& a, const std::vector<float>& b) {
  Diff d;
  d.values = a.size();
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(&a[i], &b[i], sizeof(float)) == 0) {
      ++d.identical;
      continue;
    }
    double diff = std::fabs(double(a[i]) - double(b[i]));
    double scale = std::max({std::fabs(double(a[i])), std::fabs(double(b[i])), 1e-3});
    d.maxAbs = std::max(d.maxAbs, diff);
    d.maxRel = std::max(d.maxRel, std::isfinite(diff) ? diff / scale : INFINITY);
  }
  return d;
}

bool Report(const char* name, const Diff& d, double maxRel) {
  std::printf("%-10s %zu of %zu values bit-identical; max |a-b| %.3g; max relative %.3g\n",
              name, d.identical, d.values, d.maxAbs, d.maxRel);
  return maxRel < 0.0 ? d.identical == d.values : d.maxRel <= maxRel;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && !(argc == 5 && std::strcmp(argv[3], "--max-rel") == 0)) {
    std::fprintf(stderr, "usage: image_compare A B [--max-rel R]\n");
    return 2;
  }
  double maxRel = argc == 5 ? std::atof(argv[4]) : -1.0;
  std::string pathA = argv[1], pathB = argv[2];
  int wa = 0, ha = 0, wb = 0, hb = 0;
  std::vector<float> a, b;
  try {
    pt::ReadImageRgb(pathA, &wa, &ha, &a);
    pt::ReadImageRgb(pathB, &wb, &hb, &b);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "image_compare: %s\n", e.what());
    return 2;
  }
  if (wa != wb || ha != hb) {
    std::fprintf(stderr, "image_compare: %dx%d against %dx%d\n", wa, ha, wb, hb);
    return 2;
  }
  bool ok = Report("rgb", Compare(a, b), maxRel);
  std::printf("%-10s %.3g\n", "relMSE", pt::RelMse(b, a));
  if (pt::IsExrPath(pathA) && pt::IsExrPath(pathB)) {
    for (const char* channel : {"variance.R", "variance.G", "variance.B", "samples", "albedo.R",
                                "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z", "Z"}) {
      try {
        int w = 0, h = 0;
        ok = Report(channel, Compare(pt::ReadExrChannel(pathA, channel, &w, &h),
                                     pt::ReadExrChannel(pathB, channel, &w, &h)),
                    maxRel) && ok;
      } catch (const std::exception&) {
        // a channel one of the files lacks is not compared
      }
    }
  }
  std::printf("%s\n", ok ? (maxRel < 0.0 ? "identical" : "within tolerance")
                         : (maxRel < 0.0 ? "different" : "outside tolerance"));
  return ok ? 0 : 1;
}
