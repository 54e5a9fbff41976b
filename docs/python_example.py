"""The worked example of docs/python.md: a max_depth sweep and a convergence plot, from one
scene loaded once. Run from the repository root after the build:

    PYTHONPATH=build/python python3 docs/python_example.py            # writes python_example.png
"""
import argparse

import matplotlib
matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt
import numpy as np

import pathtracer

parser = argparse.ArgumentParser()
parser.add_argument("--size", type=int, default=160)
parser.add_argument("--out", default="python_example.png")
args = parser.parse_args()
size = dict(width=args.size, height=args.size)

scene = pathtracer.Scene("scenes/cornell_box.json")  # loaded and its BVH built once

# 1. A sweep: light arriving after at most 1, 2 and 8 bounces (the BVH is reused each time).
depths = [1, 2, 8]
sweep = [pathtracer.render(scene, spp=64, max_depth=d, **size) for d in depths]

# 2. Convergence: the relative MSE of each progressive step against a 1024-spp reference.
reference = pathtracer.render(scene, spp=1024, seed=99, **size).image
spp, relmse = [], []
for partial in pathtracer.render_progressive(scene, spp=256, **size):
    spp.append(partial.spp)
    relmse.append(np.mean((partial.image - reference) ** 2 / (reference ** 2 + 1e-2)))

# 3. An edit without reloading: a blue right wall.
scene.set_material("green", albedo=[0.1, 0.2, 0.6])
edited = pathtracer.render(scene, spp=64, **size)


def srgb(linear):  # display encoding of a linear image
    x = np.clip(linear, 0, 1)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


fig, axes = plt.subplots(1, 5, figsize=(17, 3.6))
for ax, result, d in zip(axes, sweep, depths):
    ax.imshow(srgb(result.image))
    ax.set_title(f"max_depth={d}, {result.spp:.0f} spp")
    ax.axis("off")
axes[3].imshow(srgb(edited.image))
axes[3].set_title('set_material("green", ...)')
axes[3].axis("off")
axes[4].loglog(spp, relmse, "o-", label="render_progressive")
axes[4].loglog(spp, relmse[0] / np.array(spp), "--", label="1 / spp")
axes[4].set_xlabel("samples per pixel")
axes[4].set_ylabel("relMSE vs 1024 spp")
axes[4].legend()
fig.tight_layout()
fig.savefig(args.out, dpi=80)
print(f"wrote {args.out}; albedo AOV {sweep[0].aovs['albedo'].shape}, "
      f"{sweep[-1].stats['mrays_per_s']:.1f} Mrays/s on {sweep[-1].stats['device']}")
