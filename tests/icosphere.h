// A subdivided icosahedron: the closed test mesh of several suites (watertightness, hard
// cases, smooth shading). Computed in double; each vertex is rounded to float once, so shared
// vertices are bit-identical in every triangle that uses them.
#pragma once

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "src/scene/scene_types.h"

namespace pt::test {

struct UnitIcosphere {
  std::vector<glm::dvec3> vertices;  // on the unit sphere (also the exact normals)
  std::vector<glm::uvec3> faces;     // counter-clockwise seen from outside
};

inline UnitIcosphere MakeUnitIcosphere(int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  UnitIcosphere m;
  m.vertices = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (glm::dvec3& p : m.vertices) p = glm::normalize(p);
  m.faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
             {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
             {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
             {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> middles;
    auto middle = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = middles.find(key);
      if (it != middles.end()) return it->second;
      m.vertices.push_back(glm::normalize(m.vertices[a] + m.vertices[b]));
      return middles[key] = uint32_t(m.vertices.size() - 1);
    };
    std::vector<glm::uvec3> next;
    for (glm::uvec3 f : m.faces) {
      uint32_t a = middle(f.x, f.y), b = middle(f.y, f.z), c = middle(f.z, f.x);
      next.insert(next.end(), {{f.x, a, c}, {f.y, b, a}, {f.z, c, b}, {a, b, c}});
    }
    m.faces = std::move(next);
  }
  return m;
}

// The icosphere's triangles at a centre and radius (geometric normals point out).
inline std::vector<Triangle> IcosphereTriangles(glm::dvec3 centre, double radius,
                                                int subdivisions) {
  UnitIcosphere m = MakeUnitIcosphere(subdivisions);
  std::vector<vec3> p;
  for (const glm::dvec3& v : m.vertices) p.push_back(vec3(centre + radius * v));
  std::vector<Triangle> out;
  for (glm::uvec3 f : m.faces) out.push_back(Triangle{p[f.x], p[f.y], p[f.z]});
  return out;
}

}  // namespace pt::test
