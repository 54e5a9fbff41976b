#include "src/lights/light_table.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <utility>

#include "src/core/parallel_ranges.h"
#include "src/lights/emission_power.h"
#include "src/lights/environment.h"
#include "src/lights/light_bvh_build.h"
#include "src/lights/light_sample.h"
#include "src/scene/instances.h"

namespace pt {

namespace {

// How much a glTF emissive texture scales a primitive's power (1 without one): the luminance
// of the material's emission times the texture's mean over the primitive (emission_power.h),
// over the emission's own. A primitive whose texels are black gets 0 and is no light (BSDF
// sampling alone finds whatever filtering bleeds onto its edges).
double EmissionScale(const SceneView& view, const PrimRef& prim) {
  const Material& m = view.materials[prim.material];
  if (m.type != MaterialType::kGltfPbr || m.emissiveTexture < 0) return 1.0;
  double plain = double(Luminance(m.radiance));
  if (!(plain > 0.0)) return 0.0;
  return double(Luminance(m.radiance * MeanEmissiveTexture(view, prim))) / plain;
}

double PrimArea(const SceneDesc& desc, const PrimRef& prim) {
  switch (prim.Type()) {
    case ShapeType::kQuad: return QuadArea(desc.quads[prim.Index()]);
    case ShapeType::kTriangle: return TriangleArea(desc.triangles[prim.Index()]);
    case ShapeType::kSphere: return SphereArea(desc.spheres[prim.Index()]);
  }
  return 0.0;
}

// Probabilities from powers. The cdf is accumulated in double and rounded once; each pmf is
// then the float width of its cdf interval, so the probability a light is chosen and the pmf
// its pdf is divided by agree, and a light of zero power is never chosen.
void FillDistribution(const std::vector<double>& power, Scene& scene) {
  size_t n = power.size();
  double total = 0.0;
  for (double p : power) total += (std::isfinite(p) && p > 0.0) ? p : 0.0;
  bool uniform = !(total > 0.0) || !std::isfinite(total);  // no power at all: choose evenly
  scene.lightCdf.assign(n + 1, 0.0f);
  scene.lightPmf.assign(n, 0.0f);
  double running = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double p = (std::isfinite(power[i]) && power[i] > 0.0) ? power[i] : 0.0;
    running += uniform ? 1.0 : p;
    scene.lightCdf[i + 1] = float(running / (uniform ? double(n) : total));
  }
  if (n > 0) scene.lightCdf[n] = 1.0f;
  for (size_t i = 0; i < n; ++i) scene.lightPmf[i] = scene.lightCdf[i + 1] - scene.lightCdf[i];
}

// The spot's falloff integrated over the sphere of directions: 2 pi times the integral over
// c = cos(angle to the axis) in [-1, 1] of clamp(c s + o, 0, 1)^2, in closed form (the
// falloff is 0 below c0 = -o/s, quadratic up to c1 = (1 - o)/s and 1 above).
double SpotSolidAngle(const Light& light) {
  double s = light.spotScale, o = light.spotOffset;
  if (!(s > 0.0)) return o >= 1.0 ? 4.0 * double(kPi) : 0.0;
  auto cube = [](double v) { return v * v * v; };
  auto t = [&](double c) { return std::clamp(c * s + o, 0.0, 1.0); };
  double c0 = std::clamp(-o / s, -1.0, 1.0), c1 = std::clamp((1.0 - o) / s, -1.0, 1.0);
  double ramp = (cube(t(c1)) - cube(t(c0))) / (3.0 * s);
  return 2.0 * double(kPi) * (ramp + (1.0 - c1));
}

}  // namespace

Light MakeSpotLight(const SpotLightDesc& desc) {
  Light light;
  light.type = LightType::kSpot;
  light.position = desc.position;
  light.direction = glm::normalize(desc.direction);
  light.intensity = desc.intensity;
  // glTF KHR_lights_punctual's recommended falloff (its max(0.001, ...) keeps the ramp finite).
  double cosInner = std::cos(double(desc.innerAngle)), cosOuter = std::cos(double(desc.outerAngle));
  double scale = 1.0 / std::max(0.001, cosInner - cosOuter);
  light.spotScale = float(scale);
  light.spotOffset = float(-cosOuter * scale);
  return light;
}

double LightPower(const Scene& scene, const Light& light) {
  switch (light.type) {
    case LightType::kArea: {
      double area = light.instance >= 0 ? InstanceLightArea(scene, light)
                                        : PrimArea(scene.desc, scene.prims[light.prim]);
      double sides = light.twoSided ? 2.0 : 1.0;
      return double(Luminance(light.radiance)) * area * double(kPi) * sides;
    }
    case LightType::kPoint: return 4.0 * double(kPi) * double(Luminance(light.intensity));
    case LightType::kSpot: return SpotSolidAngle(light) * double(Luminance(light.intensity));
    case LightType::kBackground: {
      // pbrt-v4 UniformInfiniteLight::Phi: radiance over the disk of the bounding sphere.
      double r = scene.sceneRadius;
      return double(Luminance(light.radiance)) * 4.0 * double(kPi) * double(kPi) * r * r;
    }
    case LightType::kDirectional: {
      // pbrt-v4 DistantLight::Phi: the irradiance over the disk of the bounding sphere.
      double r = scene.sceneRadius;
      return double(Luminance(light.irradiance)) * double(kPi) * r * r;
    }
    case LightType::kEnvironmentMap: {
      // pbrt-v4 ImageInfiniteLight::Phi: the integral of radiance over directions times the
      // disk of the bounding sphere.
      double r = scene.sceneRadius;
      return EnvironmentMapLuminanceIntegral(scene) * double(kPi) * r * r;
    }
  }
  return 0.0;
}

// The world primitives [0, count) that emit, with their emission scale, in primitive order
// (dark ones left out: BSDF sampling only); every primitive's light index reset. A big scene's
// primitives on every core.
static std::vector<std::pair<uint32_t, double>> WorldEmitters(Scene& scene, const SceneView& view,
                                                              size_t count) {
  using Part = std::vector<std::pair<uint32_t, double>>;
  std::mutex mutex;
  std::vector<std::pair<size_t, Part>> parts;
  ForRangesOnThreads(count, 0, size_t(1) << 16, [&](size_t lo, size_t hi) {
    Part part;
    for (size_t i = lo; i < hi; ++i) {
      PrimRef& prim = scene.prims[i];
      prim.light = -1;
      if (!MaterialEmits(scene.desc.materials[prim.material])) continue;
      double scale = EmissionScale(view, prim);
      if (scale > 0.0) part.emplace_back(uint32_t(i), scale);
    }
    std::lock_guard<std::mutex> lock(mutex);
    parts.emplace_back(lo, std::move(part));
  });
  std::sort(parts.begin(), parts.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  Part all;
  for (auto& [lo, part] : parts) all.insert(all.end(), part.begin(), part.end());
  return all;
}

void BuildLightTable(Scene& scene) {
  const SceneDesc& desc = scene.desc;
  scene.lights.clear();
  scene.backgroundLight = -1;
  SceneView view = HostSceneView(scene);
  // Area lights in the order of the shapes (tagIndex), not of the BVH's leaves, so the table
  // and every light choice are the same whatever the layout or builder; a shape that spatial
  // splits put in several leaves is one light, named by every copy.
  // With instances, each placement's emitters come first (AppendInstanceLights), then the
  // world-space primitives': the order of a scene whose instances FlattenInstances placed.
  if (scene.HasInstances()) AppendInstanceLights(scene);
  size_t worldPrims = scene.HasInstances() ? scene.worldPrimCount : scene.prims.size();
  std::vector<std::pair<uint32_t, double>> emitters = WorldEmitters(scene, view, worldPrims);
  std::stable_sort(emitters.begin(), emitters.end(), [&](const auto& a, const auto& b) {
    return scene.prims[a.first].tagIndex < scene.prims[b.first].tagIndex;
  });
  std::vector<double> emissionScale;  // per world area light, for its power
  const size_t firstWorldLight = scene.lights.size();  // after the instances' lights
  for (size_t k = 0; k < emitters.size(); ++k) {
    PrimRef& prim = scene.prims[emitters[k].first];
    if (k > 0 && prim.tagIndex == scene.prims[emitters[k - 1].first].tagIndex) {
      prim.light = scene.prims[emitters[k - 1].first].light;
      continue;
    }
    const Material& m = desc.materials[prim.material];
    Light light;
    light.type = LightType::kArea;
    light.prim = emitters[k].first;
    light.radiance = m.radiance;
    light.twoSided = m.twoSided;
    prim.light = int32_t(scene.lights.size());
    scene.lights.push_back(light);
    emissionScale.push_back(emitters[k].second);
  }
  // Black point and spot lights are left out (as black directional lights): no sampler may
  // choose a light of no power.
  for (const PointLightDesc& point : desc.pointLights) {
    if (IsBlack(point.intensity)) continue;
    Light light;
    light.type = LightType::kPoint;
    light.position = point.position;
    light.intensity = point.intensity;
    scene.lights.push_back(light);
  }
  for (const SpotLightDesc& spot : desc.spotLights)
    if (!IsBlack(spot.intensity)) scene.lights.push_back(MakeSpotLight(spot));
  scene.distantLights.clear();
  for (const DirectionalLightDesc& d : desc.directionalLights) {
    Light light = MakeDirectionalLight(d, desc.environment);
    if (IsBlack(light.irradiance)) continue;
    if (!light.IsDeltaDirection()) scene.distantLights.push_back(uint32_t(scene.lights.size()));
    scene.lights.push_back(light);
  }
  if (!IsBlack(desc.background * desc.environment.strength)) {
    Light light;
    light.type = LightType::kBackground;
    light.radiance = desc.background * desc.environment.strength;
    scene.backgroundLight = int32_t(scene.lights.size());
    scene.lights.push_back(light);
  }
  BuildEnvironmentMap(scene);
  if (EnvironmentMapLuminanceIntegral(scene) > 0.0) {
    Light light;
    light.type = LightType::kEnvironmentMap;
    scene.env.light = int32_t(scene.lights.size());
    scene.lights.push_back(light);
  }
  scene.lightPower.clear();
  UpdateLightPowers(scene, 0, scene.lights.size());
  for (size_t k = 0; k < emissionScale.size(); ++k) scene.lightPower[firstWorldLight + k] *= emissionScale[k];
  UpdateLightDistribution(scene);
}

void UpdateLightPowers(Scene& scene, size_t first, size_t end) {
  scene.lightPower.resize(scene.lights.size(), 0.0);
  for (size_t i = first; i < end; ++i) scene.lightPower[i] = LightPower(scene, scene.lights[i]);
}

void UpdateLightDistribution(Scene& scene) {
  // The powers of the lights at infinity follow the bounding sphere, which moving instances
  // changes.
  for (int32_t light : {scene.backgroundLight, scene.env.light}) {
    if (light >= 0) UpdateLightPowers(scene, size_t(light), size_t(light) + 1);
  }
  FillDistribution(scene.lightPower, scene);
  BuildLightBvh(scene);  // finite lights moved with their instances, or their power changed
}

}  // namespace pt
