// Writes src/materials/ggx_albedo_table.h: the directional albedo of a GGX reflection lobe with
// Schlick's Fresnel, which the glTF material's diffuse base is scaled by (src/materials/
// gltf_pbr.h). Schlick's F = F0 + (1 - F0) (1 - cos)^5 is linear in F0, so two tables over
// (mu = cos theta_o, roughness) give every F0: E1 (F = 1) and E5 (F = (1 - wo.wm)^5).
//
// Each entry is an upper bound of the albedo over the table cells around its node (the maximum
// of a 4 x 4 sub-grid of every adjacent cell, plus the quadrature's error estimate), so the
// bilinear interpolation of the table never falls below the true albedo and the scaled diffuse
// base can only lose energy, never create it. The albedo is integrated over the visible normals
// (Heitz's sampling map, u in [0, 1]^2, midpoint rule): E = integral of F G2/G1 over the VNDF.
// Deterministic: the same bytes on every run.
//
//   make_ggx_albedo_table OUT.h
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "src/materials/fresnel.h"
#include "src/materials/microfacet.h"

namespace {

// Nodes: mu = (i / 31)^2, dense at grazing where the albedo changes fastest (0 read at 1e-4);
// roughness = j / 31.
constexpr int kMu = 32, kRough = 32;
constexpr int kSub = 4;               // sub-grid per cell for the upper bound

struct Albedo {
  double e1, e5;
};

// Albedo for wo at cosine mu, GGX alpha = roughness^2, with an n x n midpoint rule.
Albedo Integrate(double mu, double roughness, int n) {
  pt::GgxDistribution d{float(roughness * roughness)};
  mu = std::max(mu, 1e-4);
  pt::vec3 wo(float(std::sqrt(1.0 - mu * mu)), 0.0f, float(mu));
  double e1 = 0, e5 = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      pt::vec3 wm = d.SampleVisibleNormal(wo, pt::vec2((i + 0.5f) / n, (j + 0.5f) / n));
      pt::vec3 wi = pt::Reflect(wo, wm);
      if (wi.z <= 0.0f) continue;
      double w = double(d.G(wo, wi)) / double(d.G1(wo));
      double c = std::max(0.0, 1.0 - double(glm::dot(wo, wm)));
      e1 += w;
      e5 += w * c * c * c * c * c;
    }
  return {e1 / (double(n) * n), e5 / (double(n) * n)};
}

// The integral with an error estimate (change from half the resolution), both components.
Albedo IntegrateBound(double mu, double roughness) {
  Albedo fine = Integrate(mu, roughness, 128), coarse = Integrate(mu, roughness, 64);
  return {fine.e1 + 2.0 * std::fabs(fine.e1 - coarse.e1) + 1e-6,
          fine.e5 + 2.0 * std::fabs(fine.e5 - coarse.e5) + 1e-6};
}

std::string Literal(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.8g", std::min(v, 1.0));
  std::string s = buf;
  if (s.find_first_of(".e") == std::string::npos) s += ".0";  // a float literal needs one
  return s + "f";
}

std::string Block(const std::vector<double>& values) {
  std::string out, line = "   ";
  for (size_t i = 0; i < values.size(); ++i) {
    std::string item = " ";  // appended piecewise: " " + ... trips a GCC 12 -Wrestrict false alarm
    item.append(Literal(values[i])).append(",");
    if (line.size() + item.size() > 96) {
      out += line + " \\\n";
      line = "   ";
    }
    line += item;
  }
  return out + line;
}

// Cosine of node i (fine = the sub-grid index, kSub per cell).
double MuAt(double i) { return (i / (kMu - 1)) * (i / (kMu - 1)); }

// 2 * integral of the piecewise-linear (in mu) interpolant of a row times mu over [0, 1].
double RowAverage(const std::vector<double>& table, int j) {
  double sum = 0;
  for (int i = 0; i + 1 < kMu; ++i) {
    double a = MuAt(i), b = MuAt(i + 1), ea = table[j * kMu + i], eb = table[j * kMu + i + 1];
    sum += (b - a) / 6.0 * (ea * (2 * a + b) + eb * (a + 2 * b));
  }
  return 2.0 * sum;
}


// Node values of one component that bound the sub-grid values from above when interpolated.
std::vector<double> Bounded(const std::vector<Albedo>& fine, double Albedo::*c) {
  constexpr int kFine = (kMu - 1) * kSub + 1;
  auto at = [&](int fi, int fj) { return fine[size_t(fj) * kFine + fi].*c; };
  std::vector<double> node(kMu * kRough), shortfall((kMu - 1) * (kRough - 1), 0.0);
  for (int j = 0; j < kRough; ++j)
    for (int i = 0; i < kMu; ++i) node[j * kMu + i] = at(i * kSub, j * kSub);
  for (int j = 0; j + 1 < kRough; ++j)
    for (int i = 0; i + 1 < kMu; ++i) {
      double a = MuAt(i), b = MuAt(i + 1), worst = 0.0;
      for (int sj = 0; sj <= kSub; ++sj)
        for (int si = 0; si <= kSub; ++si) {
          double x = (MuAt(i + double(si) / kSub) - a) / (b - a), y = double(sj) / kSub;
          double interp = (1 - y) * ((1 - x) * node[j * kMu + i] + x * node[j * kMu + i + 1]) +
                          y * ((1 - x) * node[(j + 1) * kMu + i] + x * node[(j + 1) * kMu + i + 1]);
          worst = std::max(worst, at(i * kSub + si, j * kSub + sj) - interp);
        }
      shortfall[j * (kMu - 1) + i] = worst;
    }
  std::vector<double> out(node.size());
  for (int j = 0; j < kRough; ++j)
    for (int i = 0; i < kMu; ++i) {
      double raise = 0.0;
      for (int cj = std::max(0, j - 1); cj <= std::min(kRough - 2, j); ++cj)
        for (int ci = std::max(0, i - 1); ci <= std::min(kMu - 2, i); ++ci)
          raise = std::max(raise, shortfall[cj * (kMu - 1) + ci]);
      out[j * kMu + i] = std::min(1.0, node[j * kMu + i] + raise);
    }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_ggx_albedo_table OUT.h\n");
    return 1;
  }
  // The albedo (plus its quadrature error) on the sub-grid; node values are the sub-grid's at
  // the nodes, each then raised by the largest shortfall of the bilinear interpolant below
  // the sub-grid values in any cell around it (raising a cell's four corners by d raises the
  // interpolant by d throughout it). Convex stretches need nothing: their chords lie above.
  constexpr int kFine = (kMu - 1) * kSub + 1, kFineR = (kRough - 1) * kSub + 1;
  std::vector<Albedo> fine(size_t(kFine) * kFineR);
  for (int j = 0; j < kFineR; ++j)
    for (int i = 0; i < kFine; ++i)
      fine[size_t(j) * kFine + i] = IntegrateBound(MuAt(double(i) / kSub), double(j) / (kFineR - 1));
  std::vector<double> e1 = Bounded(fine, &Albedo::e1), e5 = Bounded(fine, &Albedo::e5);
  std::vector<double> avg1(kRough), avg5(kRough);
  for (int j = 0; j < kRough; ++j) avg1[j] = RowAverage(e1, j), avg5[j] = RowAverage(e5, j);

  FILE* out = std::fopen(argv[1], "w");
  if (!out) {
    std::fprintf(stderr, "make_ggx_albedo_table: cannot write %s\n", argv[1]);
    return 3;
  }
  std::fprintf(out, "%s",
      "// Generated by tools/make_ggx_albedo_table.cpp (see there): upper bounds of the\n"
      "// directional albedo of a GGX reflection lobe with Schlick's Fresnel, E(mu, r, F0) =\n"
      "// F0 E1 + (1 - F0) E5, on nodes mu = (i / 31)^2 (rows of 32), roughness r = j / 31 (32\n"
      "// rows), linear in mu and r between nodes;\n"
      "// and each row's 2 * integral of the interpolant times mu (the hemispherical average).\n"
      "// Host and device copies of the same literals, as src/materials/srgb_table.h.\n"
      "#pragma once\n\n#include \"src/core/pt.h\"\n\nnamespace pt {\n\n");
  std::fprintf(out, "constexpr int kGgxAlbedoMu = %d, kGgxAlbedoRoughness = %d;\n\n", kMu, kRough);
  std::fprintf(out, "#define PT_GGX_ALBEDO_TABLE \\\n%s \\\n%s \\\n%s \\\n%s\n\n", Block(e1).c_str(),
               Block(e5).c_str(), Block(avg1).c_str(), Block(avg5).c_str());
  std::fprintf(out, "%s",
      "// E1 rows, E5 rows, then the E1 and E5 row averages.\n"
      "constexpr int kGgxAlbedoE1 = 0, kGgxAlbedoE5 = kGgxAlbedoMu * kGgxAlbedoRoughness;\n"
      "constexpr int kGgxAlbedoAvg1 = 2 * kGgxAlbedoE5, kGgxAlbedoAvg5 = kGgxAlbedoAvg1 + "
      "kGgxAlbedoRoughness;\n\n"
      "namespace detail {\n"
      "inline constexpr float kGgxAlbedoHost[] = {PT_GGX_ALBEDO_TABLE};\n"
      "#if PT_DEVICE_COMPILE\n"
      "static __device__ const float kGgxAlbedoDevice[] = {PT_GGX_ALBEDO_TABLE};\n"
      "#endif\n"
      "}  // namespace detail\n\n"
      "#undef PT_GGX_ALBEDO_TABLE\n\n"
      "PT_HDI float GgxAlbedoEntry(int i) {\n"
      "#if PT_IS_GPU_CODE\n"
      "  return detail::kGgxAlbedoDevice[i];\n"
      "#else\n"
      "  return detail::kGgxAlbedoHost[i];\n"
      "#endif\n"
      "}\n\n"
      "}  // namespace pt\n");
  std::fclose(out);
  std::printf("wrote %s\n", argv[1]);
  return 0;
}
