#!/usr/bin/env python3
"""Writes the many-light benchmark scenes (the light BVH, issue 30): nothing but many small
emitters lights them, so how next-event estimation chooses a light decides the noise.

  city      a generated city block at night: a grid of box buildings whose faces carry
            lit windows (small one-sided emissive quads facing out, in a few warm and cool
            tints), street lamps (small emissive spheres) along the streets, a faint sky.
            --windows N windows in all (default 50,000).
  breakfast the Breakfast Room (../shared/assets/dining-room-bitterli, 269,538 triangles,
            one diffuse material) hung with strings of fairy lights: --bulbs N small emissive
            spheres (default 10,000) on sagging strings across the room, and no other light.

  python3 benchmarks/scenes/make_many_lights.py city [--windows N] [OUT.json]
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
    buildings = []
    for i in range(blocks):
        for j in range(blocks):
            x0 = -extent / 2 + street / 2 + i * (lot + street)
            z0 = -extent / 2 + street / 2 + j * (lot + street)
            w, d = lot * rng.uniform(0.6, 1.0), lot * rng.uniform(0.6, 1.0)
            h = rng.uniform(12.0, 60.0) * (1.6 if (i, j) in ((2, 3), (3, 2)) else 1.0)
            buildings.append((x0, z0, w, d, h))
            objects.append({"type": "box", "min": [x0, 0, z0], "max": [x0 + w, h, z0 + d],
                            "material": "concrete"})
    # Window slots on every face, 1 m apart, 2.5 m per storey; a share of them lit.
    slots = []
    for (x0, z0, w, d, h) in buildings:
        for face in range(4):
            length = w if face < 2 else d
            cols, rows = int(length / 1.0), int(h / 2.5)
            for c in range(cols):
                for r in range(rows):
                    slots.append((x0, z0, w, d, face, c, r))
    rng.shuffle(slots)
    eps = 0.02  # off the wall, so the window is not inside the box
    for (x0, z0, w, d, face, c, r) in slots[:args.windows]:
        y = 2.5 * r + 0.9
        a = 1.0 * c + 0.2
        tint = rng.choices(list(TINTS)[:3], weights=[6, 2, 2])[0]
        # One-sided quads facing out of the building: normal = cross(u, v).
        if face == 0:    # z = z0 face, normal -z
            objects.append(quad([x0 + a, y, z0 - eps], [0, 1.0, 0], [0.6, 0, 0], tint))
        elif face == 1:  # z = z0 + d face, normal +z
            objects.append(quad([x0 + a, y, z0 + d + eps], [0.6, 0, 0], [0, 1.0, 0], tint))
        elif face == 2:  # x = x0 face, normal -x
            objects.append(quad([x0 - eps, y, z0 + a], [0, 0, 0.6], [0, 1.0, 0], tint))
        else:            # x = x0 + w face, normal +x
            objects.append(quad([x0 + w + eps, y, z0 + a], [0, 1.0, 0], [0, 0, 0.6], tint))
    # Street lamps every 10 m along the streets between the blocks.
    for k in range(blocks + 1):
        s = -extent / 2 + k * (lot + street)
        t = -extent / 2
        while t < extent / 2:
            for (x, z) in ((s, t), (t, s)):
                objects.append({"type": "sphere", "center": [x + 1.5, 7.0, z + 1.5],
                                "radius": 0.25, "material": "sodium"})
            t += 10.0
    materials = {"asphalt": {"type": "diffuse", "albedo": [0.12, 0.12, 0.13]},
                 "concrete": {"type": "diffuse", "albedo": [0.45, 0.43, 0.4]}}
    for name, radiance in TINTS.items():
        materials[name] = {"type": "emissive", "radiance": radiance}
    return {
        "format": 1,
        "render": {"width": 960, "height": 540, "spp": 64, "max_depth": 6, "seed": 1},
        "camera": {"position": [-extent * 0.18, 5.5, extent * 0.62],
                   "look_at": [extent * 0.05, 14.0, -extent * 0.1], "up": [0, 1, 0],
                   "fov_y": 55},
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
    p.add_argument("--windows", type=int, default=50000)
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
    lights = sum(1 for o in scene["objects"] if o["material"] in TINTS)
    print("%s: %d emitters, %d objects" % (out, lights, len(scene["objects"])))


if __name__ == "__main__":
    main()
