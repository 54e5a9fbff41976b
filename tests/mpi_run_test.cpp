// `mpirun -np N pathtracer ...` end to end, with CPU ranks (oversubscribed on a small
// machine): the same image as one process, bit for bit where the chunk tree is the same; and
// a time limit, a failing, killed, interrupted or silent rank each end the job with a clear
// message, the image so far and no hang. Skipped in a build without MPI, where a start by
// an MPI launcher must be refused instead.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>

#include <nlohmann/json.hpp>

#include "src/integrator/render_api.h"
#include "src/io/image_io.h"
#include "tests/test_util.h"

namespace pt {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

#if defined(PT_MPIEXEC)
constexpr const char* kMpiexec = PT_MPIEXEC;
#else
constexpr const char* kMpiexec = "";
#endif

// Small, CPU-only, one thread a rank: two or three ranks fit the 2-core CI machine.
const std::string kBox = " --backend cpu --threads 1 --quiet --width 32 --height 24";

std::string Launcher(int ranks) {
  return std::string(kMpiexec) + " --oversubscribe" + (geteuid() == 0 ? " --allow-run-as-root" : "") +
         " -np " + std::to_string(ranks) + " ";
}

std::string Pathtracer(const std::string& args) {
  return test::BinaryPath("pathtracer") + " " + test::SourcePath("scenes/cornell_box.json") +
         " " + args;
}

// Every channel of two EXR files, compared bit for bit.
void ExpectBitIdenticalExr(const std::string& a, const std::string& b) {
  for (const char* c : {"R", "G", "B", "variance.R", "variance.G", "variance.B", "samples",
                        "albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z",
                        "Z"}) {
    int w = 0, h = 0;
    std::vector<float> x = ReadExrChannel(a, c, &w, &h), y = ReadExrChannel(b, c, &w, &h);
    ASSERT_EQ(x.size(), y.size()) << c;
    EXPECT_EQ(std::memcmp(x.data(), y.data(), x.size() * sizeof(float)), 0)
        << "channel " << c << " of " << a << " and " << b;
  }
}

class MpiRun : public ::testing::Test {
 protected:
  void SetUp() override {
#if !defined(PT_HAVE_MPI)
    GTEST_SKIP() << "built without MPI";
#endif
    if (!fs::exists(kMpiexec)) GTEST_SKIP() << "no mpiexec at " << kMpiexec;
    dir_ = test::TempDir();
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  int Run(int ranks, const std::string& args, std::string* out) {
    return test::RunCommand(Launcher(ranks) + Pathtracer(args), out);
  }
  std::string Path(const std::string& name) const { return dir_ + "/" + name; }
  std::string dir_;
};

TEST_F(MpiRun, TwoAndThreeRanksGiveTheBitsOfOneProcessWithTheSameChunks) {
  std::string out;
  std::string common = kBox + " --spp 6 --chunks 6";
  ASSERT_EQ(test::RunCommand(Pathtracer("-o " + Path("one.png") + " --hdr " + Path("one.exr") +
                                        common), &out), 0) << out;
  ASSERT_EQ(Run(2, "-o " + Path("two.png") + " --hdr " + Path("two.exr") + common, &out), 0)
      << out;
  ASSERT_EQ(Run(3, "-o " + Path("three.png") + " --hdr " + Path("three.exr") + common, &out), 0)
      << out;
  ExpectBitIdenticalExr(Path("one.exr"), Path("two.exr"));
  ExpectBitIdenticalExr(Path("one.exr"), Path("three.exr"));
  EXPECT_EQ(test::ReadText(Path("one.png")), test::ReadText(Path("two.png")));
}

TEST_F(MpiRun, OneRankIsAPlainRunAndTwoDifferFromItOnlyByRounding) {
  std::string out, common = kBox + " --spp 6";
  ASSERT_EQ(test::RunCommand(Pathtracer("-o " + Path("plain.pfm") + " --hdr " +
                                        Path("plain.exr") + common), &out), 0) << out;
  ASSERT_EQ(Run(1, "-o " + Path("np1.pfm") + " --hdr " + Path("np1.exr") + common, &out), 0)
      << out;
  ExpectBitIdenticalExr(Path("plain.exr"), Path("np1.exr"));
  // Two ranks take the default chunks, min(32, spp) = 6: the bits of one process with those.
  ASSERT_EQ(Run(2, "-o " + Path("np2.pfm") + " --hdr " + Path("np2.exr") + " --stats-json " +
                       Path("np2.json") + common, &out), 0) << out;
  ASSERT_EQ(test::RunCommand(Pathtracer("-o " + Path("ch6.pfm") + " --hdr " + Path("ch6.exr") +
                                        common + " --chunks 6"), &out), 0) << out;
  ExpectBitIdenticalExr(Path("ch6.exr"), Path("np2.exr"));
  // Against the plain render: float Welford over n samples errs by at most ~n * eps * the
  // largest sample, which is at most |mean| + sqrt(variance * (n - 1)).
  int w = 0, h = 0;
  std::vector<float> plain, split;
  ReadExrRgb(Path("plain.exr"), &w, &h, &plain);
  ReadExrRgb(Path("np2.exr"), &w, &h, &split);
  size_t differing = 0;
  for (int c = 0; c < 3; ++c) {
    std::vector<float> var = ReadExrChannel(Path("plain.exr"), std::string("variance.") + "RGB"[c], &w, &h);
    for (size_t p = 0; p < var.size(); ++p) {
      double x = plain[3 * p + c], y = split[3 * p + c];
      double tolerance = 4.0 * 6 * std::ldexp(1.0, -24) * (std::abs(x) + std::sqrt(var[p] * 5));
      EXPECT_LE(std::abs(x - y), tolerance) << "pixel " << p << " channel " << c;
      differing += x != y;
    }
  }
  EXPECT_GT(differing, 0u);  // the split does round differently
  nlohmann::json stats = nlohmann::json::parse(test::ReadText(Path("np2.json")));
  const nlohmann::json& mpi = stats.at("mpi");
  EXPECT_EQ(mpi.at("ranks"), 2);
  EXPECT_EQ(mpi.at("chunks"), 6);
  ASSERT_EQ(mpi.at("per_rank").size(), 2u);
  int leaves = 0;
  for (const auto& r : mpi.at("per_rank")) leaves += r.at("leaves").get<int>();
  EXPECT_EQ(leaves, 6);
  EXPECT_EQ(stats.at("samples"), 32 * 24 * 6);
  EXPECT_GT(mpi.at("load_balance").get<double>(), 0.0);
  EXPECT_LE(mpi.at("load_balance").get<double>(), 1.0);
}

TEST_F(MpiRun, TheTimeLimitEndsEveryRankWithTheImageSoFar) {
  std::string out;
  auto t0 = Clock::now();
  ASSERT_EQ(Run(2, "-o " + Path("t.png") + " --stats-json " + Path("t.json") + kBox +
                       " --spp 1000000 --time-limit 1", &out), 0) << out;
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 30.0);
  nlohmann::json stats = nlohmann::json::parse(test::ReadText(Path("t.json")));
  EXPECT_GT(stats.at("spp_mean").get<double>(), 0.0);
  EXPECT_LT(stats.at("spp_mean").get<double>(), 1000000.0);
  EXPECT_TRUE(stats.at("mpi").at("time_limited").get<bool>());
  EXPECT_TRUE(fs::exists(Path("t.png")));
}

TEST_F(MpiRun, AFailingRankEndsTheJobWithItsMessageAndTheImageSoFar) {
  std::string out;
  // Rank 1 fails on its first leaf: a leaf is granted to it (its own range) unless rank 0
  // has rendered all 16 (~0.1 s) before rank 1's first request arrives.
  int status = test::RunCommand("PT_FAULT_INJECT=throw:1:0 " + Launcher(2) +
                                    "-x PT_FAULT_INJECT " +
                                    Pathtracer("-o " + Path("f.png") + " --hdr " + Path("f.exr") +
                                               " --stats-json " + Path("f.json") + kBox +
                                               " --spp 32 --chunks 16"),
                                &out);
  EXPECT_EQ(status, 3) << out;
  EXPECT_NE(out.find("rank 1: injected failure"), std::string::npos) << out;
  int w = 0, h = 0;
  std::vector<float> samples = ReadExrChannel(Path("f.exr"), "samples", &w, &h);
  double mean = 0.0;
  for (float s : samples) mean += s / samples.size();
  EXPECT_GT(mean, 0.0);
  EXPECT_LT(mean, 32.0);  // the leaf rank 1 failed on is missing
  nlohmann::json stats = nlohmann::json::parse(test::ReadText(Path("f.json")));
  EXPECT_EQ(stats.at("stop_reason"), "failed");
  EXPECT_TRUE(stats.at("interrupted").get<bool>());
  EXPECT_NE(stats.at("mpi").at("ended_early").get<std::string>().find("rank 1"),
            std::string::npos);
}

// mpirun in the background, its output in a file; finds a rank's process to signal.
class Background {
 public:
  explicit Background(const std::string& command, const std::string& log) {
    pid_ = fork();
    if (pid_ == 0) {
      setpgid(0, 0);
      execl("/bin/sh", "sh", "-c", ("exec " + command + " > " + log + " 2>&1").c_str(),
            (char*)nullptr);
      _exit(127);
    }
  }
  ~Background() {
    if (pid_ > 0 && !reaped_) {
      kill(-pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  // The pid of the child of mpirun whose environment names this rank; 0 if none (yet).
  pid_t RankPid(int rank) const {
    std::string want = "OMPI_COMM_WORLD_RANK=" + std::to_string(rank);
    for (const auto& entry : fs::directory_iterator("/proc")) {
      std::string name = entry.path().filename();
      if (name.find_first_not_of("0123456789") != std::string::npos) continue;
      std::string stat = test::ReadText(entry.path() / "stat");
      size_t close = stat.rfind(')');
      if (close == std::string::npos) continue;
      int ppid = 0;
      if (std::sscanf(stat.c_str() + close + 1, " %*c %d", &ppid) != 1 || ppid != pid_) continue;
      std::string env = test::ReadText(entry.path() / "environ");
      for (size_t at = 0; at < env.size(); at = env.find('\0', at) + 1) {
        if (env.compare(at, want.size() + 1, want + '\0') == 0) return pid_t(std::stoi(name));
        if (env.find('\0', at) == std::string::npos) break;
      }
    }
    return 0;
  }
  // CPU seconds a process has used (0 if it is gone).
  static double CpuSeconds(pid_t pid) {
    std::string stat = test::ReadText("/proc/" + std::to_string(pid) + "/stat");
    size_t close = stat.rfind(')');
    unsigned long user = 0, system = 0;
    if (close == std::string::npos ||
        std::sscanf(stat.c_str() + close + 1, " %*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %lu %lu",
                    &user, &system) != 2)
      return 0.0;
    return double(user + system) / double(sysconf(_SC_CLK_TCK));
  }
  // The exit status (128 + signal when killed), or -1 after `seconds` (then it is killed).
  int Wait(double seconds) {
    auto t0 = Clock::now();
    while (std::chrono::duration<double>(Clock::now() - t0).count() < seconds) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        reaped_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
  bool reaped_ = false;
};

// Starts a long render, waits until rank 0 has begun it, signals rank 1, and returns the
// job's exit status and output.
int SignalRankOne(MpiRun& test, const std::string& dir, int signal, const std::string& extra,
                  std::string* out) {
  std::string log = dir + "/log.txt";
  Background job(Launcher(2) + Pathtracer("-o " + dir + "/k.png" + kBox +
                                          " --spp 1000000 --time-limit 60" + extra),
                 log);
  // Rank 1 is rendering once it has used more CPU than its start-up does (a rank killed
  // during start-up would take the others down inside a collective, with nothing to write).
  auto t0 = Clock::now();
  pid_t rank1 = 0;
  while ((rank1 == 0 || Background::CpuSeconds(rank1) < 0.5) &&
         std::chrono::duration<double>(Clock::now() - t0).count() < 30.0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (rank1 == 0) rank1 = job.RankPid(1);
  }
  EXPECT_GT(rank1, 0) << "no rank 1 process found";
  if (rank1 > 0) kill(rank1, signal);
  int status = job.Wait(30.0);
  *out = test::ReadText(log);
  return status;
}

TEST_F(MpiRun, AKilledRankEndsTheJobAndRankZeroWritesTheImageSoFar) {
  std::string out;
  int status = SignalRankOne(*this, dir_, SIGKILL, "", &out);
  EXPECT_NE(status, 0) << out;
  EXPECT_NE(status, -1) << "the job hung: " << out;
  EXPECT_NE(out.find("the samples of rank(s) 1 did not arrive"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir_ + "/k.png")) << out;
}

TEST_F(MpiRun, SigtermOnOneRankEndsTheJobAsInterrupted) {
  std::string out;
  // Any rank's stop signal N ends the job as a plain run's would: exit 128 + N.
  EXPECT_EQ(SignalRankOne(*this, dir_, SIGTERM, "", &out), 128 + SIGTERM) << out;
  EXPECT_NE(out.find("rank 1 was interrupted"), std::string::npos) << out;
  EXPECT_NE(out.find("(stopped by SIGTERM)"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir_ + "/k.png")) << out;
}

TEST_F(MpiRun, ASilentRankIsGivenUpAfterTheRankTimeout) {
  std::string out;
  EXPECT_EQ(SignalRankOne(*this, dir_, SIGSTOP, " --rank-timeout 1", &out), 3) << out;
  EXPECT_NE(out.find("rank 1 has not answered"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir_ + "/k.png")) << out;
}

TEST_F(MpiRun, WhatTheSplitCannotDoIsRefusedOnEveryRank) {
  std::string out, o = " -o " + Path("x.png") + kBox + " --spp 4";
  EXPECT_EQ(Run(2, o + " --adaptive on", &out), 1) << out;
  EXPECT_NE(out.find("adaptive sampling is not supported across MPI ranks"), std::string::npos)
      << out;
  EXPECT_EQ(Run(2, o + " --chunks 5", &out), 1) << out;
  EXPECT_EQ(Run(2, o + " --resume " + Path("state.exr"), &out), 1) << out;
  EXPECT_NE(out.find("--resume is not supported across MPI ranks"), std::string::npos) << out;
  // Ranks told different things (MPMD): refused, not a silently wrong image.
  EXPECT_EQ(test::RunCommand(Launcher(1) + Pathtracer(o) + " : -np 1 " + Pathtracer(o + " --seed 9"),
                             &out),
            1)
      << out;
  EXPECT_NE(out.find("rank 1's scene or settings differ from rank 0's"), std::string::npos) << out;
  if (CudaDeviceCount() == 0) {  // a rank whose GPU is missing fails the job before it starts
    EXPECT_EQ(test::RunCommand(Launcher(1) + Pathtracer(o) + " : -np 1 " +
                                   Pathtracer(o + " --backend cuda"),
                               &out),
              3)
        << out;
    EXPECT_NE(out.find("rank 1: "), std::string::npos) << out;
  }
  EXPECT_FALSE(fs::exists(Path("x.png")));
}

// --chunks needs no MPI: what a chunked film cannot do is refused in one process too, before
// anything is written.
TEST(ChunkedRun, WhatAChunkedFilmCannotDoIsRefusedInOneProcess) {
  std::string out, dir = test::TempDir(), png = dir + "/x.png";
  std::string o = "-o " + png + kBox + " --spp 4 --chunks 2";
  auto refused = [&](const std::string& extra, const std::string& what) {
    EXPECT_EQ(test::RunCommand(Pathtracer(o + extra), &out), 1) << extra << ": " << out;
    EXPECT_NE(out.find(what + " is not supported with --chunks"), std::string::npos) << out;
  };
  refused(" --adaptive on", "adaptive sampling");
  refused(" --preview-every 1", "--preview-every");
  refused(" --hdr " + dir + "/x.exr --checkpoint-every 5", "--checkpoint-every");
  refused(" --resume " + dir + "/state.exr", "--resume");
  EXPECT_EQ(test::RunCommand(Pathtracer(o + " --chunks 5"), &out), 1) << out;
  EXPECT_NE(out.find("--chunks 5 is more than the 4 samples per pixel"), std::string::npos)
      << out;
  EXPECT_FALSE(fs::exists(png));
  EXPECT_FALSE(fs::exists(dir + "/x.exr"));
  fs::remove_all(dir);
}

#if !defined(PT_HAVE_MPI)
TEST(NoMpiBuild, AStartByAnMpiLauncherIsRefused) {
  std::string out, dir = test::TempDir(), png = dir + "/x.png";
  int status = test::RunCommand("OMPI_COMM_WORLD_SIZE=2 " + Pathtracer("-o " + png + kBox),
                                &out);
  EXPECT_EQ(status, 3) << out;
  EXPECT_NE(out.find("this build has no MPI support"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(png));
  EXPECT_EQ(test::RunCommand(Pathtracer("-o " + png + kBox + " --rank-timeout 5"), &out), 1)
      << out;
  EXPECT_EQ(test::RunCommand(Pathtracer("-o " + png + kBox + " --lanes 2"), &out), 1) << out;
  EXPECT_FALSE(fs::exists(png));
  fs::remove_all(dir);
}
#endif

}  // namespace
}  // namespace pt
