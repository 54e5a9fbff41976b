#!/usr/bin/env python3
"""The denoiser's error against time (issue 31's curve): per scene, relMSE of the raw and of
the denoised image against a reference of ours, at several spp and seeds, against render time
(raw) and render + denoise time (denoised). Each run renders once with --denoise and an --hdr
EXR, which holds the raw beauty and the denoised layer, so raw and denoised come from the same
samples; the raw time is that run's render (the film keeps its half buffers, a few percent).
The knee is where the raw curve reaches the denoised one at equal time: beyond it denoising
no longer pays. Writes denoise_curve.csv and denoise_curve.md under --out; plot it here with
--plot (matplotlib). --split also parts each mean error into the variance the seeds show and
the bias left (the mean image's error), which tells a filter that averages too little from one
that blurs; --extra passes options to every render (a sampler, a --crop window: then only the
crop's pixels count).

  python3 benchmarks/denoise_curve.py --binary .device/bin/pathtracer --out $OUT
  /usr/bin/python3 benchmarks/denoise_curve.py --plot benchmarks/results/X/denoise_curve.csv
"""
import argparse
import csv
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

DEFAULT_SCENES = ("benchmarks/scenes/bunny_cornell.json:960x540,"
                  "benchmarks/scenes/breakfast_room_sunsky.json:640x360,"
                  "benchmarks/scenes/damaged_helmet.json:960x540")


def render(binary, scene, size, spp, seed, out, backend, denoise, extra=()):
    w, h = size.split("x")
    cmd = [binary, scene, "-o", out + ".pfm", "--hdr", out + ".exr", "--width", w, "--height", h,
           "--spp", str(spp), "--seed", str(seed), "--backend", backend, "--quiet",
           "--stats-json", out + ".json"] + (["--denoise"] if denoise else []) + list(extra)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    return json.load(open(out + ".json"))["time_ms"]


def rel_mse(np, x, ref, noise, den, mask):
    return float(np.mean((((x - ref) ** 2 - noise) / den)[mask]))


class Split:
    """Per (scene, spp, image): the seeds' images summed, for the variance / bias split."""

    def __init__(self):
        self.sums = {}

    def add(self, key, img):
        s = self.sums.setdefault(key, [0, 0.0, 0.0])
        s[0] += 1
        s[1] = s[1] + img.astype("float64")
        s[2] = s[2] + img.astype("float64") ** 2

    def rows(self, np, ref, noise, den, mask, scene):
        out = []
        for (sc, spp, image), (n, s1, s2) in self.sums.items():
            if sc != scene or n < 2:
                continue
            mean = s1 / n
            var = (s2 - n * mean ** 2) / (n - 1)  # each seed's deviation from the seeds' mean
            variance = float(np.mean((var / den)[mask]))
            total = float(np.mean((((s2 - 2 * s1 * ref + n * ref ** 2) / n - noise) / den)[mask]))
            out.append(dict(scene=sc, spp=spp, image=image, seeds=n, relmse=total,
                            variance=variance, bias2=total - variance))
        return out


def measure(args):
    import numpy as np
    from accuracy_lib import read_exr
    rows = []
    for entry in args.scenes.split(","):
        scene, size = entry.split(":")
        tmp = os.path.join(args.out, "tmp")
        os.makedirs(tmp, exist_ok=True)
        render(args.binary, scene, size, args.ref_spp, 77, tmp + "/ref", args.backend, False,
               args.extra)
        ref = read_exr(tmp + "/ref.exr")
        r = np.stack([ref[c] for c in "RGB"], -1)
        mask = ref["samples"] > 0  # the crop window's pixels (every pixel without --crop)
        split = Split()
        # The reference's own noise, the variance of its mean, taken out of every squared error.
        noise = np.stack([ref["variance." + c] for c in "RGB"], -1) / \
            np.maximum(ref["samples"], 1)[..., None]
        den = r * r + 1e-2
        for spp in [int(s) for s in args.spps.split(",")]:
            for seed in range(1, args.seeds + 1):
                t = render(args.binary, scene, size, spp, seed, tmp + "/x", args.backend, True,
                           args.extra)
                img = read_exr(tmp + "/x.exr")
                raw = np.stack([img[c] for c in "RGB"], -1)
                dn = np.stack([img["denoised." + c] for c in "RGB"], -1)
                base = dict(scene=os.path.basename(scene), size=size, spp=spp, seed=seed)
                rows.append(dict(base, image="raw", seconds=t["render"] / 1000.0,
                                 relmse=rel_mse(np, raw, r, noise, den, mask)))
                rows.append(dict(base, image="denoised",
                                 seconds=(t["render"] + t.get("denoise", 0.0)) / 1000.0,
                                 relmse=rel_mse(np, dn, r, noise, den, mask)))
                split.add((base["scene"], spp, "raw"), raw)
                split.add((base["scene"], spp, "denoised"), dn)
                for name, extra in args.variant_list:  # the same film, other settings (or another film)
                    t = render(args.binary, scene, size, spp, seed, tmp + "/x", args.backend,
                               True, args.extra + extra)
                    img = read_exr(tmp + "/x.exr")
                    if args.variant_raw:  # a variant that samples otherwise: its raw image too
                        vr = np.stack([img[c] for c in "RGB"], -1)
                        rows.append(dict(base, image=name + " raw", seconds=t["render"] / 1000.0,
                                         relmse=rel_mse(np, vr, r, noise, den, mask)))
                        split.add((base["scene"], spp, name + " raw"), vr)
                    dn = np.stack([img["denoised." + c] for c in "RGB"], -1)
                    rows.append(dict(base, image=name,
                                     seconds=(t["render"] + t.get("denoise", 0.0)) / 1000.0,
                                     relmse=rel_mse(np, dn, r, noise, den, mask)))
                    split.add((base["scene"], spp, name), dn)
        print("%s: reference %d spp, own relMSE %.2e" % (scene, args.ref_spp,
                                                          float(np.mean((noise / den)[mask]))))
        if args.split:
            args.split_rows += split.rows(np, r, noise, den, mask, os.path.basename(scene))
        for f in os.listdir(tmp):
            os.remove(os.path.join(tmp, f))
    with open(os.path.join(args.out, "denoise_curve.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    return rows


def means(rows):
    """{scene: {image: [(spp, mean seconds, mean relMSE)]}}"""
    acc = {}
    for r in rows:
        key = (r["scene"], r["image"], int(r["spp"]))
        acc.setdefault(key, []).append((float(r["seconds"]), float(r["relmse"])))
    out = {}
    for (scene, image, spp), v in sorted(acc.items()):
        out.setdefault(scene, {}).setdefault(image, []).append(
            (spp, sum(x[0] for x in v) / len(v), sum(x[1] for x in v) / len(v)))
    return out


def table(rows, label):
    lines = ["Denoiser: relMSE against time, %s; mean over seeds; time in seconds (render, "
             "or render + denoise)." % label, "",
             "| scene | spp | raw relMSE | raw s | denoised relMSE | denoised s |",
             "|---|---|---|---|---|---|"]
    extra = []  # the variants' columns, in the order first seen
    for r in rows:
        if r["image"] not in ("raw", "denoised") and r["image"] not in extra:
            extra.append(r["image"])
    for name in extra:
        lines[2] += (" %s relMSE | s |" if name.endswith(" raw") else
                     " denoised, %s, relMSE | s |") % name
        lines[3] += "---|---|"
    for scene, images in means(rows).items():
        for i, ((spp, ts, es), (_, td, ed)) in enumerate(zip(images["raw"], images["denoised"])):
            lines.append("| %s | %d | %.3e | %.3f | %.3e | %.3f |" % (scene, spp, es, ts, ed, td))
            for name in extra:
                lines[-1] += " %.3e | %.3f |" % (images[name][i][2], images[name][i][1])
    return "\n".join(lines) + "\n"


def split_table(rows):
    lines = ["", "Each mean relMSE parted (--split) into the variance across seeds and the bias "
             "left (bias^2 = relMSE - variance).", "",
             "| scene | spp | image | seeds | relMSE | variance | bias^2 |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append("| %s | %d | %s | %d | %.3e | %.3e | %.3e |" % (
            r["scene"], r["spp"], r["image"], r["seeds"], r["relmse"], r["variance"], r["bias2"]))
    return "\n".join(lines) + "\n"


def plot(csv_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = list(csv.DictReader(open(csv_path)))
    data = means(rows)
    fig, axes = plt.subplots(1, len(data), figsize=(5 * len(data), 4.2), squeeze=False)
    for ax, (scene, images) in zip(axes[0], data.items()):
        for image, style in (("raw", "o-"), ("denoised", "s--")):
            pts = images[image]
            ax.loglog([p[1] for p in pts], [p[2] for p in pts], style, label=image)
            for spp, t, e in pts:
                ax.annotate(str(spp), (t, e), fontsize=7, xytext=(3, 3),
                            textcoords="offset points")
        ax.set_title(scene)
        ax.set_xlabel("seconds (render, + denoise)")
        ax.set_ylabel("relMSE")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    out = os.path.splitext(csv_path)[0] + ".png"
    fig.savefig(out, dpi=110)
    print("wrote", out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--binary", default=".device/bin/pathtracer")
    ap.add_argument("--backend", default="cuda")
    ap.add_argument("--scenes", default=DEFAULT_SCENES, help="comma-separated PATH:WxH")
    ap.add_argument("--spps", default="4,16,64,256,1024")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--ref-spp", type=int, default=8192)
    ap.add_argument("--out", default="out")
    ap.add_argument("--label", default="")
    ap.add_argument("--plot", help="plot this CSV instead of measuring")
    ap.add_argument("--outliers-off-too", action="store_true",
                    help="also denoise each film with --denoise-outliers off")
    ap.add_argument("--variant", action="append", default=[], metavar="NAME=OPTIONS",
                    help="also denoise each film with these extra options (e.g. "
                         "'radius 5=--denoise-radius 5'); repeatable")
    ap.add_argument("--extra", default="", help="options for every render, the reference's "
                    "too (e.g. '--sampler sobol --crop 800 380 1120 640')")
    ap.add_argument("--split", action="store_true",
                    help="part each mean error into variance across seeds and bias (>= 2 seeds)")
    ap.add_argument("--variant-raw", action="store_true",
                    help="record each variant's raw image too (for variants that sample "
                         "otherwise, e.g. '--sampler sobol')")
    args = ap.parse_args()
    args.extra = args.extra.split()
    args.split_rows = []
    args.variant_list = [("outliers off", ["--denoise-outliers", "off"])] \
        if args.outliers_off_too else []
    for v in args.variant:
        name, _, options = v.partition("=")
        args.variant_list.append((name, options.split()))
    if args.plot:
        return plot(args.plot)
    os.makedirs(args.out, exist_ok=True)
    rows = measure(args)
    text = table(rows, args.label or args.backend)
    if args.split_rows:
        text += split_table(args.split_rows)
    open(os.path.join(args.out, "denoise_curve.md"), "w").write(text)
    print(text)


if __name__ == "__main__":
    main()
