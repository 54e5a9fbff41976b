#!/usr/bin/env bash
# One render on 1 GPU against the same render split over N GPUs by MPI (issues 12 and 15):
# time (medians of REPEATS runs), efficiency = T1 / (N * TN), the same image as one GPU, and
# where the time goes (start-up, render, reduction), from --stats-json. Run on the GPU machine
# from a folder holding the packed binaries (tools/pack_device.sh: bin/, mpi/, shared/):
#
#   OUT=out bash benchmarks/mpi_gpu_check.sh [PACK=.device] [SOURCE=.]
#
# SOURCE holds scenes/ and benchmarks/scenes/; benchmark scenes reach ../../../shared, which
# must lead to PACK/shared. Environment: GPUS (default: all, up to 8; the list of counts to
# run is "1 GPUS" unless COUNTS is set, e.g. COUNTS="1 2 4 8"), REPEATS (3), SCENES ("bunny
# breakfast"), SPP (1024), LANES_CHECK (empty: skip the one-lane run), EXTRA (more options for every run), BACKEND (cuda; cpu checks the
# script on a machine without a GPU: BACKEND=cpu SPP=4 EXTRA="--width 64 --height 36").
set -uo pipefail
PACK="$(cd "${1:-.device}" && pwd)"
SOURCE="$(cd "${2:-.}" && pwd)"
OUT="${OUT:-out}"
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"
S="$OUT/stats"  # every --stats-json and comparison, packed into stats.tar.gz at the end
mkdir -p "$S"
exec > >(tee "$OUT/log.txt") 2>&1
T="$(mktemp -d)"
# Benchmark scenes reach ../../../shared from benchmarks/scenes/: point it at the carried copy.
[ -e "$SOURCE/../shared" ] || ln -s "$PACK/shared" "$SOURCE/../shared"
BIN="$PACK/bin/pathtracer"
CMP="$PACK/bin/image_compare"
REPEATS="${REPEATS:-3}"
SPP="${SPP:-1024}"
BACKEND="${BACKEND:-cuda}"
# NVLink multicast stays off on shared machines (KINDS.md); nothing here uses NCCL anyway.
export NCCL_NVLS_ENABLE=0
if [ "$BACKEND" = cuda ]; then
  GPUS="${GPUS:-$(nvidia-smi -L | wc -l)}"
else
  GPUS="${GPUS:-2}"
fi
COUNTS="${COUNTS:-1 $GPUS}"
CHUNKS=$((SPP < 32 ? SPP : 32))  # the split's default chunk count
SCENES="${SCENES:-bunny breakfast}"
step() { echo; echo "=== $* ($(date +%T))"; }

step "machine"
[ "$BACKEND" = cuda ] && nvidia-smi -L && nvidia-smi topo -m
nproc

# Open MPI: the packed Debian runtime (what the binary was built with), else the machine's own.
step "MPI"
MPI_MODE=""
hello() {  # $1: a shell prefix that sets the environment up
  (eval "$1"; mpirun --allow-run-as-root --bind-to none -np 2 "$BIN" "$SOURCE/scenes/cornell_box.json" \
     -o "$T/hello.png" --width 16 --height 16 --spp 4 --backend cpu --threads 1 --quiet) > "$T/hello.log" 2>&1 \
    && grep -q "2 ranks" "$T/hello.log"
}
if [ -f "$PACK/mpi/env.sh" ] && hello "source $PACK/mpi/env.sh"; then
  MPI_MODE="source $PACK/mpi/env.sh"
elif hello "true"; then
  MPI_MODE="true"
else
  cat "$T/hello.log"
  echo "no working mpirun: neither the packed Open MPI nor the machine's"
  exit 1
fi
# Every run from here on, one-process ones too, loads that libmpi.
eval "$MPI_MODE"
echo "MPI: ${MPI_MODE} ($(mpirun --version | head -1))"
ldd "$BIN" | grep -E "not found" && echo "missing libraries" && exit 1
mpi() {  # mpi N ARGS...: the binary on N ranks, one GPU each
  local n="$1"
  shift
  mpirun --allow-run-as-root --bind-to none -np "$n" "$BIN" "$@"
}

scene_file() {
  case "$1" in
    bunny) echo "$SOURCE/benchmarks/scenes/bunny_cornell.json" ;;
    breakfast) echo "$SOURCE/benchmarks/scenes/breakfast_room.json" ;;
    *) echo "$SOURCE/$1" ;;
  esac
}

for name in $SCENES; do
  scene="$(scene_file "$name")"
  common=(--spp "$SPP" --backend "$BACKEND" --quiet ${EXTRA:-})
  for n in $COUNTS; do
    for r in $(seq 1 "$REPEATS"); do
      step "$name: $n GPU(s), run $r"
      tag="${name}_${n}gpu_$r"
      t0=$(date +%s.%N)
      if [ "$n" = 1 ]; then
        "$BIN" "$scene" -o "$T/$tag.png" --hdr "$T/$tag.pfm" --stats-json "$S/$tag.json" \
          "${common[@]}" 2>&1 | tail -2
      else
        mpi "$n" "$scene" -o "$T/$tag.png" --hdr "$T/$tag.pfm" --stats-json "$S/$tag.json" \
          "${common[@]}" 2>&1 | tail -$((n + 2))
      fi
      awk -v a="$t0" -v b="$(date +%s.%N)" -v t="$tag" 'BEGIN { printf "%s,%.3f\n", t, b - a }' >> "$S/wall.csv"
    done
  done
  step "$name: 1 GPU with the chunks of the split (the bits it must reproduce)"
  "$BIN" "$scene" -o "$T/${name}_chunks.png" --hdr "$T/${name}_chunks.pfm" --chunks "$CHUNKS" \
    --stats-json "$S/${name}_1gpu_chunks.json" "${common[@]}" 2>&1 | tail -1
  for n in $COUNTS; do
    [ "$n" = 1 ] && continue
    step "$name: $n GPUs against 1 GPU"
    echo "-- bit for bit against one GPU with --chunks $CHUNKS:"
    "$CMP" "$T/${name}_chunks.pfm" "$T/${name}_${n}gpu_1.pfm" | tee "$S/${name}_${n}gpu_compare.txt"
    echo "-- run 1 against run 2:"
    "$CMP" "$T/${name}_${n}gpu_1.pfm" "$T/${name}_${n}gpu_2.pfm" | tail -1 | tee -a "$S/${name}_${n}gpu_compare.txt"
    echo "-- against the plain one-GPU render (float summation order only):"
    "$CMP" "$T/${name}_1gpu_1.pfm" "$T/${name}_${n}gpu_1.pfm" --max-rel 1e-3 | tee -a "$S/${name}_${n}gpu_compare.txt"
  done
  cp "$T/${name}_${GPUS}gpu_1.png" "$OUT/${name}_${GPUS}gpu.png" 2>/dev/null || true
done

if [ -n "${LANES_CHECK-1}" ] && [ "$GPUS" -gt 1 ]; then
  name="${SCENES%% *}"
  step "$name: $GPUS GPUs with one lane each (no overlap of film downloads)"
  mpi "$GPUS" "$(scene_file "$name")" -o "$T/lanes1.png" --stats-json "$S/${name}_${GPUS}gpu_lanes1.json" \
    --spp "$SPP" --backend "$BACKEND" --quiet ${EXTRA:-} --lanes 1 2>&1 | tail -1
fi

step "summary"
python3 "$SOURCE/benchmarks/mpi_summary.py" "$S" | tee "$OUT/summary.md"
tar czf "$OUT/stats.tar.gz" -C "$OUT" stats && rm -rf "$S"
rm -rf "$T"
