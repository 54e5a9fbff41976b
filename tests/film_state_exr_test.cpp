// The resumable EXR (src/io/film_state_exr): the film's state comes back bit for bit, float
// and double films alike, with the image channels any --hdr EXR has; an image-only EXR and a
// damaged state are refused with a message naming the file.
#include <gtest/gtest.h>

#include <bit>
#include <random>

#include "src/integrator/wave_plan.h"
#include "src/io/exr_codec.h"
#include "src/io/film_state_exr.h"
#include "src/io/image_io.h"
#include "tests/test_util.h"

namespace pt {
namespace {

// A film of random state: doubles that use every mantissa bit (or float values), odd counts.
FilmState RandomFilm(uint32_t w, uint32_t h, bool doubleFilm, bool features) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  FilmState f;
  f.width = w;
  f.height = h;
  size_t n = f.PixelCount();
  auto value = [&] { return doubleFilm ? u(rng) : double(float(u(rng))); };
  for (size_t i = 0; i < n; ++i) {
    f.mean.push_back(glm::dvec3(value(), value(), value()));
    f.m2.push_back(glm::dvec3(value(), value(), value()));
    f.lumMean.push_back(float(u(rng)));
    f.lumM2.push_back(float(u(rng)));
    f.count.push_back(uint32_t(rng() % 100000) + 17000000);  // beyond float's exact integers
    if (features) {
      f.albedoSum.push_back(vec3(float(u(rng)), float(u(rng)), float(u(rng))));
      f.normalSum.push_back(vec3(float(u(rng)), -float(u(rng)), float(u(rng))));
      f.depthSum.push_back(float(u(rng)));
      f.evenSum.push_back(vec3(float(u(rng)), float(u(rng)), float(u(rng))));  // --denoise's
      f.evenCount.push_back(f.count.back() / 2 + 1);
      for (std::vector<vec3>* v : {&f.residualMean, &f.residualM2, &f.evenEmissionSum})
        v->push_back(vec3(float(u(rng)), float(u(rng)), float(u(rng))));
    }
  }
  return f;
}

TEST(FilmStateExr, TheStateComesBackBitForBit) {
  std::string dir = test::TempDir();
  for (bool doubleFilm : {false, true}) {
    for (bool features : {false, true}) {
      SCOPED_TRACE(std::string(doubleFilm ? "double" : "float") + (features ? " features" : ""));
      FilmState film = RandomFilm(7, 5, doubleFilm, features);
      std::string path = dir + "/state.exr";
      WriteResumableExr(path, ResolveFilmImage(film), film, doubleFilm, "{\"format\": 1}");
      ResumableExr back = ReadResumableExr(path);
      EXPECT_EQ(back.doubleFilm, doubleFilm);
      EXPECT_EQ(back.description, "{\"format\": 1}");
      EXPECT_EQ(back.film.width, 7u);
      EXPECT_EQ(back.film.height, 5u);
      EXPECT_TRUE(test::BitIdentical(back.film.mean, film.mean));
      EXPECT_TRUE(test::BitIdentical(back.film.m2, film.m2));
      EXPECT_TRUE(test::BitIdentical(back.film.lumMean, film.lumMean));
      EXPECT_TRUE(test::BitIdentical(back.film.lumM2, film.lumM2));
      EXPECT_EQ(back.film.count, film.count);
      EXPECT_TRUE(test::BitIdentical(back.film.albedoSum, film.albedoSum));
      EXPECT_TRUE(test::BitIdentical(back.film.normalSum, film.normalSum));
      EXPECT_TRUE(test::BitIdentical(back.film.depthSum, film.depthSum));
      EXPECT_TRUE(test::BitIdentical(back.film.evenSum, film.evenSum));
      EXPECT_EQ(back.film.evenCount, film.evenCount);
      EXPECT_TRUE(test::BitIdentical(back.film.residualMean, film.residualMean));
      EXPECT_TRUE(test::BitIdentical(back.film.residualM2, film.residualM2));
      EXPECT_TRUE(test::BitIdentical(back.film.evenEmissionSum, film.evenEmissionSum));
      // The image a viewer sees is there too.
      int w = 0, h = 0;
      std::vector<float> rgb;
      ReadExrRgb(path, &w, &h, &rgb);
      EXPECT_EQ(rgb, ResolveFilmImage(film).rgb);
    }
  }
}

TEST(FilmStateExr, AnImageOnlyOrDamagedFileIsRefused) {
  std::string dir = test::TempDir();
  FilmState film = RandomFilm(4, 3, false, false);
  FilmImage image = ResolveFilmImage(film);
  WriteImage(dir + "/plain.exr", image, true);
  try {
    ReadResumableExr(dir + "/plain.exr");
    ADD_FAILURE() << "an image-only EXR was read as a state";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("plain.exr: has no resumable state"), std::string::npos)
        << e.what();
  }
  // The attributes without one of the state's channels.
  std::vector<ExrChannel> channels = ImageExrChannels(image, true);
  WriteFileAtomic(dir + "/damaged.exr",
                  EncodeExr(dir + "/damaged.exr", 4, 3, channels,
                            {{kResumeAttribute, "{}"}, {"pathtracerFilm", "float"}}));
  try {
    ReadResumableExr(dir + "/damaged.exr");
    ADD_FAILURE() << "a state without its channels was read";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("lacks its channel 'state.mean.R'"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(ReadResumableExr(dir + "/missing.exr"), ImageError);
  // A film and an image that do not belong together are not written.
  FilmImage other = image;
  other.samples[0] += 1;
  EXPECT_THROW(WriteResumableExr(dir + "/bad.exr", other, film, false, "{}"), ImageError);
}

}  // namespace
}  // namespace pt
