#!/usr/bin/python3
"""A model file (.gltf/.glb) as a JSON scene with a front camera (from +Z, looking down -Z at the
centre of the bounds, the bounding sphere filling the frame) under a uniform white background:
the setup the Cycles comparison renders on both sides.

  model_scene.py MODEL OUT.json [--width W] [--height H] [--spp N] [--max-depth D] [--variant V]

Also prints the camera as JSON (what the Blender side uses)."""
import argparse
import json
import math
import os
import struct

import numpy as np


def load_gltf(path):
    if path.lower().endswith('.glb'):
        data = open(path, 'rb').read()
        length = struct.unpack_from('<I', data, 12)[0]
        return json.loads(data[20:20 + length])
    return json.load(open(path))


def node_matrix(node):
    if 'matrix' in node:
        return np.array(node['matrix'], dtype=float).reshape(4, 4).T
    t = np.eye(4)
    t[:3, 3] = node.get('translation', [0, 0, 0])
    x, y, z, w = node.get('rotation', [0, 0, 0, 1])
    r = np.eye(4)
    r[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    s = np.diag(list(node.get('scale', [1, 1, 1])) + [1])
    return t @ r @ s


def bounds(doc):
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    scene = doc.get('scenes', [{}])[doc.get('scene', 0)] if doc.get('scenes') else {}
    roots = scene.get('nodes', list(range(len(doc.get('nodes', [])))))

    def visit(i, parent):
        nonlocal lo, hi
        node = doc['nodes'][i]
        m = parent @ node_matrix(node)
        if 'mesh' in node:
            for p in doc['meshes'][node['mesh']]['primitives']:
                a = doc['accessors'][p['attributes']['POSITION']]
                amin, amax = a['min'], a['max']
                for corner in range(8):
                    c = [amax[k] if corner >> k & 1 else amin[k] for k in range(3)]
                    w = m @ np.array(c + [1.0])
                    lo, hi = np.minimum(lo, w[:3]), np.maximum(hi, w[:3])
        for c in node.get('children', []):
            visit(c, m)

    for r in roots:
        visit(r, np.eye(4))
    return lo, hi


def front_camera(lo, hi, fov_y, aspect):
    centre = (lo + hi) / 2
    radius = np.linalg.norm(hi - lo) / 2
    half = math.radians(fov_y) / 2
    half = min(half, math.atan(math.tan(half) * aspect))
    distance = radius / math.sin(half) * 1.02
    return {'position': list(centre + [0, 0, distance]), 'look_at': list(centre), 'fov_y': fov_y}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('model')
    ap.add_argument('out')
    ap.add_argument('--width', type=int, default=320)
    ap.add_argument('--height', type=int, default=320)
    ap.add_argument('--spp', type=int, default=64)
    ap.add_argument('--max-depth', type=int, default=8)
    ap.add_argument('--fov', type=float, default=30.0)
    ap.add_argument('--variant', default='')
    a = ap.parse_args()
    lo, hi = bounds(load_gltf(a.model))
    camera = front_camera(lo, hi, a.fov, a.width / a.height)
    mesh = {'type': 'mesh', 'file': os.path.abspath(a.model)}
    if a.variant:
        mesh['variant'] = a.variant
    scene = {'format': 1,
             'render': {'width': a.width, 'height': a.height, 'spp': a.spp,
                        'max_depth': a.max_depth, 'russian_roulette_depth': 100, 'seed': 1},
             'camera': camera, 'background': [1, 1, 1], 'materials': {}, 'objects': [mesh]}
    json.dump(scene, open(a.out, 'w'), indent=1)
    print(json.dumps(camera))


if __name__ == '__main__':
    main()
