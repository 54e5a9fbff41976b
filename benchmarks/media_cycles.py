#!/usr/bin/env python3
"""Participating media against Blender Cycles 3.4 (Debian's blender): a VDB cloud under a sun
and a fog-filled Cornell box, the same camera, both rendered to linear images, compared by
mean per channel and over a 3 x 3 grid of regions; side-by-side images (ours | Cycles |
relative difference) and a markdown table.

  python3 benchmarks/media_cycles.py --pathtracer build/pathtracer --make-vdb build/make_vdb \\
      --out benchmarks/results/media_cycles [--size 160] [--spp 512] [--cycles-spp 512]

Cycles builds the scene with benchmarks/media_cycles_blender.py (its settings follow
../shared/toolchain.md). The cloud's .vdb is written by tools/make_vdb; both renderers read
that file.
"""
import argparse
import json
import os
import re
import subprocess

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def cloud_scene(vdb, size):
    return {
        "render": {"width": size, "height": size, "spp": 16, "max_depth": 32, "seed": 1},
        "camera": {"position": [0, -0.1, 3.6], "look_at": [0, 0, 0], "fov_y": 40},
        "background": [0.3, 0.4, 0.55],
        "media": {"cloud": {"type": "grid", "file": vdb, "grid": "density",
                            "sigma_a": [0.3, 0.3, 0.3], "sigma_s": [25, 25, 25], "g": 0.5}},
        "materials": {"ground": {"type": "diffuse", "albedo": [0.35, 0.35, 0.35]}},
        "objects": [
            {"type": "quad", "origin": [-8, -1.1, 8], "u": [16, 0, 0], "v": [0, 0, -16],
             "material": "ground"},
            {"type": "volume", "medium": "cloud"}],
        "lights": [{"type": "directional", "direction": [-0.6, -0.5, -0.62],
                    "irradiance": [4, 3.8, 3.5], "angular_radius": 0.5}],
    }


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.fromfile(f, dtype="<f4" if scale < 0 else ">f4")
    img = data.reshape(h, w, 3 if kind == b"PF" else 1)
    return img[::-1].astype(np.float64)  # PFM rows run bottom to top


def run(cmd):
    print("+", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True)


def render_both(args, name, scene_path):
    ours = os.path.join(args.out, name + "_ours.pfm")
    cyc = os.path.join(args.out, name + "_cycles.exr")
    npy = os.path.join(args.out, name + "_cycles.npy")
    if not os.path.exists(ours):
        run([args.pathtracer, scene_path, "-o", os.path.join(args.out, name + "_ours.png"),
             "--hdr", ours, "--spp", str(args.spp), "--width", str(args.size), "--height",
             str(args.size), "--backend", args.backend, "--quiet"])
    if not os.path.exists(npy):
        scene = json.loads(re.sub(r"//[^\n]*", "", open(scene_path).read()))
        scene["render"]["width"] = scene["render"]["height"] = args.size
        tmp = os.path.join(args.out, name + "_cycles_scene.json")
        json.dump(scene, open(tmp, "w"))
        run([args.blender, "-b", "--factory-startup", "-P",
             os.path.join(HERE, "media_cycles_blender.py"), "--", os.path.abspath(tmp),
             os.path.abspath(cyc), str(args.cycles_spp)])
        run([args.blender, "-b", "--factory-startup", "-P",
             os.path.join(HERE, "media_cycles_blender.py"), "--", "--to-npy",
             os.path.abspath(cyc), os.path.abspath(npy)])
    return read_pfm(ours), np.load(npy).astype(np.float64)


def compare(name, a, b, out):
    lines = [f"### {name}", "", "| region | ours (R, G, B) | Cycles (R, G, B) | ours / Cycles |",
             "|---|---|---|---|"]
    h, w, _ = a.shape
    regions = [("whole image", slice(0, h), slice(0, w))]
    for i in range(3):
        for j in range(3):
            regions.append((f"row {i} col {j}", slice(i * h // 3, (i + 1) * h // 3),
                            slice(j * w // 3, (j + 1) * w // 3)))
    for label, ys, xs in regions:
        ma, mb = a[ys, xs].mean(axis=(0, 1)), b[ys, xs].mean(axis=(0, 1))
        ratio = ma / np.maximum(mb, 1e-9)
        lines.append(f"| {label} | {ma[0]:.4f}, {ma[1]:.4f}, {ma[2]:.4f} | "
                     f"{mb[0]:.4f}, {mb[1]:.4f}, {mb[2]:.4f} | "
                     f"{ratio[0]:.3f}, {ratio[1]:.3f}, {ratio[2]:.3f} |")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        def srgb(x):
            x = np.clip(x, 0, 1)
            return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)
        la, lb = a.mean(axis=2), b.mean(axis=2)
        rel = (la - lb) / np.maximum(0.5 * (la + lb), 1e-3)
        fig, ax = plt.subplots(1, 3, figsize=(12, 4.2))
        ax[0].imshow(srgb(a)); ax[0].set_title("ours")
        ax[1].imshow(srgb(b)); ax[1].set_title("Cycles 3.4")
        im = ax[2].imshow(rel, cmap="coolwarm", vmin=-0.5, vmax=0.5)
        ax[2].set_title("(ours - Cycles) / mean, luminance")
        fig.colorbar(im, ax=ax[2], fraction=0.046)
        for x in ax:
            x.axis("off")
        fig.tight_layout()
        fig.savefig(os.path.join(out, name + "_side_by_side.png"), dpi=100)
    except ImportError:
        pass
    return lines


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--pathtracer", default="build/pathtracer")
    ap.add_argument("--make-vdb", default="build/make_vdb")
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--backend", default="cpu")
    ap.add_argument("--out", default="benchmarks/results/media_cycles")
    ap.add_argument("--size", type=int, default=160)
    ap.add_argument("--spp", type=int, default=512)
    ap.add_argument("--cycles-spp", type=int, default=512)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    vdb = os.path.join(args.out, "cloud.vdb")
    if not os.path.exists(vdb):
        run([args.make_vdb, "cloud", "-o", vdb, "--resolution", "96", "--size", "2.2"])
    cloud = os.path.join(args.out, "cloud_scene.json")
    json.dump(cloud_scene("cloud.vdb", args.size), open(cloud, "w"), indent=1)
    report = []
    for name, scene in (("cloud", cloud), ("cornell_fog", os.path.join(ROOT, "scenes/cornell_fog.json"))):
        a, b = render_both(args, name, scene)
        report += compare(name, a, b, args.out) + [""]
    with open(os.path.join(args.out, "comparison.md"), "w") as f:
        f.write("\n".join(report))
    print("\n".join(report))


if __name__ == "__main__":
    main()
