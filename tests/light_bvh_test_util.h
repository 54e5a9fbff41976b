// Hand-built scenes of many lights for the light sampler tests: no geometry BVH (primitives in
// insertion order), a real light table and light BVH.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "src/lights/light_sample.h"
#include "src/lights/light_table.h"
#include "tests/stat_test_util.h"

namespace pt::test {

struct LightTestScene {
  Scene scene;
  SceneView view;

  uint32_t AddEmissive(vec3 radiance, bool twoSided) {
    Material m;
    m.type = MaterialType::kEmissive;
    m.radiance = radiance;
    m.twoSided = twoSided ? 1u : 0u;
    scene.desc.materials.push_back(m);
    return uint32_t(scene.desc.materials.size() - 1);
  }
  void AddQuad(Quad q, uint32_t mat) {
    scene.desc.quads.push_back(q);
    AddPrim(ShapeType::kQuad, scene.desc.quads.size() - 1, mat);
  }
  void AddTriangle(Triangle t, uint32_t mat) {
    scene.desc.triangles.push_back(t);
    scene.desc.triangleNormals.push_back({});
    AddPrim(ShapeType::kTriangle, scene.desc.triangles.size() - 1, mat);
  }
  void AddSphere(Sphere s, uint32_t mat) {
    scene.desc.spheres.push_back(s);
    AddPrim(ShapeType::kSphere, scene.desc.spheres.size() - 1, mat);
  }
  void AddPrim(ShapeType type, size_t index, uint32_t mat) {
    scene.prims.push_back({PrimRef::Pack(type, uint32_t(index)), mat, -1});
  }
  void Build(LightSampler sampler) {
    BuildLightTable(scene);
    view = HostSceneView(scene);
    view.lightTree.sampler = uint32_t(sampler);
  }
};

// n finite lights of every kind at random in [-2, 2]^3: triangles, quads and spheres (one- or
// two-sided), point and spot lights, of powers over two decades; with `infinite`, a constant
// background and a sun disk too.
inline LightTestScene RandomLights(int n, uint32_t seed, bool infinite = false) {
  LightTestScene ls;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f), u01(0.0f, 1.0f);
  auto power = [&] { return vec3(std::pow(10.0f, 2.0f * u01(rng) - 1.0f)); };
  for (int i = 0; i < n; ++i) {
    vec3 c(u(rng), u(rng), u(rng));
    float size = 0.05f + 0.3f * u01(rng);
    switch (i % 6) {
      case 0:
      case 1:
        ls.AddTriangle(Triangle{c, c + size * RandomUnit(rng), c + size * RandomUnit(rng)},
                       ls.AddEmissive(power(), i % 4 == 1));
        break;
      case 2:
        ls.AddQuad(Quad{c, size * RandomUnit(rng), size * RandomUnit(rng)},
                   ls.AddEmissive(power(), i % 5 == 2));
        break;
      case 3: ls.AddSphere(Sphere{c, 0.5f * size}, ls.AddEmissive(power(), false)); break;
      case 4: ls.scene.desc.pointLights.push_back(PointLightDesc{c, power()}); break;
      default: {
        SpotLightDesc s;
        s.position = c;
        s.direction = RandomUnit(rng);
        s.intensity = power();
        s.innerAngle = 0.3f * u01(rng);
        s.outerAngle = s.innerAngle + 0.05f + 1.0f * u01(rng);
        ls.scene.desc.spotLights.push_back(s);
      }
    }
  }
  if (infinite) {
    ls.scene.desc.background = vec3(0.2f);
    DirectionalLightDesc sun;
    sun.direction = glm::normalize(vec3(0.3f, 1.0f, 0.2f));
    sun.irradiance = vec3(2.0f);
    sun.angularRadius = 0.1f;
    ls.scene.desc.directionalLights.push_back(sun);
  }
  ls.Build(LightSampler::kBvh);
  return ls;
}

// A point on light i as seen from p, whatever the choice would be: its direction in s->wi.
// False where the light sends nothing towards p (a one-sided emitter's back, outside a cone).
inline bool SampleOneLight(const SceneView& v, uint32_t i, vec3 p, vec2 u, LightLiSample* s) {
  const Light& l = v.lights[i];
  if (l.type == LightType::kArea) {
    vec3 q, n;
    vec2 param;
    float pdf;
    if (!SampleAreaLight(v, l, p, u, &q, &n, &param, &pdf)) return false;
    s->wi = glm::normalize(q - p);
    return true;
  }
  vec3 d = l.position - p;
  if (!(glm::dot(d, d) > 0.0f)) return false;
  s->wi = glm::normalize(d);
  return l.type != LightType::kSpot || l.SpotFalloff(-glm::dot(l.direction, s->wi)) > 0.0f;
}

// Irradiance at x (normal n) from a uniform Lambertian polygon wholly above x's horizon
// (Lambert's formula, in double).
inline double LambertPolygonIrradiance(const std::vector<glm::dvec3>& verts, glm::dvec3 x,
                                       glm::dvec3 n, double radiance) {
  double sum = 0.0;
  for (size_t i = 0; i < verts.size(); ++i) {
    glm::dvec3 a = glm::normalize(verts[i] - x);
    glm::dvec3 b = glm::normalize(verts[(i + 1) % verts.size()] - x);
    double angle = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
    sum += angle * glm::dot(n, glm::normalize(glm::cross(a, b)));
  }
  return 0.5 * radiance * std::fabs(sum);
}

inline std::vector<glm::dvec3> QuadCorners(const Quad& q) {
  glm::dvec3 o(q.origin), u(q.u), v(q.v);
  return {o, o + u, o + u + v, o + v};
}

// A room under a grid of small lamps (one- and two-sided), three emissive balls, a point and a
// spot light, a dim background and a sun disk through the open front.
inline std::string ManyLightRoom(int seed, int lampsPerSide = 5) {
  std::string objects = R"(
    {"type": "quad", "origin": [-2, 0, -2], "u": [0, 0, 4], "v": [4, 0, 0], "material": "white"},
    {"type": "quad", "origin": [-2, 0, -2], "u": [4, 0, 0], "v": [0, 2.5, 0], "material": "white"},
    {"type": "quad", "origin": [-2, 0, -2], "u": [0, 2.5, 0], "v": [0, 0, 4], "material": "red"},
    {"type": "sphere", "center": [-0.6, 0.45, -0.4], "radius": 0.45, "material": "glossy"},
    {"type": "sphere", "center": [0.7, 0.4, 0.2], "radius": 0.4, "material": "glass"},
    {"type": "quad", "origin": [0.6, 0.01, -1.5], "u": [0.8, 1.2, 0], "v": [0, 0, 0.8],
     "material": "white2"})";
  for (int i = 0; i < lampsPerSide; ++i)
    for (int j = 0; j < lampsPerSide; ++j) {
      float x = -1.8f + 3.6f * (i + 0.5f) / lampsPerSide, z = -1.8f + 3.6f * (j + 0.5f) / lampsPerSide;
      const char* mat = (i + j) % 3 == 0 ? "lamp2" : ((i * j) % 2 ? "lampWarm" : "lamp");
      objects += R"(,
    {"type": "quad", "origin": [)" + std::to_string(x) + ", 2.4, " + std::to_string(z) +
                 R"(], "u": [0.12, 0, 0], "v": [0, 0, 0.12], "material": ")" + mat + "\"}";
    }
  objects += R"(,
    {"type": "sphere", "center": [-1.5, 0.15, 1.2], "radius": 0.12, "material": "lamp"},
    {"type": "sphere", "center": [1.6, 1.8, -1.6], "radius": 0.08, "material": "lampWarm"},
    {"type": "sphere", "center": [0.0, 1.2, -1.9], "radius": 0.05, "material": "lamp"})";
  return R"({"format": 1,
    "render": {"width": 32, "height": 32, "spp": 8, "max_depth": 4, "seed": )" +
         std::to_string(seed) + R"(},
    "camera": {"position": [0, 1.3, 4.2], "look_at": [0, 1.0, 0], "up": [0, 1, 0], "fov_y": 50},
    "background": [0.05, 0.06, 0.08],
    "materials": {"white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
                  "red": {"type": "diffuse", "albedo": [0.6, 0.1, 0.1]},
                  "white2": {"type": "plastic", "albedo": [0.6, 0.6, 0.5], "ior": 1.5, "roughness": 0.3},
                  "glossy": {"type": "conductor", "albedo": [0.9, 0.7, 0.4], "roughness": 0.25},
                  "glass": {"type": "dielectric", "ior": 1.5, "roughness": 0.2},
                  "lamp": {"type": "emissive", "radiance": [12, 11, 9]},
                  "lampWarm": {"type": "emissive", "radiance": [20, 9, 3]},
                  "lamp2": {"type": "emissive", "radiance": [6, 8, 12], "two_sided": true}},
    "lights": [{"type": "point", "position": [1.2, 1.6, 1.0], "intensity": [2, 2, 1.5]},
               {"type": "spot", "position": [-1.5, 2.2, 1.5], "direction": [0.5, -1, -0.6],
                "intensity": [8, 8, 8], "inner_angle": 10, "outer_angle": 30},
               {"type": "directional", "direction": [0.2, 0.5, 1], "radiance": [300, 280, 250],
                "angular_radius": 2}],
    "objects": [)" + objects + "]}";
}

}  // namespace pt::test
