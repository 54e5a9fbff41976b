#include "src/lights/light_table.h"

#include <algorithm>

#include "src/lights/light_sample.h"
#include "src/scene/instances.h"

namespace pt {

namespace {

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

}  // namespace

double LightPower(const Scene& scene, const Light& light) {
  switch (light.type) {
    case LightType::kArea: {
      double area = light.instance >= 0 ? InstanceLightArea(scene, light)
                                        : PrimArea(scene.desc, scene.prims[light.prim]);
      double sides = light.twoSided ? 2.0 : 1.0;
      return double(Luminance(light.radiance)) * area * double(kPi) * sides;
    }
    case LightType::kPoint: return 4.0 * double(kPi) * double(Luminance(light.intensity));
    case LightType::kBackground: {
      // pbrt-v4 UniformInfiniteLight::Phi: radiance over the disk of the bounding sphere.
      double r = scene.sceneRadius;
      return double(Luminance(light.radiance)) * 4.0 * double(kPi) * double(kPi) * r * r;
    }
  }
  return 0.0;
}

void BuildLightTable(Scene& scene) {
  const SceneDesc& desc = scene.desc;
  scene.lights.clear();
  scene.backgroundLight = -1;
  // Area lights in the order of the shapes (tagIndex), not of the BVH's leaves, so the table
  // and every light choice are the same whatever the layout or builder; a shape that spatial
  // splits put in several leaves is one light, named by every copy.
  // With instances, each placement's emitters come first (AppendInstanceLights), then the
  // world-space primitives': the order of a scene whose instances FlattenInstances placed.
  if (scene.HasInstances()) AppendInstanceLights(scene);
  std::vector<uint32_t> emitters;
  size_t worldPrims = scene.HasInstances() ? scene.worldPrimCount : scene.prims.size();
  for (size_t i = 0; i < worldPrims; ++i) {
    PrimRef& prim = scene.prims[i];
    prim.light = -1;
    const Material& m = desc.materials[prim.material];
    if (m.type == MaterialType::kEmissive && !IsBlack(m.radiance)) emitters.push_back(uint32_t(i));
  }
  std::stable_sort(emitters.begin(), emitters.end(), [&](uint32_t a, uint32_t b) {
    return scene.prims[a].tagIndex < scene.prims[b].tagIndex;
  });
  for (size_t k = 0; k < emitters.size(); ++k) {
    PrimRef& prim = scene.prims[emitters[k]];
    if (k > 0 && prim.tagIndex == scene.prims[emitters[k - 1]].tagIndex) {
      prim.light = scene.prims[emitters[k - 1]].light;
      continue;
    }
    const Material& m = desc.materials[prim.material];
    Light light;
    light.type = LightType::kArea;
    light.prim = emitters[k];
    light.radiance = m.radiance;
    light.twoSided = m.twoSided;
    prim.light = int32_t(scene.lights.size());
    scene.lights.push_back(light);
  }
  for (const PointLightDesc& point : desc.pointLights) {
    Light light;
    light.type = LightType::kPoint;
    light.position = point.position;
    light.intensity = point.intensity;
    scene.lights.push_back(light);
  }
  if (!IsBlack(desc.background)) {
    Light light;
    light.type = LightType::kBackground;
    light.radiance = desc.background;
    scene.backgroundLight = int32_t(scene.lights.size());
    scene.lights.push_back(light);
  }
  scene.lightPower.clear();
  UpdateLightPowers(scene, 0, scene.lights.size());
  UpdateLightDistribution(scene);
}

void UpdateLightPowers(Scene& scene, size_t first, size_t end) {
  scene.lightPower.resize(scene.lights.size(), 0.0);
  for (size_t i = first; i < end; ++i) scene.lightPower[i] = LightPower(scene, scene.lights[i]);
}

void UpdateLightDistribution(Scene& scene) {
  // The background's power follows the bounding sphere, which moving instances changes.
  if (scene.backgroundLight >= 0) {
    size_t b = size_t(scene.backgroundLight);
    UpdateLightPowers(scene, b, b + 1);
  }
  FillDistribution(scene.lightPower, scene);
}

}  // namespace pt
