#!/usr/bin/env python3
"""Summarises ncu's per-SASS-instruction source counters (sass_*.csv.gz, from run.sh): runs of
instructions with the same execution count (basic blocks, roughly), with their share of the
kernel's warp instructions, thread instructions per ray, active lanes and stall samples.
  sass_regions.py sass_wide.csv.gz RAYS"""
import csv, gzip, io, sys
rows = list(csv.reader(io.TextIOWrapper(gzip.open(sys.argv[1]), encoding="utf-8")))
rays = int(sys.argv[2])
hdr, data = rows[1], rows[2:]
iS, iT = hdr.index("Source"), hdr.index("Thread Instructions Executed")
iW, iSm = hdr.index("Instructions Executed"), hdr.index("Warp Stall Sampling (All Samples)")
blocks, cur = [], None
for i, r in enumerate(data):
    w, t, sm = int(r[iW]), int(r[iT]), int(r[iSm])
    if cur and cur["w"] == w:
        cur.update(n=cur["n"] + 1, t=cur["t"] + t, sm=cur["sm"] + sm, end=i)
    else:
        cur = dict(start=i, end=i, w=w, n=1, t=t, sm=sm, first=r[iS].strip()[:44])
        blocks.append(cur)
totw = sum(b["w"] * b["n"] for b in blocks)
tott = sum(b["t"] for b in blocks)
totsm = sum(b["sm"] for b in blocks)
print(f"{len(data)} SASS instructions; per ray: {totw / rays:.0f} warp instructions, "
      f"{tott / rays:.0f} thread instructions ({tott / totw:.2f} active lanes)")
print("first-last  count  warp%  thread/ray  lanes  stall%  first instruction")
for b in blocks:
    ww = b["w"] * b["n"]
    if ww / totw > 0.01 or b["sm"] / totsm > 0.01:
        print(f"{b['start']:5d}-{b['end']:<5d} {b['n']:4d} {100 * ww / totw:6.1f} {b['t'] / rays:10.1f} "
              f"{b['t'] / max(1, ww):6.2f} {100 * b['sm'] / totsm:6.1f}  {b['first']}")
