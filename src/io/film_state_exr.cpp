#include "src/io/film_state_exr.h"

#include <bit>

#include "src/io/exr_codec.h"
#include "src/io/image_io.h"

namespace pt {
namespace {

constexpr const char* kPrecisionAttribute = "pathtracerFilm";
constexpr const char* kXyz = "XYZ";

// Exact 32-bit words for the mean or M2 of one channel: floats, or a double's two halves.
void AddWelfordChannels(const std::string& name, const std::vector<glm::dvec3>& values,
                        bool doubleFilm, std::vector<ExrChannel>& channels) {
  for (int c = 0; c < 3; ++c) {
    std::string base = "state." + name + "." + "RGB"[c];
    if (!doubleFilm) {
      std::vector<float> f(values.size());
      for (size_t i = 0; i < values.size(); ++i) f[i] = float(values[i][c]);
      channels.push_back(FloatChannel(base, f, 1, 0));
      continue;
    }
    std::vector<uint32_t> hi(values.size()), lo(values.size());
    for (size_t i = 0; i < values.size(); ++i) {
      uint64_t bits = std::bit_cast<uint64_t>(values[i][c]);
      hi[i] = uint32_t(bits >> 32);
      lo[i] = uint32_t(bits);
    }
    channels.push_back(UintChannel(base + ".hi", hi));
    channels.push_back(UintChannel(base + ".lo", lo));
  }
}

void AddVec3Channels(const std::string& name, const std::vector<vec3>& values,
                     std::vector<ExrChannel>& channels) {
  std::vector<float> flat(values.size() * 3);
  for (size_t i = 0; i < values.size(); ++i) {
    for (int c = 0; c < 3; ++c) flat[3 * i + size_t(c)] = values[i][c];
  }
  for (int c = 0; c < 3; ++c) {
    channels.push_back(FloatChannel("state." + name + "." + kXyz[c], flat, 3, c));
  }
}

// Reads channels of a resumable file; every one must be there.
class StateReader {
 public:
  explicit StateReader(const std::string& path) : path_(path), file_(path) {}
  const ExrFile& File() const { return file_; }

  std::vector<uint32_t> Words(const std::string& name) const {
    std::vector<uint32_t> words;
    if (!file_.Words(name, &words)) {
      throw ImageError(path_ + ": the resumable state lacks its channel '" + name + "'");
    }
    return words;
  }
  std::vector<float> Floats(const std::string& name) const {
    std::vector<uint32_t> words = Words(name);
    std::vector<float> f(words.size());
    for (size_t i = 0; i < f.size(); ++i) f[i] = std::bit_cast<float>(words[i]);
    return f;
  }
  std::vector<glm::dvec3> Welford(const std::string& name, bool doubleFilm) const {
    std::vector<glm::dvec3> values(Pixels());
    for (int c = 0; c < 3; ++c) {
      std::string base = "state." + name + "." + "RGB"[c];
      if (!doubleFilm) {
        std::vector<float> f = Floats(base);
        for (size_t i = 0; i < f.size(); ++i) values[i][c] = double(f[i]);
        continue;
      }
      std::vector<uint32_t> hi = Words(base + ".hi"), lo = Words(base + ".lo");
      for (size_t i = 0; i < hi.size(); ++i) {
        values[i][c] = std::bit_cast<double>((uint64_t(hi[i]) << 32) | lo[i]);
      }
    }
    return values;
  }
  std::vector<vec3> Vec3s(const std::string& name) const {
    std::vector<vec3> values(Pixels());
    for (int c = 0; c < 3; ++c) {
      std::vector<float> f = Floats("state." + name + "." + kXyz[c]);
      for (size_t i = 0; i < f.size(); ++i) values[i][c] = f[i];
    }
    return values;
  }
  bool Has(const std::string& name) const {
    std::vector<uint32_t> ignored;
    return file_.Words(name, &ignored);
  }

 private:
  size_t Pixels() const { return size_t(file_.Width()) * size_t(file_.Height()); }
  std::string path_;
  ExrFile file_;
};

}  // namespace

void WriteResumableExr(const std::string& path, const FilmImage& image, const FilmState& film,
                       bool doubleFilm, const std::string& description) {
  size_t pixels = film.PixelCount();
  bool features = !film.albedoSum.empty();
  if (int(film.width) != image.width || int(film.height) != image.height ||
      image.samples != film.count || film.mean.size() != pixels || film.m2.size() != pixels ||
      film.lumMean.size() != pixels || film.lumM2.size() != pixels ||
      (features && (film.normalSum.size() != pixels || film.depthSum.size() != pixels)) ||
      film.evenSum.size() != film.evenCount.size() ||
      (!film.evenSum.empty() &&
       (film.evenSum.size() != pixels || film.residualMean.size() != pixels ||
        film.residualM2.size() != pixels || film.evenEmissionSum.size() != pixels))) {
    throw ImageError(path + ": internal: the film state does not match its image");
  }
  // The image as any --hdr EXR holds it; its "samples" channel is the film's counts.
  std::vector<ExrChannel> channels = ImageExrChannels(image, true);
  AddWelfordChannels("mean", film.mean, doubleFilm, channels);
  AddWelfordChannels("m2", film.m2, doubleFilm, channels);
  channels.push_back(FloatChannel("state.lum.mean", film.lumMean, 1, 0));
  channels.push_back(FloatChannel("state.lum.m2", film.lumM2, 1, 0));
  if (features) {
    AddVec3Channels("albedoSum", film.albedoSum, channels);
    AddVec3Channels("normalSum", film.normalSum, channels);
    channels.push_back(FloatChannel("state.depthSum", film.depthSum, 1, 0));
  }
  if (!film.evenSum.empty()) {  // --denoise's half film
    AddVec3Channels("evenSum", film.evenSum, channels);
    channels.push_back(UintChannel("state.evenCount", film.evenCount));
    AddVec3Channels("residualMean", film.residualMean, channels);
    AddVec3Channels("residualM2", film.residualM2, channels);
    AddVec3Channels("evenEmissionSum", film.evenEmissionSum, channels);
  }
  std::vector<ExrAttribute> attributes = {{kResumeAttribute, description},
                                          {kPrecisionAttribute, doubleFilm ? "double" : "float"}};
  WriteFileAtomic(path, EncodeExr(path, image.width, image.height, std::move(channels), attributes));
}

ResumableExr ReadResumableExr(const std::string& path) {
  StateReader reader(path);
  ResumableExr out;
  std::string precision;
  if (!reader.File().Attribute(kResumeAttribute, &out.description) ||
      !reader.File().Attribute(kPrecisionAttribute, &precision)) {
    throw ImageError(path + ": has no resumable state (only an EXR that a render stopped "
                            "early or --checkpoint-every wrote can be resumed)");
  }
  if (precision != "float" && precision != "double") {
    throw ImageError(path + ": unknown film precision '" + precision + "' in its state");
  }
  out.doubleFilm = precision == "double";
  FilmState& film = out.film;
  film.width = uint32_t(reader.File().Width());
  film.height = uint32_t(reader.File().Height());
  film.mean = reader.Welford("mean", out.doubleFilm);
  film.m2 = reader.Welford("m2", out.doubleFilm);
  film.lumMean = reader.Floats("state.lum.mean");
  film.lumM2 = reader.Floats("state.lum.m2");
  film.count = reader.Words("samples");
  if (reader.Has("state.depthSum")) {
    film.albedoSum = reader.Vec3s("albedoSum");
    film.normalSum = reader.Vec3s("normalSum");
    film.depthSum = reader.Floats("state.depthSum");
  }
  if (reader.Has("state.evenCount")) {
    film.evenSum = reader.Vec3s("evenSum");
    film.evenCount = reader.Words("state.evenCount");
    if (!reader.Has("state.residualMean.X"))  // kept since 2026-11-28 (docs/denoise.md)
      throw ImageError(path + ": a --denoise state from before the film kept its seen "
                              "emission (no state.residualMean channels); it cannot be resumed");
    film.residualMean = reader.Vec3s("residualMean");
    film.residualM2 = reader.Vec3s("residualM2");
    film.evenEmissionSum = reader.Vec3s("evenEmissionSum");
  }
  return out;
}

}  // namespace pt
