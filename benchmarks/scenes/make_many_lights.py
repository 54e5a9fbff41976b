#!/usr/bin/env python3
"""Writes the many-light benchmark scenes (the light BVH, issue 30): nothing but many small
emitters lights them, so how next-event estimation chooses a light decides the noise.

  city      a generated city block at night: a grid of 100 box buildings, the streets
            between them lined with festoons of small downward-facing lamps (one-sided
            emissive quads in a few tints, brightness over a decade), a faint sky, seen from
            above. --lamps N lamps in all (default 20,000).
  breakfast the Breakfast Room (../shared/assets/dining-room-bitterli, 269,538 triangles,
            one diffuse material) hung with strings of fairy lights: --bulbs N small emissive
            spheres (default 10,000) on sagging strings across the room, and no other light.

  python3 benchmarks/scenes/make_many_lights.py city [--lamps N] [OUT.json]
  python3 benchmarks/scenes/make_many_lights.py breakfast [--bulbs N] [OUT.json]

Default OUT: benchmarks/scenes/many_lights_city.json / many_lights_breakfast.json (generated,
not tracked). Fixed seeds: the same arguments always write the same file.
"""
import argparse
import json
import math
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))
TINTS = {"warm": [9.0, 6.5, 3.5], "cool": [4.5, 6.0, 9.0], "neutral": [7.0, 7.0, 6.5],
         "sodium": [14.0, 8.0, 2.0]}


def quad(origin, u, v, material):
    return {"type": "quad", "origin": [round(c, 5) for c in origin],
            "u": [round(c, 5) for c in u], "v": [round(c, 5) for c in v], "material": material}


def city(args):
    rng = random.Random(1)
    blocks, street, lot = 10, 8.0, 14.0  # 10 x 10 buildings, streets 8 wide
    extent = blocks * (lot + street)
    objects = [quad([-extent / 2, 0, -extent / 2], [0, 0, extent], [extent, 0, 0], "asphalt")]
    buildings, lamps = [], set()
    for i in range(blocks):
        for j in range(blocks):
            x0 = -extent / 2 + street / 2 + i * (lot + street)
            z0 = -extent / 2 + street / 2 + j * (lot + street)
            w, d = lot * rng.uniform(0.6, 1.0), lot * rng.uniform(0.6, 1.0)
            h = rng.uniform(12.0, 60.0) * (1.6 if (i, j) in ((2, 3), (3, 2)) else 1.0)
            buildings.append((x0, z0, w, d, h))
            objects.append({"type": "box", "min": [x0, 0, z0], "max": [x0 + w, h, z0 + d],
                            "material": "concrete"})
    # Festoons along both sides of every street, 1.5 m in front of the building line and 5 m
    # up: small one-sided lamps facing down (from above they show their dark backs, so the
    # picture's noise is that of the light they cast), brightness and tint varying.
    lines = []
    for k in range(blocks + 1):
        centre = -extent / 2 + k * (lot + street)
        for side in (-1.0, 1.0):
            off = centre + side * (street / 2 - 1.5)
            if -extent / 2 < off < extent / 2:
                lines.append(("x", off))
                lines.append(("z", off))
    spacing = len(lines) * extent / args.lamps
    size = 0.3
    for axis, off in lines:
        t = -extent / 2 + spacing / 2
        while t < extent / 2 - size:
            tint = rng.choices(list(TINTS), weights=[5, 2, 2, 1])[0]
            scale = round(rng.uniform(0.3, 3.0), 3)
            name = "%s_%d" % (tint, int(scale * 2))
            x, z = (t, off) if axis == "x" else (off, t)
            # normal = cross(u, v) = -y
            objects.append(quad([x, 5.0, z], [size, 0, 0], [0, 0, size], name))
            lamps.add(name)
            t += spacing
    materials = {"asphalt": {"type": "diffuse", "albedo": [0.25, 0.25, 0.26]},
                 "concrete": {"type": "diffuse", "albedo": [0.45, 0.43, 0.4]}}
    for name in sorted(lamps):
        tint, level = name.rsplit("_", 1)
        scale = 4.0 * (int(level) + 1) / 2.0
        materials[name] = {"type": "emissive", "radiance": [c * scale for c in TINTS[tint]]}
    return {
        "format": 1,
        "render": {"width": 960, "height": 540, "spp": 64, "max_depth": 6, "seed": 1},
        # From high above, looking down into the lit streets.
        "camera": {"position": [0.0, extent * 1.1, extent * 0.35], "look_at": [0, 0, 0],
                   "up": [0, 1, 0], "fov_y": 40},
        "background": [0.002, 0.003, 0.006],
        "materials": materials,
        "objects": objects,
    }


def breakfast(args):
    rng = random.Random(2)
    glb = "../../../shared/assets/dining-room-bitterli/dining-room.glb"
    objects = [{"type": "mesh", "file": glb, "material": "white"}]
    strings = max(1, args.bulbs // 100)
    per = args.bulbs // strings
    for s in range(strings):
        # A string between two points near the walls or ceiling, sagging by a parabola.
        a = [rng.uniform(-4.5, 4.0), rng.uniform(3.2, 5.6), rng.uniform(-3.5, 8.5)]
        b = [rng.uniform(-4.5, 4.0), rng.uniform(3.2, 5.6), rng.uniform(-3.5, 8.5)]
        sag = rng.uniform(0.3, 1.2)
        tint = rng.choice(["warm", "warm", "neutral", "cool"])
        for k in range(per):
            t = (k + 0.5) / per
            p = [a[i] + t * (b[i] - a[i]) for i in range(3)]
            p[1] -= sag * 4.0 * t * (1.0 - t)
            objects.append({"type": "sphere", "center": [round(c, 5) for c in p],
                            "radius": 0.012, "material": tint})
    materials = {"white": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]}}
    for name, radiance in TINTS.items():
        materials[name] = {"type": "emissive", "radiance": [c * 40.0 for c in radiance]}
    return {
        "format": 1,
        "render": {"width": 960, "height": 540, "spp": 64, "max_depth": 6, "seed": 1},
        "camera": {"position": [-0.58732, 2.7623, 9.71429], "look_at": [-0.57426, 2.69844, 8.71642],
                   "up": [0.00084, 0.99796, -0.06386], "fov_y": 35.9834},
        "background": [0, 0, 0],
        "materials": materials,
        "objects": objects,
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("scene", choices=["city", "breakfast"])
    p.add_argument("--lamps", type=int, default=20000)
    p.add_argument("--bulbs", type=int, default=10000)
    p.add_argument("out", nargs="?", default=None)
    args = p.parse_args()
    out = args.out or os.path.join(HERE, "many_lights_%s.json" % args.scene)
    scene = city(args) if args.scene == "city" else breakfast(args)
    if args.scene == "breakfast" and os.path.dirname(os.path.abspath(out)) != HERE:
        # The mesh path is relative to the scene file: keep it valid from elsewhere.
        glb = os.path.normpath(os.path.join(HERE, scene["objects"][0]["file"]))
        scene["objects"][0]["file"] = glb
    with open(out, "w") as f:
        json.dump(scene, f, separators=(",", ":"))
        f.write("\n")
    lights = sum(1 for o in scene["objects"]
                 if scene["materials"][o["material"]]["type"] == "emissive")
    print("%s: %d emitters, %d objects" % (out, lights, len(scene["objects"])))


if __name__ == "__main__":
    main()
