#!/usr/bin/env python3
"""What accuracy costs in time: error (relMSE, MAE) against render time for the integrator's
settings, the price of numerical robustness, and a comparison with published references.

Method and the exact commands: benchmarks/ACCURACY.md. Needs only Python 3 and numpy (no
matplotlib: benchmarks/accuracy_plot.py draws the charts afterwards from the CSV).

Parts (all by default; --parts picks):
  1  references: per scene and per setting that changes the integral (max_depth, light
     paths), a high-spp render made of two halves with different seeds; their difference
     gives the reference's own noise, which must be >= 10x below every error plotted.
  2  the study: relMSE (as ../shared/cli.md defines it) and MAE against the matching
     reference, with render time, for each configuration at increasing spp and several seeds.
  3  robustness: --tri-test (time, leaked rays), --ray-offset (time, 5-sigma artefacts on
     scaled scenes), --film (time, accumulation error).
  5  published references: Bitterli's Cornell box and Veach MIS at the reference resolution,
     relMSE against the Tungsten EXRs via --reference.
  (4, the analysis, always runs: CSV, accuracy_table.md, summary.json, the summary table.)

Everything goes under --out. Typical use (the lead's GPU call is in ACCURACY.md):
  python3 benchmarks/accuracy.py --backend cuda --binary .device/bin/pathtracer --out "$OUT"
  python3 benchmarks/accuracy.py --backend cpu --quick --out /tmp/acc_quick      # smoke test
  python3 benchmarks/accuracy.py --translate-tungsten   # rewrite the two Bitterli scenes
"""
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
from accuracy_published import PublishedParts, translate_tungsten  # noqa: F401
from accuracy_report import ReportParts
from accuracy_robustness import RobustnessParts

class Study(RobustnessParts, ReportParts, PublishedParts):
    def __init__(self, args):
        self.args = args
        self.t0 = time.perf_counter()
        self.budget_s = args.budget_minutes * 60.0
        os.makedirs(args.out, exist_ok=True)
        self.log = Log(os.path.join(args.out, "accuracy.log"))
        self.work = tempfile.mkdtemp(prefix="accuracy_")
        self.runner = Runner(args, self.log, self.work, os.path.join(args.out,
                                                                     "accuracy_runs.csv"))
        self.costs = Costs(args.backend)
        self.refs = {}        # (scene path, key) -> {"img", "noise", "path"}
        self.results = []     # part-2 rows (dicts)
        self.p3 = {}
        self.p5 = []
        self.xcheck = []
        self.skipped = 0
        self.scenes = self.resolve_scenes()

    def elapsed(self):
        return time.perf_counter() - self.t0

    # --- set-up --------------------------------------------------------------------------
    def resolve_scenes(self):
        a = self.args
        specs = a.scenes.split(",") if a.scenes else list(DEFAULT_SCENES)
        scenes = []
        for spec in specs:
            path, _, size = spec.partition(":")
            w, h = (int(v) for v in size.split("x")) if size else (128, 128)
            full = path if os.path.isabs(path) else os.path.join(REPO, path)
            if not os.path.exists(full) and path.endswith("glossy_spheres.json"):
                self.log("note: %s is absent; using %s in its place" % (path, GLOSSY_FALLBACK))
                path, full = GLOSSY_FALLBACK, os.path.join(REPO, GLOSSY_FALLBACK)
            if not os.path.exists(full):
                self.log("note: scene %s is absent; left out" % path)
                continue
            if a.quick:
                w, h = QUICK_SIZE.get(w, max(8, w // 8)), QUICK_SIZE.get(h, max(8, h // 8))
            try:
                desc = load_scene(full)
                point_lights = len(desc.get("lights", []))
            except (OSError, ValueError):
                point_lights = 0
            name = os.path.splitext(os.path.basename(path))[0]
            scenes.append({"path": full, "rel": path, "name": name, "w": w, "h": h,
                           "px": w * h, "point_lights": point_lights})
        return scenes

    def keys_needed(self):
        keys = []
        for cfg in CONFIGS:
            k = ref_key(settings(cfg[3]))
            if k not in keys:
                keys.append(k)
        return keys

    def ref_spp_half(self):
        return max(1, self.args.ref_spp // 2)

    def estimate_part1(self):
        return sum(2 * self.costs.run(sc["path"], sc["px"], self.ref_spp_half())
                   for sc in self.scenes for _ in self.keys_needed())

    def print_plan(self, plan, header):
        a, L = self.args, self.log
        runs = plan.runs(self.scenes)
        L("")
        L("== %s" % header)
        L("backend %s, binary %s, budget %.1f min, elapsed %.1f s" % (
            a.backend, a.binary, a.budget_minutes, self.elapsed()))
        for sc in self.scenes:
            L("  scene %-45s %dx%d%s" % (sc["rel"], sc["w"], sc["h"],
                                         "  (%d point lights)" % sc["point_lights"]
                                         if sc["point_lights"] else ""))
        L("  part 1: %d references per scene (%s), each %d spp = 2 halves x %d spp "
          "(seeds %d, %d): %d runs" % (
              len(self.keys_needed()), ", ".join(ref_name(k) for k in self.keys_needed()),
              2 * self.ref_spp_half(), self.ref_spp_half(), REF_SEEDS[0], REF_SEEDS[1],
              2 * len(self.keys_needed()) * len(self.scenes)))
        L("  part 2 plan [%s]: spp %s; seeds: %d for tier-1 configs (%d), %d for tier-2 (%d); "
          "%d runs" % (plan.label, plan.budgets, plan.seeds1,
                       sum(1 for c in CONFIGS if c[2] == 1), plan.seeds2,
                       sum(1 for c in CONFIGS if c[2] == 2), len(runs)))
        L("    configs: " + "; ".join("%s [%s]" % (c[0], " ".join(
            "%s %s" % (FLAG_NAMES.get(k, "--" + k), v) for k, v in c[3].items()) or "baseline")
            for c in CONFIGS))
        L("    baseline flags: " + " ".join(flags_of(BASE)))
        L("  estimated: part 1 %.0f s, part 2 %.0f s, part 3 %.0f s, part 5 %.0f s "
          "(cost model: %s)" % (self.estimate_part1(), plan.cost(self.scenes, self.costs),
                                self.estimate_part3(), self.estimate_part5(),
                                "calibrated on the references" if self.costs.overhead else
                                "assumed start-up %.2f s/run, %.3g M samples/s" % (
                                    self.costs.default_overhead,
                                    self.costs.default_thr / 1e6)))

    # --- part 1 ---------------------------------------------------------------------------
    def part1(self):
        L = self.log
        L("")
        L("== part 1: references (%d spp each, 2 halves)" % (2 * self.ref_spp_half()))
        refdir = os.path.join(self.work, "refs")
        os.makedirs(refdir, exist_ok=True)
        for sc in self.scenes:
            cal = []
            for key in self.keys_needed():
                s = settings({"depth": key[0], "lp": key[1], "film": "double"})
                halves = []
                for seed in REF_SEEDS:
                    stats, img, wall, err = self.runner.render(
                        sc["path"], sc["w"], sc["h"], self.ref_spp_half(), seed, flags_of(s))
                    row = dict(part="reference", scene=sc["name"], config=ref_name(key),
                               group="reference", spp=self.ref_spp_half(), seed=seed,
                               width=sc["w"], height=sc["h"])
                    if stats is None:
                        self.runner.row(status="failed", note=err, **row)
                        continue
                    self.runner.row(status="ok", **stat_fields(stats, wall), **row)
                    cal.append((wall, stats["time_ms"]["render"] / 1000.0, stats["samples"]))
                    halves.append(img)
                if len(halves) != 2:
                    L("  ! %s %s: reference failed" % (sc["name"], ref_name(key)))
                    continue
                a, b = halves
                ref = 0.5 * (a + b)
                # Var(ref) = E[(a - b)^2] / 4 for independent halves of equal spp.
                noise = float(np.mean((a - b) ** 2 / 4.0 / (ref * ref + REL_EPS)))
                path = os.path.join(refdir, "%s_%s.pfm" % (sc["name"], ref_name(key)))
                write_pfm(path, ref)
                self.refs[(sc["path"], key)] = {"img": read_pfm(path), "noise": noise,
                                                "path": path, "mean": float(ref.mean())}
                L("  %-22s %-18s noise relMSE %.3e  mean %.4f  (%.1f s)" % (
                    sc["name"], ref_name(key), noise, float(ref.mean()), self.elapsed()))
            self.costs.calibrate(sc["path"], cal)
            if sc["path"] in self.costs.overhead:
                L("  calibration %s: %.3f s start-up/run, %.1f M samples/s" % (
                    sc["name"], self.costs.overhead[sc["path"]], self.costs.thr[sc["path"]] / 1e6))
        if self.costs.overhead:  # the other parts' scenes: the median of the measured ones
            ohs = sorted(self.costs.overhead.values())
            thrs = sorted(self.costs.thr.values())
            self.costs.default_overhead = ohs[len(ohs) // 2]
            self.costs.default_thr = thrs[len(thrs) // 2]

    # --- part 2 ---------------------------------------------------------------------------
    def part2(self, plan, deadline):
        L = self.log
        runs = plan.runs(self.scenes)
        L("")
        L("== part 2: %d runs (deadline for this part at %.0f s)" % (len(runs), deadline))
        # The renderer's own relMSE (--reference) against ours, once per scene (untimed).
        for sc in self.scenes:
            ref = self.refs.get((sc["path"], ref_key(BASE)))
            if not ref:
                continue
            stats, img, wall, err = self.runner.render(sc["path"], sc["w"], sc["h"], 16, 99,
                                                       flags_of(BASE), reference=ref["path"])
            if stats and stats.get("reference_relmse"):
                theirs = stats["reference_relmse"][-1]["relmse"]
                ours = relmse(img, ref["img"])
                ok = abs(theirs - ours) <= 1e-4 * max(ours, 1e-12) + 1e-9
                self.xcheck.append((sc["name"], ours, theirs, ok))
                L("  relMSE check %-20s numpy %.6e  renderer --reference %.6e  %s" % (
                    sc["name"], ours, theirs, "agree" if ok else "DISAGREE"))
                self.runner.row(part="xcheck", scene=sc["name"], config="mis", group="xcheck",
                                spp=16, seed=99, width=sc["w"], height=sc["h"], relmse=ours,
                                mae=mae(img, ref["img"]), ref=os.path.basename(ref["path"]),
                                status="ok", note="renderer relMSE %.9g" % theirs,
                                **stat_fields(stats, wall))
        last_report = time.perf_counter()
        for n, (sc, cfg, spp, seed) in enumerate(runs):
            est = self.costs.run(sc["path"], sc["px"], spp, cfg[4])
            if self.elapsed() + est > deadline:
                self.skipped += 1
                continue
            s = settings(cfg[3])
            ref = self.refs.get((sc["path"], ref_key(s)))
            row = dict(part="study", scene=sc["name"], config=cfg[0], group=cfg[1], spp=spp,
                       seed=seed, width=sc["w"], height=sc["h"])
            stats, img, wall, err = self.runner.render(sc["path"], sc["w"], sc["h"], spp, seed,
                                                       flags_of(s))
            if stats is None:
                self.runner.row(status="failed", note=err, **row)
                continue
            f = stat_fields(stats, wall)
            rec = dict(row, **f)
            if ref is not None:
                rec["relmse"] = relmse(img, ref["img"])
                rec["mae"] = mae(img, ref["img"])
                rec["ref"] = os.path.basename(ref["path"])
            self.results.append(rec)
            self.runner.row(status="ok", **{k: v for k, v in rec.items()})
            if time.perf_counter() - last_report > 15 or n + 1 == len(runs):
                last_report = time.perf_counter()
                L("  %d/%d runs, %.0f s elapsed" % (n + 1, len(runs), self.elapsed()))
        if self.skipped:
            L("  ! %d runs skipped to stay within the time budget" % self.skipped)

    # --- part 3 ---------------------------------------------------------------------------
    def guard(self, est, what):
        limit = self.budget_s + self.args.grace
        if self.elapsed() + est > limit:
            self.log("  ! skipped %s: it would end past %.0f s" % (what, limit))
            return False
        return True

    def run(self):
        a, L = self.args, self.log
        if not self.scenes:
            L("no scenes to study")
            return 1
        reserve = self.estimate_part3() + self.estimate_part5() + 5.0
        allowed = self.budget_s - self.estimate_part1() - reserve
        plan = choose_plan(a, self.scenes, self.costs, allowed)
        self.print_plan(plan, "plan (before calibration)")
        if a.dry_run:
            return 0
        if "1" in a.parts or "2" in a.parts:
            self.part1()
        if "2" in a.parts:
            reserve = self.estimate_part3() + self.estimate_part5() + 5.0
            allowed = self.budget_s - self.elapsed() - reserve
            plan = choose_plan(a, self.scenes, self.costs, allowed)
            self.print_plan(plan, "plan (calibrated on the references)")
            self.part2(plan, self.budget_s - reserve)
        if "3" in a.parts:
            self.part3()
        if "5" in a.parts:
            self.part5()
        self.write_outputs(plan)
        shutil.rmtree(self.work, ignore_errors=True)
        return 0


def find_binary(backend):
    for p in ([".device/bin/pathtracer", "build/pathtracer"] if backend == "cuda" else
              ["build-acc/pathtracer", "build/pathtracer"]):
        full = os.path.join(REPO, p)
        if os.path.exists(full):
            return full
    return None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", help="the pathtracer (default: .device/bin, build, build-acc)")
    ap.add_argument("--backend", default="cuda", choices=["cuda", "cpu"])
    ap.add_argument("--out", default=os.path.join(REPO, "out", "accuracy"),
                    help="output folder (the lead passes $OUT)")
    ap.add_argument("--quick", action="store_true",
                    help="smoke test: tiny images, spp 4 and 16, 2 seeds, 1024-spp references")
    ap.add_argument("--budget-minutes", type=float, default=7.0,
                    help="total time to plan for (default 7)")
    ap.add_argument("--grace", type=float, default=45.0,
                    help="seconds parts 3 and 5 may run past the budget (default 45)")
    ap.add_argument("--scenes", help="comma-separated PATH[:WxH] (default: %s)"
                    % ",".join(DEFAULT_SCENES))
    ap.add_argument("--shared", default=os.path.join(os.path.dirname(REPO), "shared"),
                    help="the shared folder with assets/ (default ../shared)")
    ap.add_argument("--ref-spp", type=int, help="spp of each reference (two halves); "
                    "default 65536 (quick: 1024)")
    ap.add_argument("--budgets", help="part 2 spp list, e.g. 1,4,16,64,256,1024 (no trimming)")
    ap.add_argument("--seeds", type=int, default=4, help="most seeds per budget (default 4)")
    ap.add_argument("--parts", default="1,2,3,5", help="parts to run (default 1,2,3,5)")
    ap.add_argument("--offset-scene", default="scenes/cornell_glass_mirror.json",
                    help="scene of the ray-offset study")
    ap.add_argument("--offset-scales", default="1e-3,1,1e3,1e4",
                    help="scales of the ray-offset study (default 1e-3,1,1e3,1e4)")
    ap.add_argument("--threads", type=int, default=0, help="CPU threads (cpu backend)")
    ap.add_argument("--no-images", action="store_true",
                    help="write only the 4 text outputs (no accuracy_refs.npz, no PNGs)")
    ap.add_argument("--dry-run", action="store_true", help="print the plan and stop")
    ap.add_argument("--translate-tungsten", action="store_true",
                    help="rewrite benchmarks/scenes/{bitterli_cornell,veach_mis}.json from "
                    "the Tungsten files in --shared, and stop")
    a = ap.parse_args(argv)
    a.shared = os.path.abspath(a.shared)
    if a.translate_tungsten:
        translate_tungsten(a.shared)
        return 0
    a.parts = set(a.parts.split(","))
    if a.ref_spp is None:
        a.ref_spp = 1024 if a.quick else 65536
    if a.quick:
        a.seeds = min(a.seeds, 2)
    a.binary = a.binary or find_binary(a.backend)
    if not a.binary or not os.path.exists(a.binary):
        print("no pathtracer binary found; pass --binary", file=sys.stderr)
        return 2
    a.binary = os.path.abspath(a.binary)
    a.out = os.path.abspath(a.out)
    return Study(a).run()


if __name__ == "__main__":
    sys.exit(main())
