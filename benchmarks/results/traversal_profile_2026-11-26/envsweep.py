#!/usr/bin/env python3
"""Variants that differ by environment variables (experiment builds), flags or binary,
alternating, N rounds; prints medians of render and stage times. Usage:
  envsweep.py BINARY ROUNDS SCENE[,SCENE...] 'name|K=V K=V|--flag v[|OTHER_BINARY]' ..."""
import json, os, statistics, subprocess, sys, tempfile
binary, rounds, scenes = sys.argv[1], int(sys.argv[2]), sys.argv[3].split(",")
variants = [v.split("|") for v in sys.argv[4:]]
res = {}
tmp = tempfile.mkdtemp()
for r in range(rounds):
    for scene in scenes:
        for v in variants:
            name, envs, flags = v[:3]
            exe = v[3] if len(v) > 3 else binary
            env = dict(os.environ)
            for kv in envs.split():
                k, v = kv.split("="); env[k] = v
            st = os.path.join(tmp, "s.json")
            cmd = [exe, scene, "-o", os.path.join(tmp, "i.exr"), "--backend", "cuda", "--quiet",
                   "--stats-json", st] + flags.split()
            p = subprocess.run(cmd, env=env, capture_output=True, text=True)
            if p.returncode: print("FAIL", name, scene, p.stderr[-500:]); continue
            s = json.load(open(st)); t = s.get("time_ms", {})
            row = res.setdefault((scene, name), [])
            g = t.get("stages", {})
            row.append((t.get("render"), g.get("intersect"), g.get("shadow"), s.get("mrays_per_s")))
            print(r, os.path.basename(scene), name, row[-1], flush=True)
print("\n| scene | variant | render ms | intersect | shadow | M rays/s | runs |\n|---|---|---|---|---|---|---|")
for (scene, name), rows in res.items():
    med = lambda i: statistics.median(x[i] for x in rows if x[i] is not None) if any(x[i] is not None for x in rows) else float('nan')
    print(f"| {os.path.basename(scene)} | {name} | {med(0):.1f} | {med(1):.1f} | {med(2):.1f} | {med(3):.0f} | {len(rows)} |")
