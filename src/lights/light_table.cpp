#include "src/lights/light_table.h"

#include "src/lights/light_sample.h"

namespace pt {

namespace {

// Whether a material emits: emissive, or glTF with an emissive factor.
bool Emits(const Material& m) {
  return (m.type == MaterialType::kEmissive || m.type == MaterialType::kGltfPbr) &&
         !IsBlack(m.radiance);
}

// Mean luminance of a glTF emissive texture over a primitive (1 without one), which scales
// the light's power and so the probability of choosing it: 16 stratified points, each read at
// the mip level whose footprint is a sixteenth of the primitive, so the mean covers its area.
// Next-event estimation reads the texture at the sampled point; this estimate only shapes the
// choice (a primitive estimated dark is no light, and BSDF sampling alone finds it).
double EmissionScale(const SceneView& view, const PrimRef& prim, double area) {
  const Material& m = view.materials[prim.material];
  if (m.type != MaterialType::kGltfPbr || m.emissiveTexture < 0) return 1.0;
  constexpr int kGrid = 4;
  float width = float(std::sqrt(area / (kGrid * kGrid)));
  double sum = 0.0;
  for (int i = 0; i < kGrid * kGrid; ++i) {
    vec2 u((float(i % kGrid) + 0.5f) / kGrid, (float(i / kGrid) + 0.5f) / kGrid);
    vec2 param = u;  // quads: (s, t)
    if (prim.Type() == ShapeType::kTriangle) {
      vec2 b = SampleUniformTriangle(u);
      param = vec2(b.y, 1.0f - b.x - b.y);
    }
    TexCoords tc = TexCoordsAt(view, prim, param, width);
    sum += double(Luminance(vec3(SampleTextureRef(view, m.emissiveTexture, tc))));
  }
  return sum / (kGrid * kGrid);
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

}  // namespace

double LightPower(const Scene& scene, const Light& light) {
  switch (light.type) {
    case LightType::kArea: {
      double area = PrimArea(scene.desc, scene.prims[light.prim]);
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
  SceneView view = HostSceneView(scene);
  std::vector<double> emissionScale;  // per area light, for its power
  for (size_t i = 0; i < scene.prims.size(); ++i) {
    PrimRef& prim = scene.prims[i];
    prim.light = -1;
    const Material& m = desc.materials[prim.material];
    if (!Emits(m)) continue;
    double scale = EmissionScale(view, prim, PrimArea(desc, prim));
    if (!(scale > 0.0)) continue;  // dark where sampled: left to BSDF sampling
    Light light;
    light.type = LightType::kArea;
    light.prim = uint32_t(i);
    light.radiance = m.radiance;
    light.twoSided = m.twoSided;
    prim.light = int32_t(scene.lights.size());
    scene.lights.push_back(light);
    emissionScale.push_back(scale);
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
  std::vector<double> power;
  power.reserve(scene.lights.size());
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    double scale = i < emissionScale.size() ? emissionScale[i] : 1.0;  // area lights come first
    power.push_back(LightPower(scene, scene.lights[i]) * scale);
  }
  FillDistribution(power, scene);
}

}  // namespace pt
