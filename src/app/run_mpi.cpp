// The program as one rank of an MPI job (`mpirun -np N pathtracer SCENE -o OUT ...`). Every
// rank parses the command line, loads the scene and makes its render lanes; the ranks agree
// on each step (one rank's failure ends all, with its message printed once, by rank 0);
// RenderDistributed splits the samples; rank 0 writes every output and the statistics.
#include <malloc.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>
#include <new>
#include <optional>
#include <thread>

#include "src/app/app_failure.h"
#include "src/app/denoise_step.h"
#include "src/app/device_start.h"
#include "src/app/outputs.h"
#include "src/app/progress.h"
#include "src/app/render_job.h"
#include "src/app/run_steps.h"
#include "src/app/run_timeline.h"
#include "src/app/stats_json.h"
#include "src/app/stop_signals.h"
#include "src/distributed/distributed.h"
#include "src/distributed/fault_injection.h"
#include "src/integrator/wave_plan.h"
#include "src/io/image_io.h"
#include "src/scene/scene_checks.h"

namespace pt {

namespace {

// This rank's share of its host's cores: the cores mpirun bound it to, else an even share.
// mpirun binds each of one or two ranks to a single core by default, which starves the
// lanes and merge threads: say so.
unsigned CoresForThisRank(const MpiJob& job) {
  unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  unsigned share = std::max(1u, cores / unsigned(job.LocalSize()));
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return share;
  unsigned allowed = unsigned(std::max(1, CPU_COUNT(&set)));
  if (allowed == 1 && share > 1) {
    std::fprintf(stderr,
                 "pathtracer: warning: rank %d is bound to one core; pass --bind-to none (or "
                 "--map-by ...:pe=N) to mpirun\n",
                 job.Rank());
  }
  return std::min(share, allowed);
}

// What a rank renders with.
struct RankSetup {
  std::optional<Scene> scene;
  RenderOptions options;
  SessionFactory factory = nullptr;
  DistributedOptions distributed;
  AppTimes times;
  double mpiInitMs = 0.0;
  std::unique_ptr<Denoiser> denoiser;  // rank 0 with --denoise: once, on the merged film
  double deviceProbeMs = 0.0;  // ChooseBackend: the driver's start and the device count
};

RankSetup SetUp(const MpiJob& job, const CliOptions& cli, const AppBackends& backends,
                DeviceStart* device) {
  RankSetup s;
  if (job.Rank() == 0) CheckOutputsWritable(cli);
  s.scene.emplace(Build(LoadAndOverride(cli, &s.times.loadMs),
                        ChooseBvh(cli, backends, device, job.LocalRank(), &s.times.bvhOnDevice),
                        &s.times.bvhBuildMs));
  s.times.bvhBuilder = BuilderThatRan(cli, s.times.bvhOnDevice);
  const AppClock::time_point probe = AppClock::now();
  BackendKind backend = ChooseBackend(cli.backend, backends, device);
  s.deviceProbeMs = MsSince(probe);
  s.times.deviceStartBackgroundMs = device->BackgroundMs();
  s.factory = backend == BackendKind::kCuda ? backends.cudaSession : backends.cpuSession;
  s.options = MakeRenderOptions(cli, backend, nullptr);
  CheckChunkOptions(cli, *s.scene, s.options, true);
  s.options.timeLimitSeconds = 0.0;  // rank 0 keeps the time for the whole job
  unsigned coresPerRank = CoresForThisRank(job);
  DistributedOptions& d = s.distributed;
  d.chunks = uint32_t(cli.chunks.value_or(std::min(32, s.scene->desc.render.spp)));
  d.timeLimitSeconds = cli.timeLimitSeconds;
  d.rankTimeoutSeconds = cli.rankTimeoutSeconds.value_or(60.0);
  if (backend == BackendKind::kCuda) {
    int gpus = backends.cudaDeviceCount();
    s.options.device = job.LocalRank() % gpus;
    // Two lanes share the GPU, filling each other's idle gaps between kernels;
    // the host cores left over (past the lanes' and the main thread's) merge films.
    d.lanes = cli.lanes.value_or(2);
    d.mergeThreads = int(std::clamp(coresPerRank - 3, 1u, 16u));
  } else {
    if (cli.threads == 0) s.options.threads = int(coresPerRank);  // ranks of a host share it
    d.lanes = cli.lanes.value_or(1);
    d.mergeThreads = 1;
  }
  if (job.Rank() == 0)
    s.denoiser = MakeAppDenoiser(cli, s.scene->desc.render.sampler, backend, backends,
                                 s.options.device);
  return s;
}

// FNV-1a of what the image depends on: every rank must render the same scene and settings.
uint64_t Fingerprint(const Scene& scene, const RenderOptions& o, uint32_t chunks) {
  const RenderSettings& r = scene.desc.render;
  double geometry = 0.0;
  for (const Triangle& t : scene.desc.triangles) geometry += double(t.p0.x) + double(t.p1.y) + double(t.p2.z);
  std::string text = std::to_string(r.width) + " " + std::to_string(r.height) + " " +
                     std::to_string(r.spp) + " " + std::to_string(r.maxDepth) + " " +
                     std::to_string(r.seed) + " " + std::to_string(r.russianRouletteDepth) +
                     " " + std::to_string(o.crop.x0) + " " + std::to_string(o.crop.y0) + " " +
                     std::to_string(o.crop.x1) + " " + std::to_string(o.crop.y1) + " " +
                     std::to_string(chunks) + " " + std::to_string(int(o.integrator)) + " " +
                     std::to_string(int(o.lightPaths)) + " " + std::to_string(o.filmDouble) +
                     " " + std::to_string(o.featureBuffers) + " " +
                     std::to_string(o.rayOffsetEpsilon) + " " +
                     std::to_string(int(o.triangleTest)) + " " +
                     std::to_string(o.clampLuminance) + " " +
                     std::to_string(scene.TriangleCount()) + " " +
                     std::to_string(scene.PrimitiveCount()) + " " +
                     std::to_string(scene.lights.size()) + " " + std::to_string(geometry);
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  return h;
}

// The statistics of a distributed render: the one-process schema, with counters summed over
// ranks and the render time the job's, plus an "mpi" section per rank.
nlohmann::ordered_json MpiJson(const DistributedResult& r, int ranks, uint32_t chunks,
                               double mpiInitMs, bool features, bool halves) {
  nlohmann::ordered_json perRank = nlohmann::ordered_json::array();
  double lanesStartup = 0.0;
  for (const RankReport& rank : r.ranks) {
    perRank.push_back(nlohmann::ordered_json(RankReportToJson(rank)));
    lanesStartup = std::max(lanesStartup, rank.startupMs);
  }
  return {{"ranks", ranks},
          {"chunks", chunks},
          {"leaves_rendered", r.leavesRendered},
          {"render_ms", r.renderMs},
          {"reduction_ms", r.reductionMs},
          {"startup_ms", {{"mpi_init", mpiInitMs}, {"lanes", lanesStartup}}},
          {"load_balance", LoadBalance(r.ranks)},
          {"film_bytes_per_pixel", 60 + (features ? 28 : 0) + (halves ? 16 : 0)},
          {"interrupted", r.interrupted},
          {"time_limited", r.timeLimited},
          {"ended_early", r.why},
          {"per_rank", perRank}};
}

RenderStats SumOverRanks(const DistributedResult& r) {
  RenderStats sum;
  for (const RankReport& rank : r.ranks) {
    AddRenderStats(sum, rank.stats);
    if (sum.backend.empty()) sum.backend = rank.backend, sum.device = rank.device;
    if (sum.backend != rank.backend) sum.backend = "mixed";
  }
  if (r.ranks.size() > 1) sum.device = std::to_string(r.ranks.size()) + " ranks, rank 0: " + sum.device;
  sum.renderMs = r.renderMs;  // the job's wall time, as a rate's denominator
  sum.samples = r.samples;
  sum.interrupted = r.interrupted;
  return sum;
}

void PrintRanks(const DistributedResult& r) {
  for (const RankReport& rank : r.ranks) {
    std::fprintf(stderr,
                 "pathtracer: rank %d (%s, %s %s, %d lane%s): %d leaves, %.3g samples, "
                 "finished at %.3f s%s%s\n",
                 rank.rank, rank.host.c_str(), rank.backend.c_str(), rank.device.c_str(),
                 rank.lanes, rank.lanes == 1 ? "" : "s", rank.leaves, double(rank.samples),
                 rank.finishedMs / 1e3, rank.failure.empty() ? "" : "; failed: ",
                 rank.failure.c_str());
  }
  std::fprintf(stderr, "pathtracer: render %.3f s (reduction %.1f ms), load balance %.3f\n",
               r.renderMs / 1e3, r.reductionMs, LoadBalance(r.ranks));
}

// What the job did, as the one-process flow describes a render (summary line, stats).
JobOutcome Outcome(const DistributedResult& r) {
  JobOutcome out;
  out.result.image = ResolveFilmImage(r.film);
  out.result.stats = SumOverRanks(r);
  uint64_t filmSamples = 0;
  for (uint32_t c : out.result.image.samples) filmSamples += c;
  out.result.stats.sppMean = double(filmSamples) / double(std::max<size_t>(1, r.film.PixelCount()));
  out.signal = r.signal;
  if (r.status == kExitRuntimeFailure) out.reason = StopReason::kFailed;
  else if (r.interrupted) out.reason = StopReason::kSignal;
  else if (r.timeLimited) out.reason = StopReason::kTimeLimit;
  return out;
}

// Rank 0 after the render: the image so far (if any sample arrived), statistics, summary.
int FinishRoot(const CliOptions& cli, const RankSetup& s, const DistributedResult& r, int ranks,
               RunTimeline& timeline) {
  if (!r.why.empty()) {
    std::fprintf(stderr, "pathtracer: the render ended early: %s; %s\n", r.why.c_str(),
                 r.samples ? "writing the image so far" : "no samples, nothing written");
  }
  if (r.samples == 0) return r.status != 0 ? r.status : kExitRuntimeFailure;
  JobOutcome outcome = Outcome(r);
  AppTimes times = s.times;
  try {
    DenoiseImage(s.denoiser.get(), outcome.result.image, &times);
    if (s.denoiser) timeline.Mark("denoise");
  } catch (const AppFailure& f) {
    std::fprintf(stderr, "pathtracer: %s\n", f.message.c_str());
    return f.status;
  }
  std::vector<std::string> written;
  try {
    // No resumable state: a film of chunks is not a per-pixel prefix of the samples.
    written = WriteImages(cli, outcome.result.image, nullptr);
    timeline.Mark("output");
    if (!cli.statsJsonPath.empty()) {
      RunReport report = MakeReport(cli, *s.scene, outcome, s.options.backend);
      timeline.Mark("stats");
      times.timeline = &timeline;
      times.totalMs = timeline.TotalMs();
      nlohmann::ordered_json doc = StatsToJson(outcome.result.stats, *s.scene, times, report);
      doc["mpi"] = MpiJson(r, ranks, s.distributed.chunks, s.mpiInitMs,
                           s.options.featureBuffers, s.options.halfFilms);
      WriteStatsJson(cli.statsJsonPath, doc);
      written.push_back(cli.statsJsonPath);
    }
  } catch (const ImageError& e) {
    std::fprintf(stderr, "pathtracer: %s\n", e.what());
    return kExitRuntimeFailure;
  }
  PrintSummary(outcome);
  PrintRanks(r);
  PrintWritten(written, cli, false);
  return r.status;
}

// Every rank's outcome of a step; all return the worst status, printed once by rank 0.
std::optional<int> AgreeOn(MpiJob& job, int status, const std::string& message) {
  auto [worst, text] = job.Agree(status, message);
  if (worst == 0) return std::nullopt;
  if (job.Rank() == 0) std::fprintf(stderr, "pathtracer: %s\n", text.c_str());
  return worst;
}

// A rank allocates a film per leaf (60 bytes a pixel: 124 MB at 1080p) and frees it once
// merged. Kept in the heap instead of mapped and unmapped each time, the pages are not
// faulted in again: SaveFilm of a 1080p film took ~100 ms with fresh pages, ~20 ms reusing
// them (measured on this project's 2-core machine).
void KeepFreedMemory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
#endif
}

// The command line and this rank's set-up, agreed on by every rank: the job's exit status
// when it ends here (a bad command line, a failed set-up, --help), else nullopt.
std::optional<int> Prepare(MpiJob& job, int argc, const char* const* argv,
                           const AppBackends& backends, CliOptions* cli, RankSetup* s,
                           RunTimeline& timeline, std::optional<DeviceStart>* device) {
  bool root = job.Rank() == 0;
  int status = 0;
  std::string message;
  try {
    *cli = ParseCli(argc, argv);
  } catch (const CliError& e) {
    status = kExitBadCommandLine;
    message = std::string(e.what()) + " (see --help)";
  }
  if (std::optional<int> failed = AgreeOn(job, status, message)) return failed;
  if (cli->help || cli->version) {
    if (root && cli->help) std::fputs(CliUsage().c_str(), stdout);
    if (root && cli->version) std::printf("pathtracer %s\n", PT_VERSION);
    return kExitOk;
  }
  device->emplace(backends, cli->backend, job.LocalRank());  // beside loading and the BVH
  timeline.Mark("setup");
  try {
    *s = SetUp(job, *cli, backends, &**device);
  } catch (const AppFailure& f) {
    status = f.status, message = f.message;
  } catch (const OutOfDeviceMemory& e) {
    status = kExitRuntimeFailure, message = OutOfMemoryMessage(e, *cli);
  } catch (const std::bad_alloc&) {
    status = kExitRuntimeFailure, message = "out of memory";
  } catch (const std::exception& e) {
    status = kExitRuntimeFailure, message = e.what();
  }
  timeline.Mark("scene");
  timeline.Split("scene",
                 {{"load", s->times.loadMs}, {"bvh_build", s->times.bvhBuildMs},
                  {"device_start", s->deviceProbeMs}},
                 "scene_prep");
  if (std::optional<int> failed = AgreeOn(job, status, message)) return failed;
  std::vector<uint64_t> prints =
      job.AllGather(Fingerprint(*s->scene, s->options, s->distributed.chunks));
  for (size_t r = 1; r < prints.size(); ++r) {
    if (prints[r] == prints[0]) continue;
    if (root) std::fprintf(stderr, "pathtracer: rank %zu's scene or settings differ from rank 0's "
                                   "(every rank must render the same scene with the same options)\n", r);
    return kExitBadCommandLine;
  }
  return std::nullopt;
}

// Rank 0's part of the timeline spent in RenderDistributed: its lanes' start (sessions made,
// scene uploaded), the render until the last rank's last leaf, the reduction of the films to
// the root film, and the hand-over (waiting for every rank to be ready, the lanes' end).
void SplitDistributedTime(const DistributedResult& r, int rank, RunTimeline& timeline) {
  double lanesStart = 0.0;
  for (const RankReport& report : r.ranks) {
    if (report.rank == rank) lanesStart = report.startupMs;
  }
  timeline.Split("distributed",
                 {{"lanes_start", lanesStart}, {"render", r.renderMs - r.reductionMs},
                  {"reduction", r.reductionMs}},
                 "hand_over");
}

int RunRanks(MpiJob& job, int argc, const char* const* argv, const AppBackends& backends,
             AppClock::time_point start, double mpiInitMs) {
  bool root = job.Rank() == 0;
  RunTimeline timeline(start, "launch");  // the process's start, then MPI_Init
  timeline.Mark("launch");
  KeepFreedMemory();
  CliOptions cli;
  RankSetup s;
  std::optional<DeviceStart> device;
  if (std::optional<int> ended = Prepare(job, argc, argv, backends, &cli, &s, timeline, &device))
    return *ended;
  timeline.Mark("ranks_sync");
  s.mpiInitMs = mpiInitMs;
  InstallStopSignals();
  if (root) {
    for (const std::string& warning : DarkSceneWarnings(*s.scene)) Warn(warning);
    PrintEffects(*s.scene, cli.specialize);
  }
  ProgressReporter progress(cli.quiet || !root, cli.progressEverySeconds);
  uint64_t spp = uint64_t(s.scene->desc.render.spp);
  auto onProgress = [&](uint64_t done, uint64_t total) {  // total: pixels x spp
    progress.Update({done, done, total, std::max<uint64_t>(1, total / spp)});
  };
  DistributedResult r;
  try {
    r = RenderDistributed(job, InjectFaults(s.factory, job.Rank()), *s.scene, s.options,
                          s.distributed, onProgress, StopSignal);
  } catch (const std::exception& e) {
    progress.Finish();
    std::fprintf(stderr, "pathtracer: rank %d: %s; ending the job\n", job.Rank(), e.what());
    job.Abort(kExitRuntimeFailure);
  }
  progress.Finish();
  timeline.Mark("distributed");
  SplitDistributedTime(r, job.Rank(), timeline);
  int status = root ? FinishRoot(cli, s, r, job.Size(), timeline) : r.status;
  if (root && r.rankLost) {
    std::fprintf(stderr, "pathtracer: ending the job: a rank is not answering\n");
    job.Abort(status);
  }
  return job.ShareExitStatus(status, StopSignal);
}

}  // namespace

int RunMpiApp(int argc, const char* const* argv, const AppBackends& backends) {
  int announced = LauncherWorldSize();
  if (!MpiBuilt()) {
    if (announced == 1) return RunProcess(argc, argv, backends);
    std::fprintf(stderr,
                 "pathtracer: started by an MPI launcher%s, but this build has no MPI support "
                 "(no MPI library was found when it was configured): install libopenmpi-dev and "
                 "rebuild, or run a single process\n",
                 announced > 1 ? (" with " + std::to_string(announced) + " processes").c_str()
                               : "");
    return kExitRuntimeFailure;
  }
  AppClock::time_point start = AppClock::now();
  std::unique_ptr<MpiJob> job;
  try {
    job = MpiJob::Start();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pathtracer: %s\n", e.what());
    return kExitRuntimeFailure;
  }
  // One rank is a plain run, bit for bit.
  if (job->Size() == 1) return RunProcess(argc, argv, backends);
  try {
    return RunRanks(*job, argc, argv, backends, start, MsSince(start));
  } catch (const std::exception& e) {  // an MPI call failed during set-up
    std::fprintf(stderr, "pathtracer: rank %d: %s; ending the job\n", job->Rank(), e.what());
    job->Abort(kExitRuntimeFailure);
  }
  return kExitRuntimeFailure;  // not reached: Abort ends the process
}

}  // namespace pt
