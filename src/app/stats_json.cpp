#include "src/app/stats_json.h"

#include <sys/resource.h>

#include <algorithm>
#include <optional>

#include "src/integrator/shade_queues.h"
#include "src/io/image_io.h"
#include "src/scene/effects.h"

namespace pt {
namespace {

using Json = nlohmann::ordered_json;

double Mean(uint64_t total, uint64_t count) { return count ? double(total) / count : 0.0; }

Json SceneJson(const Scene& scene) {
  const SceneDesc& d = scene.desc;
  // What textures occupy wherever the scene arrays live (device memory on the GPU): RGBA8
  // mip pyramids, 4 bytes a texel, plus their small descriptors.
  size_t textureBytes = d.texels.size() * sizeof(uint32_t) + d.textures.size() * sizeof(Texture) +
                        d.textureRefs.size() * sizeof(TextureRef);
  // With instances, "triangles" are those stored (each mesh once), "placed_triangles" those
  // the instances place in the world.
  return Json{{"triangles", scene.TriangleCount()},
              {"placed_triangles", scene.PlacedTriangleCount()},
              {"instances", scene.desc.instances.size()},
              {"primitives", scene.PrimitiveCount()},
              {"lights", scene.lights.size()},
              {"textures", d.textures.size()},
              {"texture_bytes", textureBytes},
              {"effects", SceneEffectNames(scene)}};
}

// Milliseconds per shade queue (--sort queues), queues that ran only.
Json ShadeQueueTimesJson(const StageTimes& s) {
  Json queues = Json::object();
  for (uint32_t q = 0; q < kShadeQueueCount; ++q)
    if (s.shadeQueues[q] > 0.0) queues[ShadeQueueName(q)] = s.shadeQueues[q];
  return queues;
}

Json StagesJson(const StageTimes& s) {
  return Json{{"generate", s.generate},
              {"intersect", s.intersect},
              {"sort", s.sort},
              {"shade", s.shade},
              {"shadow", s.shadow},
              {"compact", s.compact},
              {"accumulate", s.accumulate},
              {"medium", s.medium},
              {"shade_queues", ShadeQueueTimesJson(s)}};
}

// The shading order that ran (auto's choice and its reason).
Json SortJson(const RenderStats& stats) {
  return Json{{"mode", stats.sortMode},
              {"method", stats.sortMethod.empty() ? Json(nullptr) : Json(stats.sortMethod)},
              {"reason", stats.sortReason},
              {"paths_ordered", stats.pathsOrdered}};
}

// The timeline's parts (they sum to total), their names in run order, the time to the first
// pixel and what ran beside the main thread.
void AddTimelineJson(const AppTimes& times, Json* out) {
  const RunTimeline& t = *times.timeline;
  Json names = Json::array();
  for (const auto& [name, ms] : t.Parts()) {
    if (name != "load" && name != "bvh_build" && name != "upload" && name != "render")
      (*out)[name] = ms;
    names.push_back(name);
  }
  (*out)["parts"] = names;
  std::optional<double> firstPixel = t.FirstPixelMs();
  (*out)["first_pixel"] = firstPixel ? Json(*firstPixel) : Json(nullptr);
  Json background = Json::object();
  if (times.deviceStartBackgroundMs >= 0.0)
    background["device_start"] = times.deviceStartBackgroundMs;
  (*out)["background"] = background;
}

Json TimesJson(const RenderStats& stats, const AppTimes& times) {
  const StageTimes& s = stats.stages;
  if (times.timeline) {  // the parts as the timeline cut them
    const RunTimeline& t = *times.timeline;
    Json out{{"total", t.TotalMs()},
             {"load", t.Part("load")},
             {"bvh_build", t.Part("bvh_build")},
             {"upload", t.Part("upload")},
             {"render", t.Part("render")},
             {"stages", StagesJson(s)}};
    AddTimelineJson(times, &out);
    return out;
  }
  Json json{{"total", times.totalMs},
            {"load", times.loadMs},
            {"bvh_build", times.bvhBuildMs},
            {"upload", stats.uploadMs},
            {"render", stats.renderMs},
            {"stages", StagesJson(s)}};
  if (times.denoiseMs >= 0.0) json["denoise"] = times.denoiseMs;  // --denoise only
  return json;
}

// Peaks that mean something on each backend: the renderer's own buffers (device memory on a
// GPU, host memory on the CPU) and the whole process's resident set.
Json MemoryJson(const RenderStats& stats, const RunReport& run) {
  return Json{{"renderer_buffers_peak_bytes", stats.peakDeviceBytes},
              {"renderer_buffers_on", run.deviceMemory ? "device" : "host"},
              {"process_peak_rss_bytes", run.peakRssBytes}};
}

Json RelMseJson(const RenderStats& stats) {
  Json points = Json::array();
  for (const auto& [seconds, value] : stats.referenceRelMse) {
    points.push_back(Json{{"seconds", seconds}, {"relmse", value}});
  }
  return points;
}

Json ResumeJson(const RunReport& run) {
  if (run.resumedFrom.empty()) return nullptr;
  return Json{{"file", run.resumedFrom}, {"samples_before", run.resumedSamples}};
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

size_t PeakRssBytes() {
  struct rusage usage = {};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return size_t(usage.ru_maxrss) * 1024;  // kilobytes on Linux
}

Json StatsToJson(const RenderStats& stats, const Scene& scene, const AppTimes& times,
                 const RunReport& run) {
  RenderRates rates = ComputeRates(stats);
  bool stoppedEarly =
      run.stopReason == "signal" || run.stopReason == "time_limit" || run.stopReason == "failed";
  Json doc{
      {"version", PT_VERSION},
      {"command_line", run.commandLine},
      {"scene_file", run.sceneFile},
      {"backend", stats.backend},
      {"device", stats.device},
      {"threads", stats.threads},
      {"scene", SceneJson(scene)},
      {"time_ms", TimesJson(stats, times)},
      {"spp_requested", run.sppRequested},
      {"samples", stats.samples},
      {"spp_mean", stats.sppMean},
      {"stop_reason", run.stopReason},
      {"signal", run.signal.empty() ? Json(nullptr) : Json(run.signal)},
      {"interrupted", stoppedEarly},
      {"resumed", ResumeJson(run)},
      {"checkpoints_written", run.checkpoints},
      {"clamp_luminance", run.clampLuminance > 0.0f ? Json(run.clampLuminance) : Json(nullptr)},
      {"biased", run.clampLuminance > 0.0f},
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
      {"sort", SortJson(stats)},
      {"light_sampler", Json{{"sampler", stats.lightSampler},
                             {"tree_nodes", scene.lightTree.nodeCount},
                             {"tree_build_ms", scene.lightBvhBuildMs}}},
      {"sampler", stats.sampler},
      {"compact", stats.compactUsed},
      {"ray_order", stats.rayOrderUsed},
      {"prim_pool", stats.primPoolUsed},
      {"warm_up", stats.warmedUp},
      {"path_state_bytes_per_path", stats.pathStateBytesPerPath},
      {"paths_in_flight", stats.pathsInFlight},
      {"memory", MemoryJson(stats, run)},
      {"peak_device_bytes", run.deviceMemory ? Json(stats.peakDeviceBytes) : Json(nullptr)},
      {"nonfinite_samples", stats.nonfiniteSamples},
      {"reference_relmse", RelMseJson(stats)},
  };
  if (!times.bvhBuilder.empty()) {  // which builder ran (--bvh-build auto's choice), and where
    doc["bvh"]["builder"] = times.bvhBuilder;
    doc["bvh"]["built_on"] = times.bvhOnDevice ? "device" : "host";
  }
  return doc;
}

void WriteStatsJson(const std::string& path, const Json& document) {
  WriteFileAtomic(path, document.dump(2) + "\n");
}

}  // namespace pt
