// The --stats-json file of ../shared/cli.md: render statistics, scene facts and phase times.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "src/integrator/render_api.h"

namespace pt {

// Times measured by the app around the renderer, in milliseconds.
struct AppTimes {
  double loadMs = 0.0;
  double bvhBuildMs = 0.0;
};

// Millions of samples and of rays (camera, extension, shadow) per second of render time.
struct RenderRates {
  double msamplesPerS = 0.0, mraysPerS = 0.0;
};
RenderRates ComputeRates(const RenderStats& stats);

// The effects the scene uses: material types present ("diffuse", "emissive", "conductor",
// "dielectric", "plastic"), "absorption", "area_lights", "point_lights", "background_light",
// "depth_of_field". Only materials some primitive uses count.
std::vector<std::string> SceneEffectNames(const Scene& scene);

// The whole document: exactly the keys of the schema, in its order.
nlohmann::ordered_json StatsToJson(const RenderStats& stats, const Scene& scene, const AppTimes& times);

// Writes the document through a temporary file and a rename; throws ImageError on failure.
void WriteStatsJson(const std::string& path, const nlohmann::ordered_json& document);

}  // namespace pt
