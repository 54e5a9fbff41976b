// Hard geometric cases, part 2: shared edges and vertices of meshes far from the origin, rays
// inside a surface's plane, and surfaces 1e-5 apart. Deterministic (fixed seeds, exact
// double-precision references).
#include <gtest/gtest.h>

#include "tests/icosphere.h"

#include "tests/hard_geometry_util.h"

namespace pt {
namespace {

using namespace pt::hard;

// ---- Shared edges and vertices far from the origin ----

// A closed, tessellated axis-aligned cube whose grid coordinates are each one float.
std::vector<Triangle> TessellatedCube(dvec3 center, double half, int n, std::vector<float> grid[3]) {
  for (int a = 0; a < 3; ++a) {
    grid[a].clear();
    for (int i = 0; i <= n; ++i) grid[a].push_back(float(center[a] - half + 2.0 * half * i / n));
  }
  std::vector<Triangle> out;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side : {0, n}) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          vec3 p[4];
          for (int q = 0; q < 4; ++q) {
            glm::ivec3 idx;
            idx[axis] = side;
            idx[(axis + 1) % 3] = i + (q == 1 || q == 2);
            idx[(axis + 2) % 3] = j + (q >= 2);
            p[q] = vec3(grid[0][idx.x], grid[1][idx.y], grid[2][idx.z]);
          }
          bool flip = (i + j) % 2 == 1;
          out.push_back(flip ? Triangle{p[0], p[1], p[3]} : Triangle{p[0], p[1], p[2]});
          out.push_back(flip ? Triangle{p[1], p[2], p[3]} : Triangle{p[0], p[2], p[3]});
        }
      }
    }
  }
  return out;
}

// Rays from outside aimed exactly at a vertex or at a point of a shared edge (the point rounded
// to float, so it lies within an ulp of the edge), continuing to a point inside: each must
// enter the closed mesh there - never slip through the crack between two triangles to the far
// side or out. The target is exactly on the float mesh; rounding the origin to float moves the
// ray sideways by at most eps |o|_1, which moves the hit along the ray by that times
// (1 + tan(incidence)) < 2 for rays aimed inside the inner ball (incidence < 35 deg); the
// renderer's own rounding of p - o adds a few eps |p - o|. Tolerance: 8 eps |o|_1 + 64 eps dist
// (1.4e-2 at 1e4, against a slip-through error of at least the mesh's chord, > 0.5 radius).
int TraceAtMeshEdges(const ShapeScene& s, const std::vector<Triangle>& tris, dvec3 center,
                     double innerRadius, int rays, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> g;
  std::uniform_int_distribution<size_t> pick(0, tris.size() - 1);
  int failures = 0;
  for (int i = 0; i < rays; ++i) {
    const Triangle& tri = tris[pick(rng)];
    const vec3 corner[3] = {tri.p0, tri.p1, tri.p2};
    int e = int(u01(rng) * 3.0) % 3;
    dvec3 target = i % 4 == 0 ? dvec3(corner[e])
                              : glm::mix(dvec3(corner[e]), dvec3(corner[(e + 1) % 3]), u01(rng));
    dvec3 inner = center + glm::normalize(dvec3(g(rng), g(rng), g(rng))) *
                               (innerRadius * std::cbrt(u01(rng)));
    double dist = 0.05 * innerRadius + 3.0 * innerRadius * u01(rng);
    vec3 o = vec3(target + glm::normalize(target - inner) * dist);
    Ray ray{o, vec3(glm::normalize(target - dvec3(o)))};
    double expected = glm::length(target - dvec3(o));
    double tol = 8.0 * kEps * (std::fabs(o.x) + std::fabs(o.y) + std::fabs(o.z)) + 64.0 * kEps * dist;
    HitRecord hit;
    bool ok = IntersectClosest(s.view, ray, kInfinity, &hit, nullptr) &&
              std::fabs(hit.t - expected) <= tol;
    if (i % 8 == 0) ok = ok && IntersectAny(s.view, ray, kInfinity, nullptr);
    if (!ok && ++failures <= 5)
      ADD_FAILURE() << "ray " << i << " hit " << hit.prim << " t " << hit.t << " vs " << expected
                    << " (tol " << tol << ")";
  }
  return failures;
}

TEST_P(HardLayout, WatertightAtSharedEdgesOfMeshesFarFromTheOrigin) {
  // Unit-size and kilometre-size meshes at offset 1e4 (float spacing there is ~1e-3) and 1e5.
  struct Case { dvec3 center; double radius; };
  for (Case c : {Case{dvec3(1e4, -1e4, 1e4), 1.0}, Case{dvec3(1e4, 1e4, -1e4), 1e3},
                 Case{dvec3(-1e5, 2e5, 1e5), 50.0}}) {
    std::vector<Triangle> sphere = test::IcosphereTriangles(c.center, c.radius, 4);
    ShapeScene s = BuildShapes(sphere);
    EXPECT_EQ(TraceAtMeshEdges(s, sphere, c.center, 0.5 * c.radius, 40000, 11), 0)
        << "icosphere at " << c.center.x << " radius " << c.radius;
  }
  dvec3 center(1e4 + 0.3, -1e4 + 0.7, 1e4 - 0.2);
  std::vector<float> grid[3];
  std::vector<Triangle> cube = TessellatedCube(center, 1.0, 12, grid);
  ShapeScene s = BuildShapes(cube);
  EXPECT_EQ(TraceAtMeshEdges(s, cube, center, 0.8, 40000, 12), 0);

  // Axis-aligned rays exactly through the grid's vertices and along its edges' lines, where the
  // edge functions are exactly 0 and the double-precision fallback decides: every one must hit
  // the first face at the grid coordinate. face - o is exact (Sterbenz), and t = sum(e_i z) /
  // sum(e_i) rounds a few times: within 8 eps relative.
  int failures = 0, rays = 0;
  for (int axis = 0; axis < 3; ++axis) {
    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int i = 0; i <= 12; ++i) {
      for (int j = 0; j <= 12; ++j) {
        for (int dir : {-1, 1}) {
          vec3 o, d(0.0f);
          o[axis] = float(center[axis] - 5.0 * dir);
          o[a1] = grid[a1][i];
          o[a2] = grid[a2][j];
          d[axis] = float(dir);
          float face = dir > 0 ? grid[axis].front() : grid[axis].back();
          HitRecord hit;
          ++rays;
          bool ok = IntersectClosest(s.view, Ray{o, d}, kInfinity, &hit, nullptr);
          double expected = std::fabs(double(face) - double(o[axis]));
          ok = ok && std::fabs(hit.t - expected) <= 8.0 * kEps * expected;
          if (!ok && ++failures <= 5)
            ADD_FAILURE() << "axis " << axis << " grid " << i << "," << j << " t " << hit.t;
        }
      }
    }
  }
  EXPECT_EQ(failures, 0) << "of " << rays;
}

// ---- Rays inside a surface's plane ----

// Rays running exactly inside the plane of a tessellated floor (along its grid lines, through
// its vertices and across its triangles) must not report the floor - every triangle and quad
// is seen edge-on, det = 0 - and must still find the sphere resting on it, at the right t,
// with no NaN anywhere. The same for rays spawned from a floor point along the tangent plane.
TEST_P(HardLayout, RaysInsideASurfacePlaneReportNoSpuriousHits) {
  for (float scale : {1e-4f, 1.0f, 1e4f}) {
    std::vector<Triangle> floor;
    const int n = 8;
    auto at = [&](int i, int j) { return vec3(scale * (-4.0f + i), 0.0f, scale * (-4.0f + j)); };
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        floor.push_back(Triangle{at(i, j), at(i, j + 1), at(i + 1, j + 1)});
        floor.push_back(Triangle{at(i, j), at(i + 1, j + 1), at(i + 1, j)});
      }
    Quad quadFloor{vec3(-4.0f * scale, 0.0f, 5.0f * scale), vec3(8.0f * scale, 0, 0),
                   vec3(0, 0, 3.0f * scale)};
    Sphere ball{vec3(0.0f, scale, 0.0f), scale};  // touches the floor at the origin
    ShapeScene s = BuildShapes(floor, {quadFloor}, {ball});
    int failures = 0, rays = 0;
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int k = 0; k < 4000; ++k) {
      // Origins in the plane y = 0: grid vertices, grid lines, or anywhere; directions along
      // grid lines, diagonals or arbitrary, all with d.y = 0 exactly.
      vec3 o(scale * 6.0f * u(rng), 0.0f, scale * 6.0f * u(rng));
      if (k % 3 == 0) o = at(int(4 + 4 * u(rng)), int(4 + 4 * u(rng)));
      if (k % 3 == 1) o.x = at(int(4 + 4 * u(rng)), 0).x;
      vec3 d;
      if (k % 4 == 0) d = vec3(k % 8 == 0 ? 1.0f : -1.0f, 0.0f, 0.0f);
      else if (k % 4 == 1) d = vec3(0.0f, 0.0f, k % 8 == 1 ? 1.0f : -1.0f);
      else if (k % 4 == 2) d = glm::normalize(vec3(1.0f, 0.0f, k % 8 == 2 ? 1.0f : -1.0f));
      else d = glm::normalize(vec3(u(rng), 0.0f, u(rng)));
      d.y = 0.0f;
      if (!(glm::length(d) > 0.5f)) continue;
      HitRecord hit;
      ++rays;
      bool any = IntersectAny(s.view, Ray{o, d}, kInfinity, nullptr);
      bool found = IntersectClosest(s.view, Ray{o, d}, kInfinity, &hit, nullptr);
      bool ok = found == any &&
                (!found || (std::isfinite(hit.t) && std::isfinite(hit.uv.x) &&
                            std::isfinite(hit.uv.y)));
      if (found) {
        // Only the ball may be hit: at its touching point (the origin), which lies in the plane.
        PrimRef ref = s.view.prims[hit.prim];
        dvec3 p = dvec3(o) + double(hit.t) * dvec3(d);
        ok = ok && ref.Type() == ShapeType::kSphere &&
             glm::length(p) <= 1e-3 * scale + 16.0 * kEps * glm::length(dvec3(o));
      }
      if (!ok && ++failures <= 5)
        ADD_FAILURE() << "scale " << scale << " ray " << k << " found " << found << " any " << any
                      << " t " << hit.t;
    }
    EXPECT_EQ(failures, 0) << "of " << rays << " at scale " << scale;

    // Rays 1 ulp above the floor, aimed at the ball's centre height: must hit the ball first.
    HitRecord hit;
    vec3 o(-3.5f * scale, NextFloatUp(0.0f), 0.0f);
    ASSERT_TRUE(IntersectClosest(s.view, Ray{o, vec3(1, 0, 0)}, kInfinity, &hit, nullptr));
    EXPECT_EQ(s.view.prims[hit.prim].Type(), ShapeType::kSphere);
    o.y = scale;
    ASSERT_TRUE(IntersectClosest(s.view, Ray{o, vec3(1, 0, 0)}, kInfinity, &hit, nullptr));
    EXPECT_NEAR(hit.t, 2.5f * scale, 1e-5f * scale);

    // A ray spawned from a floor hit along the tangent plane (dot(w, n) == 0) leaves from
    // above the floor and never re-hits it.
    for (int k = 0; k < 200; ++k) {
      Ray down{vec3(scale * 3.0f * u(rng), scale, scale * 3.0f * u(rng) - 0.0f), vec3(0, -1, 0)};
      if (glm::length(vec2(down.o.x, down.o.z)) < 1.5f * scale) continue;  // not above the ball
      ASSERT_TRUE(IntersectClosest(s.view, down, kInfinity, &hit, nullptr));
      SurfaceInteraction si = MakeInteraction(s.view, down, hit);
      vec3 w = glm::normalize(vec3(u(rng), 0.0f, u(rng)));
      vec3 origin = OffsetRayOrigin(si.p, si.pError, si.ng, w);
      EXPECT_TRUE(IsFinite(origin));
      HitRecord again;
      bool found = IntersectClosest(s.view, Ray{origin, w}, kInfinity, &again, nullptr);
      if (found) {
        EXPECT_EQ(s.view.prims[again.prim].Type(), ShapeType::kSphere) << "scale " << scale;
      }
    }
  }
}

// ---- Surfaces 1e-5 apart (relative to the scene's size) ----

// The exact (double) distance along a float ray to the float primitive hit.record names: its
// plane for a triangle or quad, its nearest root beyond the origin for a sphere.
double ExactT(const ShapeScene& s, const Ray& ray, const HitRecord& hit) {
  PrimRef ref = s.view.prims[hit.prim];
  const SceneDesc& d = s.scene.desc;
  if (ref.Type() == ShapeType::kQuad) {
    const Quad& q = d.quads[ref.Index()];
    return ExactPlaneT(ray, dvec3(q.origin), glm::cross(dvec3(q.u), dvec3(q.v)));
  }
  if (ref.Type() == ShapeType::kTriangle) {
    const Triangle& t = d.triangles[ref.Index()];
    return ExactPlaneT(ray, dvec3(t.p0),
                       glm::cross(dvec3(t.p1) - dvec3(t.p0), dvec3(t.p2) - dvec3(t.p0)));
  }
  const Sphere& sp = d.spheres[ref.Index()];
  dvec3 f = dvec3(ray.o) - dvec3(sp.center), dd(ray.d);
  double a = glm::dot(dd, dd), b = glm::dot(f, dd) / a;
  double c = (glm::dot(f, f) - double(sp.radius) * sp.radius) / a;
  double root = std::sqrt(std::max(0.0, b * b - c));
  return -b - root > 0.0 ? -b - root : -b + root;
}

// Two parallel quads, two parallel (tilted) triangles and two concentric spheres whose surfaces
// are 1e-5 * size apart, at sizes 1e-3, 1 and 1e4 and at offsets from the origin up to the size
// itself (the gap must exceed the float spacing of the coordinates: 1e-5 of a size at an
// offset of the size is ~170 ulps). From outside, the upper surface is hit first; from that
// hit (origin pushed through by OffsetRayOrigin), the lower one is next; from the lower one
// going back up, the upper one. Each t must match the exact distance along the float ray to
// within 5% of the gap: t's own rounding is a few eps * size (< 0.5% of the gap), while
// hitting the wrong surface is off by the whole gap.
TEST_P(HardLayout, SurfacesOneHundredThousandthApartStayDistinct) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int failures = 0, checks = 0;
  for (double size : {1e-3, 1.0, 1e4}) {
    for (double offset : {0.0, 0.37, 1.0}) {
      double gap = 1e-5 * size;
      dvec3 base = dvec3(0.3, 0.6, -0.8) * offset * size;
      const dvec3 triNormal = glm::normalize(dvec3(0.2, 1.0, 0.1));
      const dvec3 triCenter = base + dvec3(3.0 * size, 0.0, 0.0);
      float yLo = float(base.y), yHi = float(base.y + gap);
      std::vector<Quad> quads;
      std::vector<Triangle> tris;
      for (int upper = 0; upper < 2; ++upper) {
        float y = upper ? yHi : yLo;
        quads.push_back(Quad{vec3(float(base.x - size), y, float(base.z - size)),
                             vec3(float(2 * size), 0, 0), vec3(0, 0, float(2 * size))});
        dvec3 c = triCenter + (upper ? gap : 0.0) * triNormal;
        dvec3 a = glm::normalize(glm::cross(triNormal, dvec3(0, 0, 1))), b = glm::cross(a, triNormal);
        tris.push_back(Triangle{vec3(c - size * a - size * b), vec3(c + size * a - size * b),
                                vec3(c + size * b)});
      }
      dvec3 sc = base + dvec3(-3.0 * size, 0.0, 0.0);
      std::vector<Sphere> spheres = {Sphere{vec3(sc), float(size)},
                                     Sphere{vec3(sc), float(size + gap)}};
      ShapeScene s = BuildShapes(tris, quads, spheres);
      auto isUpper = [&](const HitRecord& h) {
        PrimRef r = s.view.prims[h.prim];
        switch (r.Type()) {
          case ShapeType::kQuad: return s.scene.desc.quads[r.Index()].origin.y == yHi;
          case ShapeType::kTriangle: return r.Index() == 1;
          default: return s.scene.desc.spheres[r.Index()].radius > float(size);
        }
      };
      auto fail = [&](int which, const char* what, double t, double exact) {
        if (++failures <= 8)
          ADD_FAILURE() << "size " << size << " offset " << offset << " shape " << which << ": "
                        << what << " (t " << t << ", exact " << exact << ", gap " << gap << ")";
      };
      for (int k = 0; k < 300; ++k) {
        int which = k % 3;  // 0 quads, 1 triangles, 2 spheres
        dvec3 n, target;
        if (which == 0) {
          n = dvec3(0, 1, 0);
          target = base + dvec3((u01(rng) - 0.5) * size, 0.0, (u01(rng) - 0.5) * size);
        } else if (which == 1) {
          n = triNormal;
          target = triCenter + 0.3 * size * dvec3(u01(rng) - 0.5, 0.0, u01(rng) - 0.5);
          target -= glm::dot(target - triCenter, n) * n;
        } else {
          n = glm::normalize(dvec3(u01(rng) - 0.5, 1.0, u01(rng) - 0.5));
          target = sc + size * n;
        }
        dvec3 tilt = glm::normalize(glm::cross(n, dvec3(1, 0, 0)));
        dvec3 dirIn = glm::normalize(-n + (u01(rng) * 1.5) * tilt);  // 0..56 deg off the normal
        Ray ray{vec3(target - 0.5 * size * dirIn), vec3(dirIn)};
        ++checks;
        HitRecord h1;
        if (!IntersectClosest(s.view, ray, kInfinity, &h1, nullptr) || !isUpper(h1)) {
          fail(which, "the upper surface is not hit first", h1.t, 0.0);
          continue;
        }
        SurfaceInteraction si = MakeInteraction(s.view, ray, h1);
        Ray through{OffsetRayOrigin(si.p, si.pError, si.ng, ray.d), ray.d};
        HitRecord h2;
        if (!IntersectClosest(s.view, through, kInfinity, &h2, nullptr) || isUpper(h2)) {
          fail(which, "the lower surface is not next", h2.t, 0.0);
          continue;
        }
        double exact2 = ExactT(s, through, h2);
        if (!(std::fabs(h2.t - exact2) <= 0.05 * gap)) fail(which, "lower t", h2.t, exact2);
        SurfaceInteraction lo = MakeInteraction(s.view, through, h2);
        vec3 up = vec3(glm::normalize(n + 0.3 * (u01(rng) - 0.5) * tilt));
        Ray back{OffsetRayOrigin(lo.p, lo.pError, lo.ng, up), up};
        HitRecord h3;
        if (!IntersectClosest(s.view, back, kInfinity, &h3, nullptr) || !isUpper(h3)) {
          fail(which, "going up does not hit the upper surface", h3.t, 0.0);
          continue;
        }
        double exact3 = ExactT(s, back, h3);
        if (!(std::fabs(h3.t - exact3) <= 0.05 * gap)) fail(which, "upper t", h3.t, exact3);
        if (!(h3.t * glm::dot(dvec3(up), n) <= 1.5 * gap)) fail(which, "not the gap", h3.t, gap);
      }
    }
  }
  EXPECT_EQ(failures, 0) << "of " << checks;
}

}  // namespace
}  // namespace pt
