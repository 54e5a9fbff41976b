"""Part 3 of the accuracy study: the price of numerical robustness (triangle test,
ray offsets, film precision)."""
import argparse
import csv
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zlib
import numpy as np

from accuracy_lib import *  # noqa: F401,F403


class RobustnessParts:
    def p3_settings(self):
        q = self.args.quick
        return {"leak_w": 32 if q else 256, "leak_spp": 16 if q else 16384,
                "tri_spp": 16 if q else 4096, "tri_reps": 1 if q else 3,
                "ro_w": 16 if q else 128, "ro_spp": 64 if q else 4096,
                "film_spp": 256 if q else 16384,
                "scales": [float(v) for v in self.args.offset_scales.split(",")],
                "eps": ["1e-6", "1e-4", "1e-2"]}

    def estimate_part3(self):
        if "3" not in self.args.parts:
            return 0.0
        p = self.p3_settings()
        c = self.costs
        sc0 = self.scenes[0] if self.scenes else None
        t = 2 * c.run("leak", p["leak_w"] ** 2, p["leak_spp"], 0.15)
        tri = self.tri_scene()
        if tri:
            t += 2 * p["tri_reps"] * c.run(tri["path"], tri["px"], p["tri_spp"])
        t += len(p["scales"]) * (len(p["eps"]) + 2) * c.run("ro", p["ro_w"] ** 2, p["ro_spp"])
        if sc0:
            t += 2 * c.run(sc0["path"], sc0["px"], p["film_spp"])
        return t

    def tri_scene(self):
        for sc in self.scenes:
            if "bunny" in sc["name"]:
                return sc
        return self.scenes[0] if self.scenes else None

    def part3(self):
        L, p, R = self.log, self.p3_settings(), self.runner
        L("")
        L("== part 3: the price of numerical robustness")
        res = self.p3
        # (a) Triangle test: leaks through the edges of a closed tessellated sphere.
        leak_scene = os.path.join(REPO, "benchmarks/scenes/leak_sphere.json")
        mesh = os.path.join(REPO, "benchmarks/scenes/meshes/leak_sphere.obj")
        if not os.path.exists(mesh):
            subprocess.run([sys.executable, os.path.join(os.path.dirname(mesh),
                                                         "make_leak_sphere.py")], check=True)
        w = p["leak_w"]
        mask = self.leak_mask(leak_scene, w, w)
        res["leak"] = {}
        for test in ("watertight", "mt"):
            if not self.guard(self.costs.run("leak", w * w, p["leak_spp"], 0.15), "leak " + test):
                continue
            stats, img, wall, err = R.render(leak_scene, w, w, p["leak_spp"], 1,
                                             ["--tri-test", test, "--max-depth", "0"])
            row = dict(part="tri-test", scene="leak_sphere", config=test, group="leak",
                       spp=p["leak_spp"], seed=1, width=w, height=w)
            if stats is None:
                R.row(status="failed", note=err, **row)
                continue
            lum = img.mean(axis=2)  # radiance 1 on the inside: value = leaked fraction
            rays_inside = int(mask.sum()) * p["leak_spp"]
            leaked_inside = int(round(float(lum[mask].sum()) * p["leak_spp"]))
            leaked_all = int(round(float(lum.sum()) * p["leak_spp"]))
            frac = leaked_inside / max(1, rays_inside)
            res["leak"][test] = {"render_s": stats["time_ms"]["render"] / 1000.0,
                                 "leaked_inside": leaked_inside, "rays_inside": rays_inside,
                                 "fraction": frac, "leaked_anywhere": leaked_all,
                                 "pixels_nonzero": int((lum > 0).sum())}
            R.row(status="ok", note="leaked %d of %d rays inside the silhouette (%.3g); %d in "
                  "the whole image" % (leaked_inside, rays_inside, frac, leaked_all),
                  **stat_fields(stats, wall), **row)
            L("  leak sphere, %-10s %d of %d camera rays inside the silhouette leaked (%.3g)"
              ", %d in the whole image; render %.3f s" % (test, leaked_inside, rays_inside,
                                                         frac, leaked_all,
                                                         res["leak"][test]["render_s"]))
        # Time of the triangle test on a mesh scene with full path tracing.
        tri = self.tri_scene()
        res["tri_time"] = {}
        if tri:
            for rep in range(p["tri_reps"]):
                for test in ("watertight", "mt"):
                    if not self.guard(self.costs.run(tri["path"], tri["px"], p["tri_spp"]),
                                      "tri-test timing"):
                        continue
                    stats, img, wall, err = R.render(tri["path"], tri["w"], tri["h"],
                                                     p["tri_spp"], 1,
                                                     flags_of(BASE) + ["--tri-test", test])
                    row = dict(part="tri-test", scene=tri["name"], config=test, group="time",
                               spp=p["tri_spp"], seed=1, width=tri["w"], height=tri["h"])
                    if stats is None:
                        R.row(status="failed", note=err, **row)
                        continue
                    ref = self.refs.get((tri["path"], ref_key(BASE)))
                    extra = {}
                    if ref:
                        extra = dict(relmse=relmse(img, ref["img"]), mae=mae(img, ref["img"]),
                                     ref=os.path.basename(ref["path"]))
                    R.row(status="ok", **stat_fields(stats, wall), **row, **extra)
                    res["tri_time"].setdefault(test, []).append(
                        stats["time_ms"]["render"] / 1000.0)
            for test, ts in res["tri_time"].items():
                L("  %s, %-10s render %s s (median %.4f)" % (
                    tri["name"], test, " ".join("%.4f" % t for t in ts), float(np.median(ts))))
        # (b) Ray offsets on the scene scaled up and down.
        self.part3_offsets(p)
        # (c) Film precision: same seed, float against double.
        self.part3_film(p)

    def leak_mask(self, scene_path, w, h):
        """Pixels whose whole footprint lies well inside the sphere's silhouette (2 pixels
        of margin, the polygonal silhouette is inside the sphere's)."""
        d = load_scene(scene_path)
        cam = d["camera"]
        pos = np.array(cam["position"], float)
        fwd = np.array(cam["look_at"], float) - pos
        fwd /= np.linalg.norm(fwd)
        right = np.cross(fwd, np.array(cam.get("up", [0, 1, 0]), float))
        right /= np.linalg.norm(right)
        up = np.cross(right, fwd)
        t = math.tan(math.radians(cam["fov_y"]) / 2)
        xs = (2 * (np.arange(w) + 0.5) / w - 1) * t * w / h
        ys = (1 - 2 * (np.arange(h) + 0.5) / h) * t
        X, Y = np.meshgrid(xs, ys)
        dirs = fwd + X[..., None] * right + Y[..., None] * up
        dirs /= np.linalg.norm(dirs, axis=2, keepdims=True)
        centre = np.array(d["objects"][0]["transform"]["translate"], float)
        to_c = centre - pos
        dist = np.linalg.norm(to_c)
        ang = np.arccos(np.clip(dirs @ (to_c / dist), -1, 1))
        pixel_ang = 2 * t / h
        radius = 0.99  # the icosphere's faces lie between radius 0.9995 and 1
        return ang < math.asin(radius / dist) - 2.5 * pixel_ang

    def part3_offsets(self, p):
        L, R = self.log, self.runner
        base_rel = self.args.offset_scene
        base_path = os.path.join(REPO, base_rel)
        if not os.path.exists(base_path):
            L("  ! %s absent: ray-offset study skipped" % base_rel)
            return
        base = load_scene(base_path)
        w = p["ro_w"]
        res = self.p3["offsets"] = []
        base_ref = None
        for sc in self.scenes:
            if sc["path"] == base_path and sc["w"] == w and sc["h"] == w:
                base_ref = self.refs.get((sc["path"], ref_key(BASE)))
        L("  ray offsets on %s scaled by %s, %dx%d, %d spp; artefact = a pixel whose mean "
          "differs from the robust render's by > 5 sigma (sigma from both renders' per-pixel "
          "sample variance)" % (base_rel, p["scales"], w, w, p["ro_spp"]))
        for scale in p["scales"]:
            scene_file = os.path.join(self.work, "offset_scale_%g.json" % scale)
            with open(scene_file, "w") as f:
                json.dump(scaled_scene(base, scale, os.path.dirname(base_path)), f)
            runs = {}
            for name, offset, seed in [("robust", "robust", 1), ("robust (control)", "robust", 2)] + \
                    [("eps " + e, e, 2) for e in p["eps"]]:
                if not self.guard(self.costs.run("ro", w * w, p["ro_spp"]), "ray offset"):
                    continue
                hdr = os.path.join(self.work, "offset.exr")
                stats, img, wall, err = R.render(scene_file, w, w, p["ro_spp"], seed,
                                                 flags_of(BASE) + ["--ray-offset", offset],
                                                 hdr=hdr)
                row = dict(part="ray-offset", scene="%s x%g" % (os.path.splitext(
                    os.path.basename(base_rel))[0], scale), config=name, group="offset",
                    spp=p["ro_spp"], seed=seed, width=w, height=w)
                if stats is None:
                    R.row(status="failed", note=err, **row)
                    continue
                exr = read_exr(hdr)
                var = np.stack([exr["variance." + c] for c in "RGB"], axis=2)
                n = np.maximum(exr["samples"], 1)[..., None]
                runs[name] = {"img": img, "var_mean": var / n,
                              "render_s": stats["time_ms"]["render"] / 1000.0,
                              "stats": stats, "wall": wall, "row": row}
            if "robust" not in runs:
                continue
            r0 = runs["robust"]
            for name, r in runs.items():
                if name == "robust":
                    z5, frac = 0, 0.0
                else:
                    diff = np.abs(r["img"] - r0["img"])
                    sig = np.sqrt(r["var_mean"] + r0["var_mean"])
                    z = np.where(sig > 0, diff / np.where(sig > 0, sig, 1), np.where(
                        diff > 0, np.inf, 0.0))
                    z5 = int((z.max(axis=2) > 5).sum())
                    frac = z5 / float(w * w)
                extra = {}
                if base_ref is not None:
                    extra = dict(relmse=relmse(r["img"], base_ref["img"]),
                                 mae=mae(r["img"], base_ref["img"]),
                                 ref=os.path.basename(base_ref["path"]))
                R.row(status="ok", note="%d pixels > 5 sigma from robust" % z5,
                      **stat_fields(r["stats"], r["wall"]), **r["row"], **extra)
                rec = {"scale": scale, "offset": name, "render_s": r["render_s"],
                       "pixels_5sigma": z5, "fraction": frac,
                       "relmse_vs_ref": extra.get("relmse"),
                       "mean": float(r["img"].mean())}
                res.append(rec)
                L("    scale %-6g %-17s %5d pixels > 5 sigma (%.2f%%)  relMSE vs ref %s  "
                  "render %.3f s" % (scale, name, z5, 100 * frac,
                                     "%.3e" % rec["relmse_vs_ref"] if extra else "n/a",
                                     r["render_s"]))

    def part3_film(self, p):
        L, R = self.log, self.runner
        if not self.scenes:
            return
        sc = self.scenes[0]
        ref = self.refs.get((sc["path"], ref_key(BASE)))
        out = {}
        for film in ("float", "double"):
            if not self.guard(self.costs.run(sc["path"], sc["px"], p["film_spp"]), "film"):
                continue
            s = settings({"film": film})
            stats, img, wall, err = R.render(sc["path"], sc["w"], sc["h"], p["film_spp"], 7,
                                             flags_of(s))
            row = dict(part="film", scene=sc["name"], config="film " + film, group="film",
                       spp=p["film_spp"], seed=7, width=sc["w"], height=sc["h"])
            if stats is None:
                R.row(status="failed", note=err, **row)
                continue
            extra = {}
            if ref:
                extra = dict(relmse=relmse(img, ref["img"]), mae=mae(img, ref["img"]),
                             ref=os.path.basename(ref["path"]))
            R.row(status="ok", **stat_fields(stats, wall), **row, **extra)
            out[film] = {"img": img, "render_s": stats["time_ms"]["render"] / 1000.0,
                         "relmse_vs_ref": extra.get("relmse")}
        if len(out) == 2:
            f, d = out["float"]["img"], out["double"]["img"]
            num = relmse(f, d)
            rel = float(np.max(np.abs(f - d) / np.maximum(np.abs(d), 1e-6)))
            self.p3["film"] = {"spp": p["film_spp"], "scene": sc["name"],
                                  "float_s": out["float"]["render_s"],
                                  "double_s": out["double"]["render_s"],
                                  "relmse_float_vs_double": num, "max_rel_diff": rel,
                                  "float_vs_ref": out["float"]["relmse_vs_ref"],
                                  "double_vs_ref": out["double"]["relmse_vs_ref"]}
            L("  film, %s %d spp, same seed: float %.3f s, double %.3f s; relMSE(float vs "
              "double) %.3e (pure accumulation error), max relative difference %.2e; vs "
              "reference: float %s, double %s" % (
                  sc["name"], p["film_spp"], out["float"]["render_s"],
                  out["double"]["render_s"], num, rel,
                  "%.4e" % out["float"]["relmse_vs_ref"] if ref else "n/a",
                  "%.4e" % out["double"]["relmse_vs_ref"] if ref else "n/a"))

    # --- part 5 ---------------------------------------------------------------------------
    def part3_md(self):
        p3 = self.p3
        md = ["## The price of numerical robustness (part 3)", ""]
        if p3.get("leak"):
            md += ["Leak sphere (`benchmarks/scenes/leak_sphere.json`, closed 20,480-triangle "
                   "icosphere, max_depth 0): camera rays inside the silhouette that slipped "
                   "through an edge.", "",
                   "| triangle test | leaked rays (inside) | of rays | fraction | leaked anywhere "
                   "| render s |", "|---|---|---|---|---|---|"]
            for t, v in p3["leak"].items():
                md.append("| %s | %d | %d | %.3g | %d | %.4f |" % (
                    t, v["leaked_inside"], v["rays_inside"], v["fraction"],
                    v["leaked_anywhere"], v["render_s"]))
            md.append("")
        if p3.get("tri_time"):
            md.append("Triangle test time on %s (full path tracing): " % self.tri_scene()["name"]
                      + "; ".join("%s median %.4f s" % (t, float(np.median(v)))
                                  for t, v in p3["tri_time"].items()))
            md.append("")
        if p3.get("offsets"):
            md += ["Ray offsets (`%s` scaled about the origin; the picture must not change with "
                   "scale). Artefact pixels: mean differs from the robust render's by more than "
                   "5 sigma of both renders' own variance. `robust (control)` = robust with "
                   "another seed: the test's false-alarm level." % self.args.offset_scene, "",
                   "| scale | offset | pixels > 5 sigma | % | relMSE vs scale-1 reference "
                   "| render s |", "|---|---|---|---|---|---|"]
            for r in p3["offsets"]:
                md.append("| %g | %s | %d | %.2f | %s | %.4f |" % (
                    r["scale"], r["offset"], r["pixels_5sigma"], 100 * r["fraction"],
                    "%.3e" % r["relmse_vs_ref"] if r["relmse_vs_ref"] is not None else "n/a",
                    r["render_s"]))
            md.append("")
        if p3.get("film"):
            f = p3["film"]
            md += ["Film precision, %s at %d spp with one seed: float %.4f s, double %.4f s; "
                   "relMSE(float vs double) = %.3e (accumulation rounding only), max relative "
                   "pixel difference %.2e; relMSE vs reference: float %s, double %s." % (
                       f["scene"], f["spp"], f["float_s"], f["double_s"],
                       f["relmse_float_vs_double"], f["max_rel_diff"],
                       "%.4e" % f["float_vs_ref"] if f["float_vs_ref"] is not None else "n/a",
                       "%.4e" % f["double_vs_ref"] if f["double_vs_ref"] is not None
                       else "n/a"), ""]
        return md
