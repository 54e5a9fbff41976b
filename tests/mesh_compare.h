// Compares two loaded triangle meshes whatever their vertex and triangle order (Draco
// reorders both): every corner's position is snapped to the nearest distinct position of the
// reference (a hash grid, so large meshes stay fast), each triangle keyed by the snapped
// positions' ids rotated to start at the smallest (winding kept), and the sorted keys compared
// with the corners' normals and UVs.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "src/scene/scene.h"

namespace pt::test {

struct MeshCompareTolerance {
  float position = 0.0f, normal = 0.0f, uv = 0.0f;  // 0: exact
};

struct MeshCompareResult {
  size_t triangles = 0;       // of the reference
  size_t unmatched = 0;       // decoded triangles whose key the reference lacks
  size_t farCorners = 0;      // decoded corners farther than the tolerance from any reference one
  size_t attributeMisses = 0; // matched triangles whose normals or UVs differ beyond tolerance
};

class MeshComparer {
 public:
  MeshComparer(const SceneDesc& reference, float cell) : cell_(std::max(cell, 1e-6f)) {
    for (const Triangle& t : reference.triangles)
      for (vec3 p : {t.p0, t.p1, t.p2}) Id(p, true);
  }

  MeshCompareResult Compare(const SceneDesc& ref, const SceneDesc& dec, MeshCompareTolerance tol) {
    MeshCompareResult r;
    r.triangles = ref.triangles.size();
    auto refKeys = Keys(ref, 0.0f, nullptr);
    auto decKeys = Keys(dec, tol.position, &r.farCorners);
    std::multimap<std::array<int, 3>, size_t> byKey;
    for (size_t i = 0; i < refKeys.size(); ++i) byKey.emplace(refKeys[i].first, i);
    for (const auto& [key, t] : decKeys) {
      auto range = byKey.equal_range(key);
      if (range.first == range.second) {
        ++r.unmatched;
        continue;
      }
      bool same = false;
      for (auto it = range.first; it != range.second && !same; ++it) {
        same = SameAttributes(ref, refKeys[it->second].second, dec, t, tol);
        if (same) byKey.erase(it);
      }
      if (!same) {
        ++r.attributeMisses;
        byKey.erase(range.first);
      }
    }
    return r;
  }

 private:
  using Cell = std::tuple<int64_t, int64_t, int64_t>;
  struct CellHash {
    size_t operator()(const Cell& c) const {
      return size_t(std::get<0>(c) * 73856093 ^ std::get<1>(c) * 19349663 ^ std::get<2>(c) * 83492791);
    }
  };

  Cell CellOf(vec3 p) const {
    return {int64_t(std::floor(p.x / cell_)), int64_t(std::floor(p.y / cell_)),
            int64_t(std::floor(p.z / cell_))};
  }

  // The id of the reference position nearest p (added when `add` and none is equal); its
  // distance in *distance.
  int Id(vec3 p, bool add, float* distance = nullptr) {
    Cell c = CellOf(p);
    int best = -1;
    float bestD = INFINITY;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = grid_.find({std::get<0>(c) + dx, std::get<1>(c) + dy, std::get<2>(c) + dz});
          if (it == grid_.end()) continue;
          for (int id : it->second) {
            float d = glm::length(points_[size_t(id)] - p);
            if (d < bestD) bestD = d, best = id;
          }
        }
    if (add && bestD != 0.0f) {
      points_.push_back(p);
      best = int(points_.size()) - 1;
      grid_[c].push_back(best);
      bestD = 0.0f;
    }
    if (distance) *distance = bestD;
    return best;
  }

  // Per triangle: its key and its index.
  std::vector<std::pair<std::array<int, 3>, size_t>> Keys(const SceneDesc& s, float tol,
                                                          size_t* far) {
    std::vector<std::pair<std::array<int, 3>, size_t>> keys;
    for (size_t i = 0; i < s.triangles.size(); ++i) {
      const Triangle& t = s.triangles[i];
      std::array<int, 3> k;
      int c = 0;
      for (vec3 p : {t.p0, t.p1, t.p2}) {
        float d = 0.0f;
        k[size_t(c++)] = Id(p, false, &d);
        if (far && !(d <= tol)) ++*far;
      }
      std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
      keys.push_back({k, i});
    }
    return keys;
  }

  bool SameAttributes(const SceneDesc& a, size_t ta, const SceneDesc& b, size_t tb,
                      MeshCompareTolerance tol) {
    // Corners in key order: the corner with the smallest position id first.
    auto order = [&](const SceneDesc& s, size_t t) {
      const Triangle& tri = s.triangles[t];
      int ids[3] = {Id(tri.p0, false), Id(tri.p1, false), Id(tri.p2, false)};
      int first = int(std::min_element(ids, ids + 3) - ids);
      return first;
    };
    int fa = order(a, ta), fb = order(b, tb);
    for (int k = 0; k < 3; ++k) {
      int ca = (fa + k) % 3, cb = (fb + k) % 3;
      if (!a.triangleNormals.empty() && !b.triangleNormals.empty()) {
        const vec3* na = &a.triangleNormals[ta].n0;
        const vec3* nb = &b.triangleNormals[tb].n0;
        if (!(glm::length(na[ca] - nb[cb]) <= tol.normal)) return false;
      }
      if (!a.triangleUvs.empty() && !b.triangleUvs.empty()) {
        const vec2* ua = &a.triangleUvs[ta].uv0;
        const vec2* ub = &b.triangleUvs[tb].uv0;
        if (!(glm::length(ua[ca] - ub[cb]) <= tol.uv)) return false;
      }
    }
    return true;
  }

  float cell_;
  std::vector<vec3> points_;
  std::unordered_map<Cell, std::vector<int>, CellHash> grid_;
};

}  // namespace pt::test
