#!/usr/bin/env python3
"""Writes leak_sphere.obj: a closed icosphere (unit radius, centred at the origin) for the
ray-leak study in benchmarks/accuracy.py (scene: benchmarks/scenes/leak_sphere.json).

Every face is wound clockwise seen from outside, so its geometric normal
cross(v1 - v0, v2 - v0) points INTO the sphere: with a one-sided emissive material the sphere
is black seen from outside and glows only on its inner side. A camera ray that hits the
outside stops with radiance 0; only a ray that slips through an edge of the near side
(a leak) reaches the glowing far side. So inside the silhouette, pixel value / radiance =
the fraction of camera rays that leaked (a leak through both near and far side, which would
see the black background, is a second-order event, counted as not leaked).

Deterministic (pure Python, no dependencies): `python3 make_leak_sphere.py [LEVEL] [OUT]`.
Level 5 (default) = 20,480 triangles, 30,720 shared edges.
"""
import math
import os
import sys


def icosphere(level):
    t = (1.0 + math.sqrt(5.0)) / 2.0
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        cache = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = [(verts[a][i] + verts[b][i]) * 0.5 for i in range(3)]
                n = math.sqrt(sum(x * x for x in m))
                verts.append(tuple(x / n for x in m))
                cache[key] = len(verts) - 1
            return cache[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return verts, faces


def main():
    level = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__),
                                                             "leak_sphere.obj")
    verts, faces = icosphere(level)
    # The icosahedron's faces are counter-clockwise from outside (outward normals); write
    # them reversed so that every normal points inwards.
    lines = ["# closed icosphere, level %d: %d vertices, %d triangles, normals point inwards\n"
             % (level, len(verts), len(faces)),
             "# written by benchmarks/scenes/meshes/make_leak_sphere.py\n"]
    lines += ["v %.9g %.9g %.9g\n" % v for v in verts]
    lines += ["f %d %d %d\n" % (a + 1, c + 1, b + 1) for a, b, c in faces]
    with open(out, "w") as f:
        f.writelines(lines)
    print("wrote %s: %d triangles" % (out, len(faces)))


if __name__ == "__main__":
    main()
