// Resuming renders with the built binary: a render stopped by SIGTERM, or killed outright after
// a checkpoint, and resumed with --resume ends bit for bit where the uninterrupted render does
// (CPU); a resume against another scene, size, crop, seed or setting is refused with exit
// status 2 and nothing written.
#include <gtest/gtest.h>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "src/io/film_state_exr.h"
#include "src/io/image_io.h"
#include "tests/cli_test_util.h"

namespace pt {
namespace {

namespace fs = std::filesystem;
using test::ReadText;
using test::RunPathtracer;
using test::WriteText;

// Many waves (100 paths each over 256 pixels, so a stop leaves pixels one sample apart) and
// enough samples that the interrupted runs stop well before the end.
const std::string kLong = " --backend cpu --threads 2 --spp 4000 --max-paths 100 --quiet";

class CliResume : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::TempDir();
    scene_ = WriteText(dir_ + "/tiny.json", test::kTinyScene);
  }
  // Renders into dir_/NAME.pfm and dir_/NAME.exr with extra arguments; returns the status.
  int Render(const std::string& name, const std::string& extra, std::string* out) {
    return RunPathtracer(scene_ + Outputs(name) + extra, out);
  }
  std::string Outputs(const std::string& name) const {
    return " -o " + dir_ + "/" + name + ".pfm --hdr " + dir_ + "/" + name + ".exr";
  }
  std::string dir_, scene_;
};

// Every channel a --hdr EXR holds, compared bit for bit.
void ExpectSameExr(const std::string& a, const std::string& b) {
  for (const char* channel : {"R", "G", "B", "samples", "variance.R", "variance.G",
                              "variance.B", "albedo.R", "normal.Y", "Z"}) {
    int w = 0, h = 0;
    EXPECT_EQ(ReadExrChannel(a, channel, &w, &h), ReadExrChannel(b, channel, &w, &h)) << channel;
  }
}

TEST_F(CliResume, InterruptedAndKilledRendersResumeToTheUninterruptedImage) {
  std::string out;
  ASSERT_EQ(Render("full", kLong, &out), 0) << out;

  // SIGTERM once the render is under way (its first preview is on disk).
  std::string stopped = dir_ + "/stopped.exr";
  ASSERT_EQ(test::RunPathtracerAndSignal(scene_ + Outputs("stopped") + kLong +
                                             " --preview-every 0.05",
                                         dir_ + "/stopped.pfm", "TERM", &out),
            143)
      << out;
  ResumableExr state = ReadResumableExr(stopped);
  uint32_t lo = *std::min_element(state.film.count.begin(), state.film.count.end());
  uint32_t hi = *std::max_element(state.film.count.begin(), state.film.count.end());
  EXPECT_LT(hi, 4000u) << "the render finished before the signal: nothing was resumed";
  EXPECT_LE(hi, lo + 1);
  std::string stats = dir_ + "/resumed.json";
  ASSERT_EQ(Render("resumed", kLong + " --resume " + stopped + " --stats-json " + stats, &out),
            0)
      << out;
  EXPECT_EQ(ReadText(dir_ + "/resumed.pfm"), ReadText(dir_ + "/full.pfm"));
  ExpectSameExr(dir_ + "/resumed.exr", dir_ + "/full.exr");
  nlohmann::json j = nlohmann::json::parse(ReadText(stats));
  EXPECT_EQ(j["resumed"]["file"], stopped);
  uint64_t before = j["resumed"]["samples_before"];
  EXPECT_GT(before, 0u);
  EXPECT_EQ(before + j["samples"].get<uint64_t>(), 16u * 16u * 4000u);
  EXPECT_EQ(j["stop_reason"], "completed");

  // Killed outright (no chance to write) after its first checkpoint: the checkpoint resumes.
  std::string checkpoint = dir_ + "/killed.exr";
  ASSERT_EQ(test::RunPathtracerAndSignal(scene_ + Outputs("killed") + kLong +
                                             " --checkpoint-every 0.05",
                                         checkpoint, "KILL", &out),
            137)
      << out;
  ASSERT_EQ(Render("from_checkpoint", kLong + " --resume " + checkpoint, &out), 0) << out;
  EXPECT_EQ(ReadText(dir_ + "/from_checkpoint.pfm"), ReadText(dir_ + "/full.pfm"));
}

TEST_F(CliResume, MoreSamplesContinueACompletedCheckpoint) {
  std::string out;
  const std::string cpu = " --backend cpu --threads 2 --quiet";
  ASSERT_EQ(Render("four", cpu + " --spp 4", &out), 0) << out;
  ASSERT_EQ(Render("two", cpu + " --spp 2 --checkpoint-every 1000", &out), 0) << out;
  EXPECT_NE(out.find("(resumable: --resume"), std::string::npos) << out;
  ASSERT_EQ(Render("more", cpu + " --spp 4 --resume " + dir_ + "/two.exr", &out), 0) << out;
  EXPECT_EQ(ReadText(dir_ + "/more.pfm"), ReadText(dir_ + "/four.pfm"));
  // A double-precision film continues exactly as well.
  const std::string dbl = cpu + " --film double";
  ASSERT_EQ(Render("four_d", dbl + " --spp 4", &out), 0) << out;
  ASSERT_EQ(Render("two_d", dbl + " --spp 2 --checkpoint-every 1000", &out), 0) << out;
  ASSERT_EQ(Render("more_d", dbl + " --spp 4 --resume " + dir_ + "/two_d.exr", &out), 0) << out;
  EXPECT_EQ(ReadText(dir_ + "/more_d.pfm"), ReadText(dir_ + "/four_d.pfm"));
  // So does a Sobol film: the samples it adds continue each pixel's sequence.
  const std::string sobol = cpu + " --sampler sobol";
  ASSERT_EQ(Render("four_s", sobol + " --spp 4", &out), 0) << out;
  ASSERT_EQ(Render("two_s", sobol + " --spp 2 --checkpoint-every 1000", &out), 0) << out;
  ASSERT_EQ(Render("more_s", sobol + " --spp 4 --resume " + dir_ + "/two_s.exr", &out), 0)
      << out;
  EXPECT_EQ(ReadText(dir_ + "/more_s.pfm"), ReadText(dir_ + "/four_s.pfm"));
  EXPECT_NE(ReadText(dir_ + "/four_s.pfm"), ReadText(dir_ + "/four.pfm"));
  // Fewer samples than the film holds cannot be had.
  ASSERT_EQ(Render("fewer", cpu + " --spp 1 --resume " + dir_ + "/two.exr", &out), 2) << out;
  EXPECT_NE(out.find("hold up to 2 samples, more than the 1 spp"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir_ + "/fewer.pfm"));
}

TEST_F(CliResume, AnotherSceneSizeCropSeedOrSettingIsRefused) {
  std::string out;
  const std::string cpu = " --backend cpu --threads 2 --quiet --spp 2";
  ASSERT_EQ(Render("state", cpu + " --checkpoint-every 1000", &out), 0) << out;
  std::string resume = " --resume " + dir_ + "/state.exr";
  struct Case {
    std::string extra, expected;
  };
  for (const Case& c : std::vector<Case>{
           {" --seed 2", "seed: 1 in the checkpoint, 2 now"},
           {" --width 12", "image size: 16x16 in the checkpoint, 12x16 now"},
           {" --crop 0 0 8 8", "crop window"},
           {" --max-depth 5", "max depth"},
           {" --integrator bsdf", "integrator"},
           {" --clamp 3", "firefly clamp"},
           {" --light-paths direct", "light paths"},
           {" --env-strength 2", "environment (--env, --env-strength): the scene's in the "
                                 "checkpoint, the scene's, strength 2.0 now"},
           {" --env-sampling uniform", "environment sampling"},
           {" --sampler sobol", "sampler (--sampler): independent in the checkpoint, sobol now"},
       }) {
    SCOPED_TRACE(c.extra);
    EXPECT_EQ(Render("refused", cpu + resume + c.extra, &out), 2) << out;
    EXPECT_NE(out.find(dir_ + "/state.exr: cannot resume: it is a render of another scene or "
                              "with other settings:"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find(c.expected), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir_ + "/refused.pfm"));
  }
  // The scene file edited (the lamp brighter).
  std::string text = test::kTinyScene;
  text.replace(text.find("[5, 5, 5]"), 9, "[6, 6, 6]");
  WriteText(scene_, text);
  EXPECT_EQ(Render("refused", cpu + resume, &out), 2) << out;
  EXPECT_NE(out.find("scene files (the scene and the files it names, by content): changed"),
            std::string::npos)
      << out;
  // An EXR that is an image only.
  WriteText(scene_, test::kTinyScene);
  ASSERT_EQ(Render("plain", cpu, &out), 0) << out;
  EXPECT_EQ(Render("refused", cpu + " --resume " + dir_ + "/plain.exr", &out), 2) << out;
  EXPECT_NE(out.find("plain.exr: has no resumable state"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir_ + "/refused.pfm"));
  // The untouched scene resumes.
  EXPECT_EQ(Render("accepted", cpu + resume, &out), 0) << out;
}

// A mesh the scene names is part of its identity: editing the OBJ refuses the resume.
TEST_F(CliResume, AnEditedMeshFileIsAnotherScene) {
  WriteText(dir_ + "/tri.obj", "v -1 0 -1\nv 1 0 -1\nv 0 0 1\nf 1 3 2\n");
  std::string text = test::kTinyScene;
  text.replace(text.find("\"objects\": ["), 12,
               R"("objects": [{"type": "mesh", "file": "tri.obj", "material": "white"},)");
  WriteText(scene_, text);
  std::string out;
  const std::string cpu = " --backend cpu --threads 2 --quiet --spp 2";
  ASSERT_EQ(Render("state", cpu + " --checkpoint-every 1000", &out), 0) << out;
  WriteText(dir_ + "/tri.obj", "v -1 0 -1\nv 1 0 -1\nv 0 0.5 1\nf 1 3 2\n");
  EXPECT_EQ(Render("refused", cpu + " --resume " + dir_ + "/state.exr", &out), 2) << out;
  EXPECT_NE(out.find("scene files"), std::string::npos) << out;
}

TEST_F(CliResume, AdaptiveRendersAreNotResumableYet) {
  std::string out;
  const std::string cpu = " --backend cpu --threads 2 --quiet --spp 2 --adaptive on";
  ASSERT_EQ(Render("state", cpu + " --checkpoint-every 1000", &out), 0) << out;
  EXPECT_EQ(Render("refused", cpu + " --resume " + dir_ + "/state.exr", &out), 2) << out;
  EXPECT_NE(out.find("resuming an adaptive render is not supported yet"), std::string::npos)
      << out;
}

}  // namespace
}  // namespace pt
