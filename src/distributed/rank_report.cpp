#include "src/distributed/rank_report.h"

#include <algorithm>

namespace pt {
namespace {

using Json = nlohmann::json;

// Each field of the report once, by name: f(key, member) serves both directions.
template <typename Stats, typename F>
void StatsFields(Stats& s, F f) {
  f("render_ms", s.renderMs);
  f("upload_ms", s.uploadMs);
  f("warm_up_ms", s.warmUpMs);
  f("warm_up", s.warmedUp);
  f("samples", s.samples);
  f("camera_rays", s.cameraRays);
  f("extension_rays", s.extensionRays);
  f("shadow_rays", s.shadowRays);
  f("nodes_visited", s.nodesVisited);
  f("prims_tested", s.primsTested);
  f("traversals", s.traversals);
  f("nonfinite", s.nonfiniteSamples);
  f("path_state_bytes", s.pathStateBytesPerPath);
  f("paths_in_flight", s.pathsInFlight);
  f("peak_device_bytes", s.peakDeviceBytes);
  f("threads", s.threads);
  f("compact", s.compactUsed);
  f("sort", s.sortUsed);
  f("specialization", s.specialization);
  f("stage_generate", s.stages.generate);
  f("stage_intersect", s.stages.intersect);
  f("stage_sort", s.stages.sort);
  f("stage_shade", s.stages.shade);
  f("stage_shadow", s.stages.shadow);
  f("stage_compact", s.stages.compact);
  f("stage_accumulate", s.stages.accumulate);
}

template <typename Report, typename F>
void ReportFields(Report& r, F f) {
  f("rank", r.rank);
  f("host", r.host);
  f("backend", r.backend);
  f("device", r.device);
  f("lanes", r.lanes);
  f("leaves", r.leaves);
  f("samples", r.samples);
  f("startup_ms", r.startupMs);
  f("finished_ms", r.finishedMs);
  f("render_ms", r.renderMs);
  f("save_ms", r.saveMs);
  f("wait_ms", r.waitMs);
  f("merge_ms", r.mergeMs);
  f("send_ms", r.sendMs);
  f("failure", r.failure);
}

}  // namespace

Json RankReportToJson(const RankReport& r) {
  Json j, stats;
  ReportFields(r, [&](const char* key, const auto& value) { j[key] = value; });
  StatsFields(r.stats, [&](const char* key, const auto& value) { stats[key] = value; });
  j["stats"] = stats;
  return j;
}

RankReport RankReportFromJson(const Json& j) {
  RankReport r;
  ReportFields(r, [&](const char* key, auto& value) { j.at(key).get_to(value); });
  const Json& stats = j.at("stats");
  StatsFields(r.stats, [&](const char* key, auto& value) { stats.at(key).get_to(value); });
  r.stats.backend = r.backend;
  r.stats.device = r.device;
  return r;
}

void AddRenderStats(RenderStats& a, const RenderStats& b) {
  a.renderMs += b.renderMs;
  a.uploadMs += b.uploadMs;
  a.warmUpMs += b.warmUpMs;
  a.warmedUp = a.warmedUp || b.warmedUp;
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
