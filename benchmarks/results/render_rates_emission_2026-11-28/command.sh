#!/bin/bash
# H100 (device call of 2026-11-28): render rates of c8f16f4 (new) against d3c2fa2 (base, the
# flat shade copy), 5 interleaved rounds; summary.txt is its output (the per-run stats JSON
# did not all come back from the device).
python3 benchmarks/compare_renders.py --binary base=build_q/base/pathtracer \
  --binary new=build_q/new/pathtracer --rounds 5 --out $OUT/r
