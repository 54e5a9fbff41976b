#!/usr/bin/env bash
# Scenes without media must render exactly as before media existed. Renders every scene of
# scenes/ without media (small, few samples, CPU backend) with a binary built before the media
# work and with this one, and compares the linear images bit for bit (tools/image_compare
# exits 0 only then).
#
#   bash benchmarks/media_identity_check.sh BEFORE_PATHTRACER AFTER_PATHTRACER IMAGE_COMPARE [OUT]
#   e.g. bash benchmarks/media_identity_check.sh /work/main/build/pathtracer build/pathtracer \
#            build/image_compare /tmp/identity
# Add --backend cuda through BACKEND=cuda to compare GPU renders (same-GPU runs are compared
# with the same tool; the CUDA backend is deterministic per device).
set -euo pipefail
before=$1 after=$2 compare=$3 out=${4:-$(mktemp -d)}
backend=${BACKEND:-cpu}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
status=0
scenes=("$here"/scenes/*.json)
# BENCH_SCENES=1: the benchmark scenes too (shared assets; media scenes of ours skipped).
if [ -n "${BENCH_SCENES:-}" ]; then
  for s in "$here"/benchmarks/scenes/*.json; do
    grep -q '"media"' "$s" || scenes+=("$s")
  done
fi
for scene in "${scenes[@]}"; do
  grep -q '"media"' "$scene" && continue  # media scenes: new, nothing to compare with
  name=$(basename "$scene" .json)
  for bin in before after; do
    exe=$before; [ $bin = after ] && exe=$after
    "$exe" "$scene" -o "$out/$name.$bin.png" --hdr "$out/$name.$bin.exr" --width 64 --height 48 \
      --spp 4 --backend "$backend" --quiet 2>/dev/null
  done
  if "$compare" "$out/$name.before.exr" "$out/$name.after.exr" > "$out/$name.txt"; then
    echo "identical: $name"
  else
    echo "DIFFERENT: $name ($(tail -1 "$out/$name.txt"))"
    status=1
  fi
done
exit $status
