// What --denoise asks of the renderer: the film's half of even-indexed samples (right in
// one pass, across chunks and merges, absent unless asked for), and features that look
// through mirrors and smooth glass to the first rough surface.
#include <gtest/gtest.h>

#include "src/distributed/chunked_render.h"
#include "src/denoise/denoiser.h"
#include "src/distributed/film_merge.h"
#include "src/integrator/render_session.h"
#include "tests/render_test_util.h"

namespace pt::test {
namespace {

RenderOptions Halves(int threads = 2) {
  RenderOptions o;
  o.threads = threads;
  o.featureBuffers = o.halfFilms = true;
  return o;
}

Scene BoxScene(int spp) {
  SceneDesc d = LoadScene(SourcePath("scenes/cornell_box.json"));
  d.render.width = 20;
  d.render.height = 16;
  d.render.spp = spp;
  return BuildScene(std::move(d));
}

// Sample 0 is the only even one of two: the even half of a 2-spp render is the 1-spp image,
// bit for bit; of 5 samples, 3 are even.
TEST(HalfFilms, TheEvenHalfHoldsTheEvenSamples) {
  FilmImage one = RenderOnCpu(BoxScene(1)).image;
  FilmImage two = RenderOnCpu(BoxScene(2), Halves()).image;
  EXPECT_TRUE(BitIdentical(two.evenRgb, one.rgb));
  EXPECT_EQ(two.evenSamples, std::vector<uint32_t>(one.samples.size(), 1u));
  FilmImage five = RenderOnCpu(BoxScene(5), Halves()).image;
  EXPECT_EQ(five.evenSamples, std::vector<uint32_t>(five.samples.size(), 3u));
  EXPECT_FALSE(BitIdentical(five.evenRgb, five.rgb));
}

// Under --sampler sobol a film with half films draws its halves from two Sobol replicates
// (rng.h, kSobolHalves): sample 0 is then not the one sequence's first sample, as it is for
// independent numbers above; the statistics still name the sampler "sobol".
TEST(HalfFilms, SobolHalvesAreTwoReplicates) {
  RenderOptions sobol;
  sobol.threads = 2;
  sobol.sampler = SamplerKind::kSobol;
  RenderOptions halves = Halves();
  halves.sampler = SamplerKind::kSobol;
  FilmImage one = RenderOnCpu(BoxScene(1), sobol).image;
  RenderResult two = RenderOnCpu(BoxScene(2), halves);
  EXPECT_FALSE(BitIdentical(two.image.evenRgb, one.rgb));
  EXPECT_EQ(two.stats.sampler, "sobol");
  halves.sampler = SamplerKind::kIndependent;
  sobol.sampler = SamplerKind::kIndependent;
  EXPECT_TRUE(BitIdentical(RenderOnCpu(BoxScene(2), halves).image.evenRgb,
                           RenderOnCpu(BoxScene(1), sobol).image.rgb));
}

// A render that does not ask for them keeps no half film (it pays nothing for them).
TEST(HalfFilms, AbsentUnlessAskedFor) {
  RenderOptions o;
  o.featureBuffers = true;
  RenderResult r = RenderOnCpu(BoxScene(2), o);
  EXPECT_TRUE(r.image.evenRgb.empty());
  EXPECT_TRUE(r.image.evenSamples.empty());
  Scene scene = BoxScene(2);  // outlives the session
  std::unique_ptr<RenderSession> s = MakeCpuSession(scene, o);
  s->RenderUpTo(2);
  EXPECT_TRUE(s->SaveFilm().evenSum.empty());
}

// Chunks split the samples by their global index: the merged film's even half is the plain
// render's (the same sums: each even sample added once, in order).
TEST(HalfFilms, ChunksAndMergesKeepTheHalves) {
  Scene scene = BoxScene(6);
  RenderResult plain = RenderCpu(scene, Halves(1));
  RenderResult chunked = RenderChunked(MakeCpuSession, scene, Halves(1), {}, 3);
  EXPECT_EQ(chunked.image.evenSamples, plain.image.evenSamples);
  ASSERT_EQ(chunked.image.evenRgb.size(), plain.image.evenRgb.size());
  // The seen emission's means and the residual's variance too (Chan's merge of its Welford
  // statistics).
  for (auto plane : {&FilmImage::evenRgb, &FilmImage::emission, &FilmImage::evenEmission,
                     &FilmImage::residualVariance}) {
    const std::vector<float>& want = plain.image.*plane;
    const std::vector<float>& got = chunked.image.*plane;
    ASSERT_EQ(got.size(), want.size());
    ASSERT_EQ(want.size(), plain.image.rgb.size());
    for (size_t i = 0; i < want.size(); ++i)
      EXPECT_NEAR(got[i], want[i], 1e-5f * (1.0f + want[i])) << i;
  }
  FilmState a = EmptyFilm(4, 1, true, true), b = EmptyFilm(4, 1, true, true);
  a.count[1] = b.count[1] = 3;
  a.evenCount[1] = 2;
  b.evenCount[1] = 1;
  a.evenSum[1] = vec3(1.0f);
  b.evenSum[1] = vec3(0.5f);
  MergeFilmInto(a, b);
  EXPECT_EQ(a.evenCount[1], 3u);
  EXPECT_EQ(a.evenSum[1], vec3(1.5f));
  FilmState noHalves = EmptyFilm(4, 1, true, false);
  EXPECT_THROW(MergeFilmInto(noHalves, b), std::invalid_argument);
}

// With no bounce (max depth 0) all the film holds is the emission the camera rays saw: its
// means are the image's, the residual has no variance, though the light's edge pixels do
// (some samples see the light, some not), and the denoiser, which filters only the
// residual, gives the raw image back bit for bit.
TEST(HalfFilms, WithoutBouncesAllIsSeenEmissionAndTheDenoiserKeepsIt) {
  SceneDesc d = LoadScene(SourcePath("scenes/cornell_box.json"));
  d.render.width = 24;
  d.render.height = 20;
  d.render.spp = 6;
  d.render.maxDepth = 0;
  FilmImage img = RenderOnCpu(BuildScene(std::move(d)), Halves()).image;
  ASSERT_EQ(img.emission.size(), img.rgb.size());
  EXPECT_TRUE(BitIdentical(img.emission, img.rgb));
  EXPECT_TRUE(BitIdentical(img.evenEmission, img.evenRgb));
  float lit = 0.0f, edgeVariance = 0.0f;
  for (size_t i = 0; i < img.rgb.size(); ++i) {
    lit = std::max(lit, img.rgb[i]);
    edgeVariance = std::max(edgeVariance, img.variance[i]);
    EXPECT_EQ(img.residualVariance[i], 0.0f) << i;
  }
  EXPECT_GT(lit, 1.0f);           // the camera sees the light
  EXPECT_GT(edgeVariance, 0.1f);  // and its edge is noisy
  DenoiseSettings keep;
  keep.keepSeenEmission = true;
  MakeCpuDenoiser(2, keep)->Denoise(img);
  EXPECT_TRUE(BitIdentical(img.denoised, img.rgb));
}

// A film kept without halves cannot continue as one with them (a resumed --denoise render).
TEST(HalfFilms, LoadingAFilmWithoutHalvesIsRefused) {
  RenderOptions plain;
  plain.featureBuffers = true;
  Scene scene = BoxScene(2);
  std::unique_ptr<RenderSession> without = MakeCpuSession(scene, plain);
  without->RenderUpTo(1);
  std::unique_ptr<RenderSession> with = MakeCpuSession(scene, Halves());
  try {
    with->LoadFilm(without->SaveFilm());
    FAIL() << "loaded";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--denoise"), std::string::npos) << e.what();
  }
}

// The camera looks at a mirror (F0 0.9) that shows a red wall behind the camera, 5 + 8 units
// away: the features are the wall's (its albedo tinted by the mirror, its normal, the whole
// distance), not the mirror's. Through a smooth glass pane the features are those of the
// green wall behind it, when the sample is transmitted, as most are.
TEST(FeatureBuffers, LookThroughMirrorsAndSmoothGlass) {
  Scene mirror = SceneFromJson(R"({
    "render": {"width": 8, "height": 8, "spp": 4, "max_depth": 3},
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 10},
    "materials": {"mirror": {"type": "conductor", "albedo": [0.9, 0.9, 0.9], "roughness": 0},
                  "red": {"type": "diffuse", "albedo": [0.8, 0.2, 0.1]}},
    "objects": [
      {"type": "quad", "origin": [-2, -2, 0], "u": [4, 0, 0], "v": [0, 4, 0], "material": "mirror"},
      {"type": "quad", "origin": [-5, -5, 8], "u": [0, 10, 0], "v": [10, 0, 0], "material": "red"}]
  })");
  RenderOptions o;
  o.featureBuffers = true;
  FilmImage img = RenderOnCpu(mirror, o).image;
  size_t c = 4 * 8 + 4;
  EXPECT_NEAR(img.albedo[3 * c], 0.8f * 0.9f, 0.01f);
  EXPECT_NEAR(img.albedo[3 * c + 1], 0.2f * 0.9f, 0.005f);
  EXPECT_NEAR(img.depth[c], 13.0f, 0.05f);
  EXPECT_LT(img.normal[3 * c + 2], -0.99f);  // the wall's normal, facing the mirror (-z)

  Scene glass = SceneFromJson(R"({
    "render": {"width": 8, "height": 8, "spp": 64, "max_depth": 6},
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 10},
    "materials": {"glass": {"type": "dielectric", "ior": 1.5, "roughness": 0},
                  "green": {"type": "diffuse", "albedo": [0.1, 0.7, 0.2]}},
    "objects": [
      {"type": "box", "min": [-2, -2, -0.05], "max": [2, 2, 0.05], "material": "glass"},
      {"type": "quad", "origin": [-5, -5, -3], "u": [10, 0, 0], "v": [0, 10, 0], "material": "green"}]
  })");
  img = RenderOnCpu(glass, o).image;
  // About 92% of the samples pass both faces (the rest reflect to the black background).
  EXPECT_GT(img.albedo[3 * c + 1], 0.7f * 0.8f);
  EXPECT_LT(img.albedo[3 * c], 0.1f + 0.02f);
  EXPECT_GT(img.depth[c], 0.8f * 8.0f);
}

}  // namespace
}  // namespace pt::test
