#include "src/distributed/film_merge.h"

#include <stdexcept>

#include "src/core/parallel_ranges.h"

namespace pt {
namespace {

bool HasFeatures(const FilmState& f) { return !f.albedoSum.empty(); }
bool HasHalves(const FilmState& f) { return !f.evenSum.empty(); }

void CheckShape(const FilmState& f, const char* which) {
  size_t n = f.PixelCount();
  bool ok = f.mean.size() == n && f.m2.size() == n && f.lumMean.size() == n &&
            f.lumM2.size() == n && f.count.size() == n;
  if (HasFeatures(f))
    ok = ok && f.albedoSum.size() == n && f.normalSum.size() == n && f.depthSum.size() == n;
  if (HasHalves(f))
    ok = ok && f.evenSum.size() == n && f.evenCount.size() == n && f.residualMean.size() == n &&
         f.residualM2.size() == n && f.evenEmissionSum.size() == n;
  if (!ok) throw std::invalid_argument(std::string("film merge: the ") + which +
                                       " film's arrays do not match its size");
}

void MergePixel(FilmState& a, const FilmState& b, size_t i) {
  uint32_t nb = b.count[i];
  if (nb == 0) return;
  uint32_t na = a.count[i];
  if (HasFeatures(a)) {
    a.albedoSum[i] += b.albedoSum[i];
    a.normalSum[i] += b.normalSum[i];
    a.depthSum[i] += b.depthSum[i];
  }
  if (HasHalves(a)) {
    a.evenSum[i] += b.evenSum[i];
    a.evenCount[i] += b.evenCount[i];
    a.evenEmissionSum[i] += b.evenEmissionSum[i];
  }
  a.count[i] = na + nb;
  if (na == 0) {
    a.mean[i] = b.mean[i];
    a.m2[i] = b.m2[i];
    a.lumMean[i] = b.lumMean[i];
    a.lumM2[i] = b.lumM2[i];
    if (HasHalves(a)) {
      a.residualMean[i] = b.residualMean[i];
      a.residualM2[i] = b.residualM2[i];
    }
    return;
  }
  double n = double(na) + double(nb);
  double fb = double(nb) / n;
  double cross = double(na) * fb;  // na * nb / n
  glm::dvec3 d = b.mean[i] - a.mean[i];
  a.mean[i] = a.mean[i] + d * fb;
  a.m2[i] = a.m2[i] + b.m2[i] + d * d * cross;
  double dl = double(b.lumMean[i]) - double(a.lumMean[i]);
  a.lumMean[i] = float(double(a.lumMean[i]) + dl * fb);
  a.lumM2[i] = float(double(a.lumM2[i]) + double(b.lumM2[i]) + dl * dl * cross);
  if (HasHalves(a)) {
    glm::dvec3 dr = glm::dvec3(b.residualMean[i]) - glm::dvec3(a.residualMean[i]);
    a.residualMean[i] = vec3(glm::dvec3(a.residualMean[i]) + dr * fb);
    a.residualM2[i] = vec3(glm::dvec3(a.residualM2[i]) + glm::dvec3(b.residualM2[i]) +
                           dr * dr * cross);
  }
}

}  // namespace

void MergeFilmInto(FilmState& into, const FilmState& from, int threads) {
  if (into.width != from.width || into.height != from.height)
    throw std::invalid_argument("film merge: films of different sizes");
  if (HasFeatures(into) != HasFeatures(from))
    throw std::invalid_argument("film merge: one film has feature channels, the other not");
  if (HasHalves(into) != HasHalves(from))
    throw std::invalid_argument("film merge: one film has half-film channels, the other not");
  CheckShape(into, "first");
  CheckShape(from, "second");
  // Below ~64k pixels a thread costs more than it saves.
  ForRangesOnThreads(into.PixelCount(), threads, 65536, [&](size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i) MergePixel(into, from, i);
  });
}

FilmState EmptyFilm(uint32_t width, uint32_t height, bool features, bool halves) {
  FilmState f;
  f.width = width;
  f.height = height;
  size_t n = f.PixelCount();
  f.mean.assign(n, glm::dvec3(0.0));
  f.m2.assign(n, glm::dvec3(0.0));
  f.lumMean.assign(n, 0.0f);
  f.lumM2.assign(n, 0.0f);
  f.count.assign(n, 0u);
  if (features) {
    f.albedoSum.assign(n, vec3(0.0f));
    f.normalSum.assign(n, vec3(0.0f));
    f.depthSum.assign(n, 0.0f);
  }
  if (halves) {
    f.evenSum.assign(n, vec3(0.0f));
    f.evenCount.assign(n, 0u);
    for (std::vector<vec3>* v : {&f.residualMean, &f.residualM2, &f.evenEmissionSum})
      v->assign(n, vec3(0.0f));
  }
  return f;
}

}  // namespace pt
