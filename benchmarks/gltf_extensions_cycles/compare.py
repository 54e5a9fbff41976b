"""Per-region luminance ratios of our render to Cycles' (both linear EXR, same camera) and a
side-by-side PNG (ours | Cycles, sRGB). Runs inside Blender for its EXR reader:

  blender -b -P compare.py -- NAME OURS.exr CYCLES.exr OUT_DIR

Regions: the object's pixels (those not showing the white background, which is exactly 1 in
our image) in a 3 x 3 grid over the image, and all of them; a region needs 200 object pixels.
Appends rows to OUT_DIR/ratios.csv: model, region, object pixels, ours, cycles, ratio."""
import os
import sys

import numpy as np

np.bool = bool
np.int = int
np.float = float
np.object = object

import bpy  # noqa: E402


def load(path):
    im = bpy.data.images.load(path)
    w, h = im.size
    px = np.array(im.pixels[:], dtype=np.float64).reshape(h, w, 4)[::-1, :, :3]  # top row first
    return px


def to_srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def save_png(rgb, path):
    h, w, _ = rgb.shape
    im = bpy.data.images.new(os.path.basename(path), w, h, alpha=True)
    rgba = np.concatenate([rgb[::-1], np.ones((h, w, 1))], axis=2)
    im.pixels = rgba.ravel().tolist()
    im.file_format = 'PNG'
    im.filepath_raw = path
    im.save()


def main():
    name, ours_path, cycles_path, out_dir = sys.argv[sys.argv.index('--') + 1:][:4]
    ours, cycles = load(ours_path), load(cycles_path)
    lum = lambda x: 0.2126 * x[..., 0] + 0.7152 * x[..., 1] + 0.0722 * x[..., 2]
    mask = np.any(np.abs(ours - 1.0) > 1e-4, axis=2)
    h, w = mask.shape
    rows = []
    regions = [('all', slice(0, h), slice(0, w))]
    for gy in range(3):
        for gx in range(3):
            regions.append(('r%d%d' % (gy, gx), slice(gy * h // 3, (gy + 1) * h // 3),
                            slice(gx * w // 3, (gx + 1) * w // 3)))
    for region, ys, xs in regions:
        m = mask[ys, xs]
        if m.sum() < 200:
            continue
        a, b = lum(ours[ys, xs])[m].mean(), lum(cycles[ys, xs])[m].mean()
        rows.append('%s,%s,%d,%.5f,%.5f,%.4f' % (name, region, m.sum(), a, b, a / b))
    csv = os.path.join(out_dir, 'ratios.csv')
    new = not os.path.exists(csv)
    with open(csv, 'a') as f:
        if new:
            f.write('model,region,object_pixels,ours,cycles,ratio\n')
        f.write('\n'.join(rows) + '\n')
    gap = np.ones((h, 4, 3))
    save_png(np.concatenate([to_srgb(ours), gap, to_srgb(cycles)], axis=1),
             os.path.join(out_dir, name + '.png'))
    print('\n'.join(rows))


main()
