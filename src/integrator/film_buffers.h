// The film's arrays on a backend (a FilmView over them) and their copies to and from a host
// FilmState. The integrator keeps two: the film it renders into, and the copy a render lane
// saves from on another thread while the film is cleared and rendered into again.
#pragma once

#include <stdexcept>
#include <vector>

#include "src/core/parallel_ranges.h"
#include "src/integrator/film.h"
#include "src/integrator/render_api.h"
#include "src/integrator/stage_id.h"

namespace pt {

// Threads that widen a float film to the saved doubles (the render's own are idle then).
constexpr int kFilmSaveThreads = 4;

template <typename Backend>
class FilmBuffers {
 public:
  template <typename T>
  using Buffer = typename Backend::template Buffer<T>;

  // Float or double statistics (--film), feature sums and the even-sample half film only
  // when asked for.
  void Allocate(size_t pixels, bool dbl, bool features, bool halves = false) {
    mean_.Resize(dbl ? 0 : pixels);
    m2_.Resize(dbl ? 0 : pixels);
    meanDouble_.Resize(dbl ? pixels : 0);
    m2Double_.Resize(dbl ? pixels : 0);
    albedo_.Resize(features ? pixels : 0);
    normal_.Resize(features ? pixels : 0);
    depth_.Resize(features ? pixels : 0);
    evenSum_.Resize(halves ? pixels : 0);
    evenCount_.Resize(halves ? pixels : 0);
    for (Buffer<vec3>* b : {&residualMean_, &residualM2_, &evenEmission_})
      b->Resize(halves ? pixels : 0);
    lumMean_.Resize(pixels);
    lumM2_.Resize(pixels);
    count_.Resize(pixels);
    if constexpr (!Backend::kHostMemory) {
      // SaveInto's scratch, its pages faulted in now (start-up) rather than in the first save
      // (31-44 ms for a 1080p film on a GPU host, with the other lane rendering).
      hostMean_.resize(dbl ? 0 : pixels);
      hostM2_.resize(dbl ? 0 : pixels);
    }
  }

  size_t Pixels() const { return count_.Size(); }
  FilmView View() {
    return FilmView{mean_.Data(),         m2_.Data(),          meanDouble_.Data(),
                    m2Double_.Data(),     lumMean_.Data(),     lumM2_.Data(),
                    count_.Data(),        albedo_.Data(),      normal_.Data(),
                    depth_.Data(),        evenSum_.Data(),     evenCount_.Data(),
                    residualMean_.Data(), residualM2_.Data(),  evenEmission_.Data()};
  }
  const Buffer<uint32_t>& Counts() const { return count_; }
  const Buffer<uint32_t>& EvenCounts() const { return evenCount_; }

  // Into f's own arrays (a film of the same size saves with no fresh pages to fault in).
  void SaveInto(FilmState& f, uint32_t width, uint32_t height) {
    size_t n = Pixels();
    f.width = width;
    f.height = height;
    if (meanDouble_.Size() != 0) {
      meanDouble_.Download(f.mean);
      m2Double_.Download(f.m2);
    } else {
      const vec3* mean = HostFloats(mean_, hostMean_);
      const vec3* m2 = HostFloats(m2_, hostM2_);
      f.mean.resize(n);
      f.m2.resize(n);
      // Widening is the save's largest host cost after the pages (a 1080p film: ~8 ms on one
      // core, ~2.3 ms on four).
      ForRangesOnThreads(n, kFilmSaveThreads, 65536, [&](size_t lo, size_t hi) {
        for (size_t i = lo; i < hi; ++i) {
          f.mean[i] = glm::dvec3(mean[i]);
          f.m2[i] = glm::dvec3(m2[i]);
        }
      });
    }
    lumMean_.Download(f.lumMean);
    lumM2_.Download(f.lumM2);
    count_.Download(f.count);
    albedo_.Download(f.albedoSum);  // empty without feature buffers
    normal_.Download(f.normalSum);
    depth_.Download(f.depthSum);
    evenSum_.Download(f.evenSum);  // empty without half films
    evenCount_.Download(f.evenCount);
    residualMean_.Download(f.residualMean);
    residualM2_.Download(f.residualM2);
    evenEmission_.Download(f.evenEmissionSum);
  }

  // Throws std::invalid_argument when the film's size or channels do not match.
  void LoadFrom(const FilmState& f, uint32_t width, uint32_t height) {
    size_t n = Pixels();
    if (f.width != width || f.height != height || f.mean.size() != n || f.m2.size() != n ||
        f.lumMean.size() != n || f.lumM2.size() != n || f.count.size() != n)
      throw std::invalid_argument("film state does not match the render's size");
    bool features = albedo_.Size() != 0;
    if (features && (f.albedoSum.size() != n || f.normalSum.size() != n || f.depthSum.size() != n))
      throw std::invalid_argument("film state lacks the feature channels this render keeps");
    bool halves = evenSum_.Size() != 0;
    if (halves && (f.evenSum.size() != n || f.evenCount.size() != n ||
                   f.residualMean.size() != n || f.residualM2.size() != n ||
                   f.evenEmissionSum.size() != n))
      throw std::invalid_argument("film state lacks the half-film channels this render keeps "
                                  "(--denoise)");
    if (meanDouble_.Size() != 0) {
      meanDouble_.Upload(f.mean);
      m2Double_.Upload(f.m2);
    } else {
      mean_.Upload(std::vector<vec3>(f.mean.begin(), f.mean.end()));
      m2_.Upload(std::vector<vec3>(f.m2.begin(), f.m2.end()));
    }
    lumMean_.Upload(f.lumMean);
    lumM2_.Upload(f.lumM2);
    count_.Upload(f.count);
    if (features) {
      albedo_.Upload(f.albedoSum);
      normal_.Upload(f.normalSum);
      depth_.Upload(f.depthSum);
    }
    if (halves) {
      evenSum_.Upload(f.evenSum);
      evenCount_.Upload(f.evenCount);
      residualMean_.Upload(f.residualMean);
      residualM2_.Upload(f.residualM2);
      evenEmission_.Upload(f.evenEmissionSum);
    }
  }

 private:
  // A float array on the host: in place on a host backend, else downloaded into scratch that
  // stays mapped between saves.
  static const vec3* HostFloats(const Buffer<vec3>& b, std::vector<vec3>& scratch) {
    if constexpr (Backend::kHostMemory) {
      return b.Data();
    } else {
      b.Download(scratch);
      return scratch.data();
    }
  }

  Buffer<vec3> mean_, m2_, albedo_, normal_, evenSum_, residualMean_, residualM2_, evenEmission_;
  Buffer<glm::dvec3> meanDouble_, m2Double_;
  Buffer<float> lumMean_, lumM2_, depth_;
  Buffer<uint32_t> count_, evenCount_;
  std::vector<vec3> hostMean_, hostM2_;
};

// The film resolved on the backend (ResolveFilmPixel) and the image's planes downloaded: a
// 1080p image's rgb and variance are 50 MB, the film's float statistics widened to doubles
// on the host were 150 MB more to copy and read (issue 28's time to image). Kept between
// calls: previews resolve again and again.
template <typename Backend>
class ResolvedImage {
 public:
  template <typename T>
  using Buffer = typename Backend::template Buffer<T>;

  FilmImage Resolve(Backend& backend, const FilmView& film, const FilmBuffers<Backend>& arrays,
                    uint32_t width, uint32_t height) {
    const size_t n = size_t(width) * height;
    const bool features = film.albedoSum != nullptr, halves = film.evenSum != nullptr;
    for (Buffer<float>* b : {&rgb_, &variance_}) b->Resize(3 * n);
    for (Buffer<float>* b : {&albedo_, &normal_}) b->Resize(features ? 3 * n : 0);
    depth_.Resize(features ? n : 0);
    for (Buffer<float>* b : {&evenRgb_, &emission_, &evenEmission_, &residualVariance_})
      b->Resize(halves ? 3 * n : 0);
    const ImageView out{rgb_.Data(),      variance_.Data(),    features ? albedo_.Data() : nullptr,
                        normal_.Data(),   depth_.Data(),       halves ? evenRgb_.Data() : nullptr,
                        emission_.Data(), evenEmission_.Data(), residualVariance_.Data()};
    backend.ParallelFor(Stage::kAccumulate, uint32_t(n),
                        [=] PT_HD(uint32_t i) { ResolveFilmPixel(film, out, i); });
    backend.Synchronize();
    FilmImage img;
    img.width = int(width);
    img.height = int(height);
    rgb_.Download(img.rgb);
    variance_.Download(img.variance);
    arrays.Counts().Download(img.samples);
    if (features) {
      albedo_.Download(img.albedo);
      normal_.Download(img.normal);
      depth_.Download(img.depth);
    }
    if (halves) {
      evenRgb_.Download(img.evenRgb);
      arrays.EvenCounts().Download(img.evenSamples);
      emission_.Download(img.emission);
      evenEmission_.Download(img.evenEmission);
      residualVariance_.Download(img.residualVariance);
    }
    return img;
  }

 private:
  Buffer<float> rgb_, variance_, albedo_, normal_, depth_, evenRgb_, emission_, evenEmission_,
      residualVariance_;
};

}  // namespace pt
