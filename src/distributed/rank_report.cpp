#include "src/distributed/rank_report.h"

#include <algorithm>

namespace pt {
namespace {

using Json = nlohmann::json;

// The RenderStats fields a rank's report carries (the ones that add up over ranks).
Json StatsToJson(const RenderStats& s) {
  const StageTimes& t = s.stages;
  return Json{{"render_ms", s.renderMs},
              {"upload_ms", s.uploadMs},
              {"samples", s.samples},
              {"camera_rays", s.cameraRays},
              {"extension_rays", s.extensionRays},
              {"shadow_rays", s.shadowRays},
              {"nodes_visited", s.nodesVisited},
              {"prims_tested", s.primsTested},
              {"traversals", s.traversals},
              {"nonfinite", s.nonfiniteSamples},
              {"path_state_bytes", s.pathStateBytesPerPath},
              {"paths_in_flight", s.pathsInFlight},
              {"peak_device_bytes", s.peakDeviceBytes},
              {"threads", s.threads},
              {"compact", s.compactUsed},
              {"sort", s.sortUsed},
              {"specialization", s.specialization},
              {"stages", {t.generate, t.intersect, t.sort, t.shade, t.shadow, t.compact,
                          t.accumulate}}};
}

RenderStats StatsFromJson(const Json& j) {
  RenderStats s;
  s.renderMs = j.at("render_ms");
  s.uploadMs = j.at("upload_ms");
  s.samples = j.at("samples");
  s.cameraRays = j.at("camera_rays");
  s.extensionRays = j.at("extension_rays");
  s.shadowRays = j.at("shadow_rays");
  s.nodesVisited = j.at("nodes_visited");
  s.primsTested = j.at("prims_tested");
  s.traversals = j.at("traversals");
  s.nonfiniteSamples = j.at("nonfinite");
  s.pathStateBytesPerPath = j.at("path_state_bytes");
  s.pathsInFlight = j.at("paths_in_flight");
  s.peakDeviceBytes = j.at("peak_device_bytes");
  s.threads = j.at("threads");
  s.compactUsed = j.at("compact");
  s.sortUsed = j.at("sort");
  s.specialization = j.at("specialization");
  const Json& t = j.at("stages");
  s.stages = StageTimes{t.at(0), t.at(1), t.at(2), t.at(3), t.at(4), t.at(5), t.at(6)};
  return s;
}

}  // namespace

Json RankReportToJson(const RankReport& r) {
  return Json{{"rank", r.rank},          {"host", r.host},
              {"backend", r.backend},    {"device", r.device},
              {"lanes", r.lanes},        {"leaves", r.leaves},
              {"samples", r.samples},    {"startup_ms", r.startupMs},
              {"finished_ms", r.finishedMs}, {"render_ms", r.renderMs},
              {"save_ms", r.saveMs},     {"wait_ms", r.waitMs},
              {"merge_ms", r.mergeMs},   {"send_ms", r.sendMs},
              {"failure", r.failure},    {"stats", StatsToJson(r.stats)}};
}

RankReport RankReportFromJson(const Json& j) {
  RankReport r;
  r.rank = j.at("rank");
  r.host = j.at("host");
  r.backend = j.at("backend");
  r.device = j.at("device");
  r.lanes = j.at("lanes");
  r.leaves = j.at("leaves");
  r.samples = j.at("samples");
  r.startupMs = j.at("startup_ms");
  r.finishedMs = j.at("finished_ms");
  r.renderMs = j.at("render_ms");
  r.saveMs = j.at("save_ms");
  r.waitMs = j.at("wait_ms");
  r.mergeMs = j.at("merge_ms");
  r.sendMs = j.at("send_ms");
  r.failure = j.at("failure");
  r.stats = StatsFromJson(j.at("stats"));
  r.stats.backend = r.backend;
  r.stats.device = r.device;
  return r;
}

void AddRenderStats(RenderStats& a, const RenderStats& b) {
  a.renderMs += b.renderMs;
  a.uploadMs += b.uploadMs;
  a.samples += b.samples;
  a.cameraRays += b.cameraRays;
  a.extensionRays += b.extensionRays;
  a.shadowRays += b.shadowRays;
  a.nodesVisited += b.nodesVisited;
  a.primsTested += b.primsTested;
  a.traversals += b.traversals;
  a.nonfiniteSamples += b.nonfiniteSamples;
  a.threads += b.threads;
  a.pathsInFlight += b.pathsInFlight;
  a.peakDeviceBytes = std::max(a.peakDeviceBytes, b.peakDeviceBytes);
  a.pathStateBytesPerPath = std::max(a.pathStateBytesPerPath, b.pathStateBytesPerPath);
  a.compactUsed = a.compactUsed || b.compactUsed;
  a.sortUsed = a.sortUsed || b.sortUsed;
  if (a.specialization.empty()) a.specialization = b.specialization;
  StageTimes& s = a.stages;
  const StageTimes& t = b.stages;
  s.generate += t.generate;
  s.intersect += t.intersect;
  s.sort += t.sort;
  s.shade += t.shade;
  s.shadow += t.shadow;
  s.compact += t.compact;
  s.accumulate += t.accumulate;
}

double LoadBalance(const std::vector<RankReport>& ranks) {
  double sum = 0.0, most = 0.0;
  for (const RankReport& r : ranks) {
    sum += r.finishedMs;
    most = std::max(most, r.finishedMs);
  }
  return most > 0.0 ? sum / double(ranks.size()) / most : 1.0;
}

}  // namespace pt
