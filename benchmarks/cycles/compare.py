#!/usr/bin/env python3
"""Compares path tracer renders (PFM) of one view with a Blender Cycles render of it (.npy from
benchmarks/cycles/render_cycles.py): over the object's pixels (those not the uniform
background in the first render), the fraction of black pixels (luminance below --black) in
each image, and the ratio of mean luminance per block of a grid (blocks at least half object).
Writes a side-by-side PNG (each render, then Cycles) when --png is given.

    compare.py CYCLES.npy RENDER.pfm [RENDER2.pfm ...] [--labels A B ...] [--grid 4]
               [--background 1] [--black 0.01] [--png OUT.png]
"""
import argparse
import struct
import zlib

import numpy as np


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    channels = 3 if kind == b"PF" else 1
    img = data[: width * height * channels].reshape(height, width, channels)[::-1]
    return np.repeat(img, 3, axis=2) if channels == 1 else img.astype(np.float32)


def luminance(img):
    return 0.2126 * img[..., 0] + 0.7152 * img[..., 1] + 0.0722 * img[..., 2]


def write_png(path, img):
    v = np.clip(img, 0.0, 1.0)
    v = np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)
    rows = (v * 255 + 0.5).astype(np.uint8)
    h, w, _ = rows.shape
    raw = b"".join(b"\x00" + rows[y].tobytes() for y in range(h))

    def chunk(tag, body):
        return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body))
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("cycles")
    ap.add_argument("renders", nargs="+")
    ap.add_argument("--labels", nargs="*")
    ap.add_argument("--grid", type=int, default=4)
    ap.add_argument("--background", type=float, default=1.0)
    ap.add_argument("--black", type=float, default=0.01)
    ap.add_argument("--png")
    a = ap.parse_args()
    ref = np.load(a.cycles).astype(np.float64)
    renders = [read_pfm(p).astype(np.float64) for p in a.renders]
    labels = a.labels or a.renders
    mask = np.any(np.abs(renders[0] - a.background) > 1e-6, axis=2)
    n = int(mask.sum())
    print(f"object pixels: {n} of {mask.size}")
    lref = luminance(ref)
    print(f"{'image':>12} {'black':>8} {'fraction':>9} {'mean':>8}")
    for label, img in [("cycles", ref)] + list(zip(labels, renders)):
        lum = luminance(img)
        black = int((lum[mask] < a.black).sum())
        print(f"{label:>12} {black:>8} {black / n:>9.4f} {lum[mask].mean():>8.4f}")
    h, w = mask.shape
    g = a.grid
    print(f"ratio of mean luminance to Cycles per block ({g} x {g}, blocks at least half object):")
    for label, img in zip(labels, renders):
        lum = luminance(img)
        cells = []
        for by in range(g):
            for bx in range(g):
                sl = (slice(by * h // g, (by + 1) * h // g), slice(bx * w // g, (bx + 1) * w // g))
                m = mask[sl]
                if m.mean() < 0.5:
                    cells.append("   -  ")
                    continue
                cells.append(f"{lum[sl][m].mean() / max(lref[sl][m].mean(), 1e-9):6.3f}")
        print(f"{label:>12}: " + " ".join(cells))
    if a.png:
        write_png(a.png, np.concatenate(renders + [ref], axis=1))
        print("wrote", a.png)


if __name__ == "__main__":
    main()
