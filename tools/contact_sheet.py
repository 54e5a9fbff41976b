#!/usr/bin/env python3
"""Contact sheet of model files rendered whole, one command each (issues 8 and 27's evidence).

Renders one file per model under each folder (default ../shared/assets/khronos and
../shared/assets/khronos-ext; a model folder's glTF-Binary variant first, then glTF, then any
other) plus any extra files given, each as
`BINARY MODEL -o TILE.pfm --width S --height S --spp N [ARGS after --]` (the file's own camera
or the automatic one, its own lights added to the default environment), then tiles them into
one PNG, row by row in sorted order, and prints that order. A model the renderer refuses
becomes a dark red tile and its message is printed (the sheet shows every model). Pure Python
(PFM in, PNG out). A quick CPU sheet:

    python3 tools/contact_sheet.py --binary build/pathtracer --out /tmp/sheet.png \
        --size 96 --spp 4 -- --backend cpu
"""
import argparse
import glob
import math
import os
import struct
import subprocess
import sys
import tempfile
import zlib


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = f.read()
    channels = 3 if kind == b"PF" else 1
    fmt = ("<" if scale < 0 else ">") + "f" * (width * height * channels)
    values = struct.unpack(fmt, data[: 4 * width * height * channels])
    rows = []
    for y in range(height - 1, -1, -1):  # PFM stores the bottom row first
        row = values[y * width * channels:(y + 1) * width * channels]
        rows.append(row if channels == 3 else [v for v in row for _ in range(3)])
    return width, height, rows


def encode(v):
    v = max(0.0, min(1.0, v))
    v = 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055
    return int(v * 255 + 0.5)


def write_png(path, width, height, rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    def chunk(tag, body):
        return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body))
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def pick_models(folder):
    """One file per model folder: the glTF-Binary variant, else glTF, else the first other."""
    files = sorted(glob.glob(os.path.join(folder, "**", "*.glb"), recursive=True) +
                   glob.glob(os.path.join(folder, "**", "*.gltf"), recursive=True))
    by_model = {}
    for f in files:
        parts = os.path.relpath(f, folder).split(os.sep)
        by_model.setdefault(parts[0], []).append((parts[1] if len(parts) > 2 else "", f))
    picked = []
    for model in sorted(by_model):
        variants = by_model[model]
        rank = {"glTF-Binary": 0, "glTF": 1}
        picked.append(min(variants, key=lambda v: (rank.get(v[0], 2), v[1]))[1])
    return picked


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default="build/pathtracer")
    ap.add_argument("--folder", action="append",
                    help="a folder of models (repeatable; default khronos and khronos-ext)")
    ap.add_argument("--extra", action="append", default=[], help="another model file")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--columns", type=int, default=5)
    ap.add_argument("--out", default="contact_sheet.png")
    ap.add_argument("pathtracer_args", nargs="*", help="more pathtracer options after --")
    args = ap.parse_args()
    folders = args.folder or ["../shared/assets/khronos", "../shared/assets/khronos-ext"]
    models, seen = [], set()
    for folder in folders:  # a model already picked from an earlier folder is not repeated
        for m in pick_models(folder):
            name = os.path.relpath(m, folder).split(os.sep)[0]
            if name not in seen:
                seen.add(name)
                models.append(m)
    models += args.extra
    if not models:
        sys.exit(f"contact_sheet: no .glb or .gltf under {', '.join(folders)}")
    s, cols = args.size, min(args.columns, len(models))
    rows_n = math.ceil(len(models) / cols)
    sheet = [[0] * (3 * s * cols) for _ in range(s * rows_n)]
    with tempfile.TemporaryDirectory() as tmp:
        for i, model in enumerate(models):
            tile = os.path.join(tmp, f"{i}.pfm")
            cmd = [args.binary, model, "-o", tile, "--width", str(s), "--height", str(s),
                   "--spp", str(args.spp), "--quiet"] + args.pathtracer_args
            done = subprocess.run(cmd, capture_output=True, text=True)
            x0, y0 = (i % cols) * s * 3, (i // cols) * s
            if done.returncode != 0:
                for y in range(s):
                    sheet[y0 + y][x0:x0 + 3 * s] = [96, 0, 0] * s
                print(f"{i + 1}. {model}: REFUSED (exit {done.returncode}): {done.stderr.strip()}")
                continue
            _, _, rows = read_pfm(tile)
            for y, row in enumerate(rows):
                sheet[y0 + y][x0:x0 + 3 * s] = [encode(v) for v in row]
            print(f"{i + 1}. {model}")
    write_png(args.out, s * cols, s * rows_n, sheet)
    print(f"wrote {args.out} ({cols} x {rows_n} tiles of {s}x{s}, {args.spp} spp)")


if __name__ == "__main__":
    main()
