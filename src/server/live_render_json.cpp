// LiveRender's JSON: the flags edit, the statistics of each frame and the scene description
// the page builds its controls from.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "src/io/image_io.h"
#include "src/io/scene_loader.h"

#include "src/lights/light_bvh_build.h"
#include "src/server/live_render.h"

namespace pt {
namespace {

const char* ToggleName(Toggle t) {
  return t == Toggle::kOn ? "on" : t == Toggle::kOff ? "off" : "auto";
}
const char* SortName(SortMode m) {
  return m == SortMode::kMaterial ? "material" : m == SortMode::kOff ? "off" : "auto";
}
const char* IntegratorName(IntegratorMode m) {
  return m == IntegratorMode::kBsdf ? "bsdf" : m == IntegratorMode::kNee ? "nee" : "mis";
}

const char* MaterialTypeName(MaterialType t) {
  switch (t) {
    case MaterialType::kDiffuse: return "diffuse";
    case MaterialType::kEmissive: return "emissive";
    case MaterialType::kConductor: return "conductor";
    case MaterialType::kDielectric: return "dielectric";
    case MaterialType::kPlastic: return "plastic";
    default: return "other";
  }
}

// One of a few names, or EditError 400 listing them.
template <typename T>
T Choice(const Json& value, const char* key, std::initializer_list<std::pair<const char*, T>> choices) {
  std::string names;
  for (const auto& [name, v] : choices) {
    if (value.is_string() && value.get<std::string>() == name) return v;
    names += names.empty() ? name : std::string("|") + name;
  }
  throw EditError(400, std::string("bad value for ") + key + ": " + value.dump() +
                           " (expected " + names + ")", key);
}

int64_t Integer(const Json& value, const char* key) {
  if (!value.is_number_integer()) {
    throw EditError(400, std::string(key) + " must be an integer, not " + value.dump(), key);
  }
  return value.get<int64_t>();
}

Json StagesJson(const StageTimes& s, double per) {
  return Json{{"generate", s.generate / per}, {"intersect", s.intersect / per},
              {"sort", s.sort / per},         {"shade", s.shade / per},
              {"shadow", s.shadow / per},     {"compact", s.compact / per},
              {"accumulate", s.accumulate / per}};
}

StageTimes Minus(const StageTimes& a, const StageTimes& b) {
  return StageTimes{a.generate - b.generate, a.intersect - b.intersect, a.sort - b.sort,
                    a.shade - b.shade,       a.shadow - b.shadow,       a.compact - b.compact,
                    a.accumulate - b.accumulate};
}

std::string JoinNames(const Json& names) {
  std::string all;
  for (const Json& n : names) all += (all.empty() ? "" : ", ") + n.get<std::string>();
  return all;
}

Json OptionsJson(const RenderOptions& o) {
  return Json{{"compact", ToggleName(o.compact)},
              {"sort", SortName(o.sort)},
              {"integrator", IntegratorName(o.integrator)},
              {"specialize", o.specialize},
              {"light_sampler", LightSamplerName(o.lightSampler)},
              {"sampler", SamplerKindName(o.sampler.value_or(SamplerKind::kIndependent))}};
}

Json IndexOrNull(int index) { return index < 0 ? Json(nullptr) : Json(index); }

uint64_t Rays(const RenderStats& s) { return s.cameraRays + s.extensionRays + s.shadowRays; }

}  // namespace

EditAnswer LiveRender::EditOptions(const Json& fields) {
  if (!fields.is_object()) throw EditError(400, "the options must be a JSON object");
  std::optional<bool> denoise;
  EditAnswer answer = Queue(
      [&](Pending& p) {
        RenderOptions o = requestedOptions_;
        std::optional<int64_t> maxDepth, spp;
        for (const auto& [key, value] : fields.items()) {
          if (key == "compact") {
            o.compact = Choice<Toggle>(value, "compact", {{"on", Toggle::kOn},
                                                          {"off", Toggle::kOff},
                                                          {"auto", Toggle::kAuto}});
          } else if (key == "sort") {
            o.sort = Choice<SortMode>(value, "sort", {{"off", SortMode::kOff},
                                                      {"material", SortMode::kMaterial},
                                                      {"auto", SortMode::kAuto}});
          } else if (key == "integrator") {
            o.integrator = Choice<IntegratorMode>(value, "integrator",
                                                  {{"mis", IntegratorMode::kMis},
                                                   {"bsdf", IntegratorMode::kBsdf},
                                                   {"nee", IntegratorMode::kNee}});
          } else if (key == "specialize") {
            if (!value.is_boolean()) throw EditError(400, "specialize must be true or false", key);
            o.specialize = value.get<bool>();
          } else if (key == "light_sampler") {
            o.lightSampler = Choice<LightSampler>(value, "light_sampler",
                                                  {{"auto", LightSampler::kAuto},
                                                   {"bvh", LightSampler::kBvh},
                                                   {"power", LightSampler::kPower},
                                                   {"uniform", LightSampler::kUniform}});
          } else if (key == "sampler") {
            o.sampler = Choice<SamplerKind>(value, "sampler",
                                            {{"independent", SamplerKind::kIndependent},
                                             {"sobol", SamplerKind::kSobol}});
          } else if (key == "max_depth") {
            maxDepth = Integer(value, "max_depth");
          } else if (key == "spp") {
            spp = Integer(value, "spp");
          } else if (key == "denoise") {
            if (!value.is_boolean()) throw EditError(400, "denoise must be true or false", key);
            if (!denoiseAvailable_) throw EditError(422, "this preview has no denoiser", key);
            denoise = value.get<bool>();
          } else {
            throw EditError(400, "unknown option \"" + key +
                                     "\" (expected compact, sort, integrator, specialize, "
                                     "light_sampler, sampler, max_depth, spp or denoise)");
          }
        }
        // The loader's limits, checked before anything changes.
        try {
          if (maxDepth) document_.SetRenderSetting("max_depth", *maxDepth);
        } catch (const SceneError& e) {
          throw EditError(422, e.what(), "max_depth");
        }
        try {
          if (spp) document_.SetRenderSetting("spp", *spp);
        } catch (const SceneError& e) {
          throw EditError(422, e.what(), "spp");
        }
        if (spp) p.spp = uint32_t(*spp);
        if (maxDepth) p.maxDepth = int(*maxDepth);
        // Anything but the target spp and denoising (display only) restarts the film.
        if (fields.size() > (spp ? 1u : 0u) + (denoise ? 1u : 0u)) {
          requestedOptions_ = o;
          p.options = o;
          p.restart = true;
        }
        // Here (all checked, under the document's lock): the state the feed announces has it.
        if (denoise) denoise_ = *denoise;
      },
      ChangeFeed::kState);
  if (denoise) EncodeAgain();  // the frame shown, denoised or not
  return answer;
}

EditAnswer LiveRender::EditLighting(const Json& fields) {
  if (!fields.is_object()) throw EditError(400, "the lighting must be a JSON object");
  Json maps = ListMaps();
  return Queue(
      [&](Pending& p) {
        SceneDocument::Lighting lighting = document_.CurrentLighting();
        std::string map = lightingMap_;
        for (const auto& [key, value] : fields.items()) {
          if (key == "map") {
            if (!value.is_string()) throw EditError(400, "map must be a name", key);
            map = value.get<std::string>();
          } else if (key == "strength" || key == "rotation") {
            if (!value.is_number() || !std::isfinite(value.get<double>())) {
              throw EditError(400, key + " must be a number", key);
            }
            float v = value.get<float>();
            if (key == "strength" && !(v >= 0.0f)) throw EditError(422, "strength must be >= 0", key);
            (key == "strength" ? lighting.strength : lighting.rotation) = v;
          } else {
            throw EditError(400, "unknown lighting setting \"" + key +
                                     "\" (expected map, strength or rotation)");
          }
        }
        if (map == "scene") {
          lighting.kind = SceneDocument::Lighting::Kind::kScene;
        } else if (map == "none") {
          lighting.kind = SceneDocument::Lighting::Kind::kNone;
        } else if (std::find(maps.begin(), maps.end(), map) != maps.end()) {
          lighting.kind = SceneDocument::Lighting::Kind::kMap;
          lighting.mapPath = settings_.environmentFolder + "/" + map;
        } else {
          throw EditError(404, "no map \"" + map + "\" (the maps offered: scene, none" +
                                   (maps.empty() ? std::string() : ", " + JoinNames(maps)) + ")",
                          "map");
        }
        try {
          p.lighting = document_.EditLighting(lighting);
        } catch (const SceneError& e) {
          throw EditError(422, e.what(), fields.contains("map") ? "map" : "strength");
        }
        lightingMap_ = map;
        p.restart = true;
      },
      ChangeFeed::kState);
}

// The equirectangular maps in the environment folder (not its subfolders), by name.
Json LiveRender::ListMaps() const {
  Json names = Json::array();
  if (settings_.environmentFolder.empty()) return names;
  std::error_code ec;
  std::vector<std::string> found;
  for (const auto& entry : std::filesystem::directory_iterator(settings_.environmentFolder, ec)) {
    std::string ext = LowerExtension(entry.path().string());
    if ((ext == ".exr" || ext == ".hdr" || ext == ".pfm") && entry.is_regular_file(ec)) {
      found.push_back(entry.path().filename().string());
    }
  }
  std::sort(found.begin(), found.end());
  for (const std::string& name : found) names.push_back(name);
  return names;
}

std::string LiveRender::StatsJson(const RenderStats& now, double passMs, uint32_t passSpp) const {
  double seconds = (now.renderMs - generationStart_.renderMs) / 1e3;
  double samples = double(spp_.load()) * width_ * height_;
  double rays = double(Rays(now) - Rays(generationStart_));
  Json j;
  j["spp"] = spp_.load();
  j["target_spp"] = targetSpp_;
  j["generation"] = generation_;
  j["width"] = width_;
  j["height"] = height_;
  j["backend"] = now.backend;
  j["device"] = now.device;
  j["threads"] = now.threads;
  j["samples_per_s"] = seconds > 0.0 ? samples / seconds : 0.0;
  j["rays_per_s"] = seconds > 0.0 ? rays / seconds : 0.0;
  j["pass_ms"] = passMs / std::max<uint32_t>(1, passSpp);
  j["stage_ms"] = StagesJson(Minus(now.stages, lastPassEnd_.stages), std::max<uint32_t>(1, passSpp));
  j["compact_used"] = now.compactUsed;
  j["sort_used"] = now.sortUsed;
  j["specialization"] = now.specialization;
  j["light_sampler"] = now.lightSampler;
  j["sampler"] = now.sampler;
  j["rebuilds"] = Json{{"scene", sceneRebuilds_},
                       {"top_level", topLevelRebuilds_},
                       {"last_ms", lastRebuildMs_}};
  return j.dump();
}

std::string LiveRender::DescribeJson() const {
  Json j;
  std::lock_guard<std::mutex> lock(docMutex_);
  j["scene"] = document_.Path();
  j["width"] = width_;
  j["height"] = height_;
  j["camera"] = document_.CameraJson();
  j["render"] = document_.RenderJson();
  j["options"] = OptionsJson(requestedOptions_);
  j["options"]["denoise"] = denoise_.load();
  j["options"]["denoise_available"] = denoiseAvailable_;
  Json cameras = Json::array();
  for (size_t i = 0; i < cameras_.size(); ++i) {
    cameras.push_back(Json{{"index", i}, {"name", cameras_[i].name}});
  }
  j["cameras"] = cameras;
  j["maps"] = ListMaps();
  Json objects = Json::array();
  for (size_t i = 0; i < document_.ObjectCount(); ++i) {
    const Json& o = document_.ObjectJson(i);
    Json entry{{"index", i}, {"type", o.value("type", "")}};
    if (o.contains("material")) entry["material"] = o["material"];
    if (o.contains("file")) entry["file"] = o["file"];
    if (o.contains("mesh")) entry["mesh"] = o["mesh"];  // an instance of that table mesh
    objects.push_back(entry);
  }
  j["objects"] = objects;
  Json materials = Json::array();
  std::shared_lock<std::shared_mutex> sceneLock(sceneMutex_);
  const SceneDesc& desc = scene_.desc;
  for (size_t i = 0; i < desc.materials.size(); ++i) {
    bool inFile = i < document_.MaterialCount();
    Json entry{{"index", i},
               {"name", i < desc.materialNames.size() ? desc.materialNames[i] : ""},
               {"type", MaterialTypeName(desc.materials[i].type)},
               {"editable", inFile}};
    if (inFile) entry["fields"] = document_.MaterialJson(i);
    materials.push_back(entry);
  }
  j["materials"] = materials;
  return j.dump();
}

std::string LiveRender::StateJson() const {
  std::lock_guard<std::mutex> lock(docMutex_);
  Json j;
  j["camera"] = document_.CameraJson();
  j["camera_choice"] = IndexOrNull(cameraChoice_);
  Json options = OptionsJson(requestedOptions_);
  options["max_depth"] = document_.RenderJson()["max_depth"];
  options["spp"] = document_.RenderJson()["spp"];
  if (denoiseAvailable_) options["denoise"] = denoise_.load();
  j["options"] = options;
  j["display"] = Json{{"exposure", display_.exposure},
                      {"tone_mapping", ToneMappingName(display_.toneMapping)}};
  j["selection"] = Json{{"object", IndexOrNull(selectedObject_)},
                        {"material", IndexOrNull(selectedMaterial_)}};
  const SceneDocument::Lighting& lighting = document_.CurrentLighting();
  j["lighting"] = Json{{"map", lightingMap_}, {"strength", lighting.strength},
                       {"rotation", lighting.rotation}};
  return j.dump();
}

}  // namespace pt
