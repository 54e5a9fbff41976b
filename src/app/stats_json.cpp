#include "src/app/stats_json.h"

#include "src/scene/effects.h"

#include <algorithm>

#include "src/io/image_io.h"

namespace pt {
namespace {

using Json = nlohmann::ordered_json;

double Mean(uint64_t total, uint64_t count) { return count ? double(total) / count : 0.0; }

Json SceneJson(const Scene& scene) {
  return Json{{"triangles", scene.TriangleCount()},
              {"primitives", scene.PrimitiveCount()},
              {"lights", scene.lights.size()},
              {"effects", SceneEffectNames(scene)}};
}

Json TimesJson(const RenderStats& stats, const AppTimes& times) {
  const StageTimes& s = stats.stages;
  return Json{{"load", times.loadMs},
              {"bvh_build", times.bvhBuildMs},
              {"upload", stats.uploadMs},
              {"render", stats.renderMs},
              {"stages", Json{{"generate", s.generate},
                              {"intersect", s.intersect},
                              {"sort", s.sort},
                              {"shade", s.shade},
                              {"shadow", s.shadow},
                              {"compact", s.compact},
                              {"accumulate", s.accumulate}}}};
}

}  // namespace

std::vector<std::string> SceneEffectNames(const Scene& scene) {
  return EffectNames(AnalyzeEffects(scene));
}

RenderRates ComputeRates(const RenderStats& stats) {
  if (stats.renderMs <= 0.0) return {};
  uint64_t rays = stats.cameraRays + stats.extensionRays + stats.shadowRays;
  double microseconds = stats.renderMs * 1e3;  // count / us = millions / s
  return {double(stats.samples) / microseconds, double(rays) / microseconds};
}

Json StatsToJson(const RenderStats& stats, const Scene& scene, const AppTimes& times) {
  RenderRates rates = ComputeRates(stats);
  Json relMse = Json::array();
  for (const auto& [seconds, value] : stats.referenceRelMse) relMse.push_back({seconds, value});
  return Json{
      {"backend", stats.backend},
      {"device", stats.device},
      {"threads", stats.threads},
      {"scene", SceneJson(scene)},
      {"time_ms", TimesJson(stats, times)},
      {"samples", stats.samples},
      {"spp_mean", stats.sppMean},
      {"rays", Json{{"camera", stats.cameraRays},
                    {"extension", stats.extensionRays},
                    {"shadow", stats.shadowRays}}},
      {"msamples_per_s", rates.msamplesPerS},
      {"mrays_per_s", rates.mraysPerS},
      {"bvh", Json{{"layout", BvhLayoutName(scene.bvhLayout)},
                   {"nodes", scene.NodeCount()},
                   {"node_bytes", scene.NodeBytes()},
                   {"depth", scene.bvhDepth},
                   {"sah_cost", scene.bvhSahCost},
                   {"mean_nodes_visited", Mean(stats.nodesVisited, stats.traversals)},
                   {"mean_prims_tested", Mean(stats.primsTested, stats.traversals)}}},
      {"path_state_bytes_per_path", stats.pathStateBytesPerPath},
      {"paths_in_flight", stats.pathsInFlight},
      {"peak_device_bytes", stats.peakDeviceBytes},
      {"nonfinite_samples", stats.nonfiniteSamples},
      {"interrupted", stats.interrupted},
      {"reference_relmse", relMse},
  };
}

void WriteStatsJson(const std::string& path, const Json& document) {
  WriteFileAtomic(path, document.dump(2) + "\n");
}

}  // namespace pt
