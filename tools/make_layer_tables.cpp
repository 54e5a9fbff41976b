// Writes src/materials/layer_tables.h: the albedo tables of the glTF extension lobes
// (src/materials/gltf_layered.h), on the nodes of ggx_albedo_table.h (mu = (i / 31)^2, rows of
// 32; roughness r = j / 31, 32 rows; linear in mu and r between nodes):
//
//   MsE   the directional albedo E(mu, r) of GGX reflection with F = 1 (alpha = r^2), accurate
//         (a 512 x 512 midpoint rule over the visible normals), and each row's hemispherical
//         average 2 * integral of the interpolant times mu: the multiple-scattering
//         compensation (Kulla and Conty 2017) needs values, not bounds, to reach exactly 1.
//   Sheen upper bounds of the albedo of the Charlie sheen lobe (charlie_sheen.h, white sheen
//         colour) over sheen roughness r: the layers below sheen are scaled by 1 - E, so a
//         bound keeps the sum at most 1. Not capped at 1: the fitted visibility makes smooth
//         sheen reflect up to 2.9 times what it receives at grazing views, which
//         gltf_layered.h divides out (each node raised by the interpolant's largest
//         shortfall below a 3 x 3 sub-grid of every adjacent cell, plus the quadrature's error
//         estimate, as tools/make_ggx_albedo_table.cpp).
//
// Deterministic; about a minute: build/make_layer_tables src/materials/layer_tables.h
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "src/materials/charlie_sheen.h"
#include "src/materials/fresnel.h"
#include "src/materials/microfacet.h"

namespace {

constexpr int kMu = 32, kRough = 32;
constexpr int kSub = 3;  // sheen: sub-grid per cell for the upper bound

double MuAt(double i) { return (i / (kMu - 1)) * (i / (kMu - 1)); }

pt::vec3 ViewAt(double mu) {
  mu = std::max(mu, 1e-4);
  return pt::vec3(float(std::sqrt(1.0 - mu * mu)), 0.0f, float(mu));
}

// GGX albedo with F = 1 over the visible normals (weight G2 / G1), n x n midpoint rule.
double GgxAlbedo(double mu, double roughness, int n) {
  pt::GgxDistribution d{std::max(float(roughness * roughness), 1e-4f)};
  pt::vec3 wo = ViewAt(mu);
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      pt::vec3 wm = d.SampleVisibleNormal(wo, pt::vec2((i + 0.5f) / n, (j + 0.5f) / n));
      pt::vec3 wi = pt::Reflect(wo, wm);
      if (wi.z > 0.0f) sum += double(d.G(wo, wi)) / double(d.G1(wo));
    }
  return sum / (double(n) * n);
}

// Sheen albedo (white colour) by sampling fibre normals: weight f cos_i / pdf.
double SheenAlbedo(double mu, double roughness, int n) {
  pt::CharlieSheen s = pt::CharlieSheen::FromRoughness(float(roughness));
  pt::vec3 wo = ViewAt(mu);
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      pt::vec3 wm = s.SampleNormal(pt::vec2((i + 0.5f) / n, (j + 0.5f) / n));
      pt::vec3 wi = pt::Reflect(wo, wm);
      if (wi.z <= 0.0f) continue;
      double pdf = s.ReflectionPdf(wo, wi);
      if (pdf > 0.0) sum += double(s.Eval(wo, wi)) * wi.z / pdf;
    }
  return sum / (double(n) * n);
}

double SheenBound(double mu, double roughness) {
  double fine = SheenAlbedo(mu, roughness, 160), coarse = SheenAlbedo(mu, roughness, 80);
  return fine + 2.0 * std::fabs(fine - coarse) + 1e-6;
}

std::string Literal(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.8g", v);
  std::string s = buf;
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s + "f";
}

std::string Block(const std::vector<double>& values) {
  std::string out, line = "   ";
  for (double v : values) {
    std::string item = " ";
    item.append(Literal(v)).append(",");
    if (line.size() + item.size() > 96) {
      out += line + " \\\n";
      line = "   ";
    }
    line += item;
  }
  return out + line;
}

// 2 * integral of the row's piecewise-linear (in mu) interpolant times mu over [0, 1].
double RowAverage(const std::vector<double>& table, int j) {
  double sum = 0;
  for (int i = 0; i + 1 < kMu; ++i) {
    double a = MuAt(i), b = MuAt(i + 1), ea = table[j * kMu + i], eb = table[j * kMu + i + 1];
    sum += (b - a) / 6.0 * (ea * (2 * a + b) + eb * (a + 2 * b));
  }
  return 2.0 * sum;
}

// Node values that bound the fine-grid values from above when interpolated.
std::vector<double> Bounded(const std::vector<double>& fine) {
  constexpr int kFine = (kMu - 1) * kSub + 1;
  auto at = [&](int fi, int fj) { return fine[size_t(fj) * kFine + fi]; };
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
      out[j * kMu + i] = node[j * kMu + i] + raise;
    }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_layer_tables OUT.h\n");
    return 1;
  }
  std::vector<double> ms(kMu * kRough), msAvg(kRough);
  for (int j = 0; j < kRough; ++j)
    for (int i = 0; i < kMu; ++i)
      ms[j * kMu + i] = std::min(1.0, GgxAlbedo(MuAt(i), double(j) / (kRough - 1), 512));
  for (int j = 0; j < kRough; ++j) msAvg[j] = RowAverage(ms, j);
  constexpr int kFine = (kMu - 1) * kSub + 1, kFineR = (kRough - 1) * kSub + 1;
  std::vector<double> fine(size_t(kFine) * kFineR);
  for (int j = 0; j < kFineR; ++j)
    for (int i = 0; i < kFine; ++i)
      fine[size_t(j) * kFine + i] = SheenBound(MuAt(double(i) / kSub), double(j) / (kFineR - 1));
  std::vector<double> sheen = Bounded(fine);

  FILE* out = std::fopen(argv[1], "w");
  if (!out) {
    std::fprintf(stderr, "make_layer_tables: cannot write %s\n", argv[1]);
    return 3;
  }
  std::fprintf(out, "%s",
      "// Generated by tools/make_layer_tables.cpp (see there): on the nodes of\n"
      "// ggx_albedo_table.h, the accurate GGX albedo with F = 1 (32 rows of 32) and its row\n"
      "// averages (32), then upper bounds of the Charlie sheen albedo (32 rows of 32) over sheen\n"
      "// roughness. Host and device copies of the same literals, as src/materials/srgb_table.h.\n"
      "#pragma once\n\n#include \"src/core/pt.h\"\n\nnamespace pt {\n\n");
  std::fprintf(out, "#define PT_LAYER_TABLES \\\n%s \\\n%s \\\n%s\n\n", Block(ms).c_str(),
               Block(msAvg).c_str(), Block(sheen).c_str());
  std::fprintf(out, "%s",
      "// The MsE rows, their averages, then the sheen rows.\n"
      "constexpr int kLayerMsE = 0, kLayerMsAvg = 32 * 32, kLayerSheenE = kLayerMsAvg + 32;\n\n"
      "namespace detail {\n"
      "inline constexpr float kLayerTablesHost[] = {PT_LAYER_TABLES};\n"
      "#if PT_DEVICE_COMPILE\n"
      "static __device__ const float kLayerTablesDevice[] = {PT_LAYER_TABLES};\n"
      "#endif\n"
      "}  // namespace detail\n\n"
      "#undef PT_LAYER_TABLES\n\n"
      "PT_HDI float LayerTableEntry(int i) {\n"
      "#if PT_IS_GPU_CODE\n"
      "  return detail::kLayerTablesDevice[i];\n"
      "#else\n"
      "  return detail::kLayerTablesHost[i];\n"
      "#endif\n"
      "}\n\n"
      "}  // namespace pt\n");
  std::fclose(out);
  std::printf("wrote %s\n", argv[1]);
  return 0;
}
