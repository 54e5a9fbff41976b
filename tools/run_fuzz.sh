#!/usr/bin/env bash
# Fuzzes the scene loader (fuzz/scene_loader_fuzz.cpp) with libFuzzer under AddressSanitizer
# and UndefinedBehaviorSanitizer for a bounded time.
#
#   tools/run_fuzz.sh [SECONDS]      (default 60)
#
# Builds build-fuzz/scene_loader_fuzz with clang++-14 -fsanitize=fuzzer,address,undefined from
# the loader's sources (src/io, src/scene, src/geometry, src/lights, src/materials, src/media,
# src/core/prefault.cpp; the Debian tinygltf, tinyobjloader, tinyexr, Draco, meshoptimizer and
# WebP libraries are linked as they are), replays every seed file of
# tests/malformed/ and scenes/ (scenes and meshes) once at full size, then fuzzes from those
# seeds for the given time with inputs up to 16 KiB. New interesting inputs go to
# build-fuzz/corpus (kept between runs); a crashing, leaking or hanging input is saved under
# build-fuzz/artifacts/. Exits non-zero when a seed or a fuzzed input is a finding; 0 means
# none in the time.
#
# Needs the Debian packages clang-14 and libclang-rt-14-dev.
set -euo pipefail

SECONDS_TO_RUN="${1:-60}"
if ! [[ "$SECONDS_TO_RUN" =~ ^[0-9]+$ ]] || [ "$SECONDS_TO_RUN" -lt 1 ]; then
  echo "usage: $0 [SECONDS]  (a positive whole number of seconds)" >&2
  exit 1
fi

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="$ROOT/build-fuzz"
CXX="${CXX_FUZZ:-clang++-14}"
JOBS="$(nproc 2>/dev/null || echo 2)"
command -v "$CXX" >/dev/null || { echo "run_fuzz: $CXX not found (apt-get install clang-14 libclang-rt-14-dev)" >&2; exit 1; }

mkdir -p "$OUT/obj" "$OUT/corpus" "$OUT/artifacts"

# ---- Build (recompiles only sources newer than their object; a newer header rebuilds all) ----
FLAGS=(-std=c++20 -O1 -g -fno-omit-frame-pointer
       -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
       -DGLM_FORCE_CTOR_INIT "-DPT_VERSION=\"fuzz\"" -I"$ROOT" -I/usr/include/stb -w)
# OpenVDB's reader is left out (src/io/vdb_unavailable.cpp instead): .vdb files are OpenVDB's
# own binary format, and a scene naming one still exercises the loader's refusal path.
mapfile -t SOURCES < <(cd "$ROOT" && ls src/io/*.cpp src/scene/*.cpp src/geometry/*.cpp \
                       src/lights/*.cpp src/materials/*.cpp src/media/*.cpp src/core/prefault.cpp \
                       fuzz/scene_loader_fuzz.cpp \
                       | grep -v -e '^src/io/vdb_io\.cpp$' -e '^src/io/vdb_loader\.cpp$')
STAMP="$OUT/obj/.stamp"
echo "$CXX ${FLAGS[*]}" > "$STAMP.new"
NEWER_HEADER="$( [ -f "$STAMP" ] && cd "$ROOT" && find src fuzz -name '*.h' -newer "$STAMP" | head -n 1 || true )"
if ! cmp -s "$STAMP.new" "$STAMP" || [ -n "$NEWER_HEADER" ]; then rm -f "$OUT"/obj/*.o; fi
mv "$STAMP.new" "$STAMP"
echo "run_fuzz: compiling ${#SOURCES[@]} sources with $CXX ($JOBS jobs)"
START=$(date +%s)
PIDS=()
OBJECTS=()
for src in "${SOURCES[@]}"; do
  obj="$OUT/obj/$(echo "$src" | tr '/' '_').o"
  OBJECTS+=("$obj")
  if [ ! -f "$obj" ] || [ "$ROOT/$src" -nt "$obj" ]; then
    while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do sleep 0.2; done
    "$CXX" "${FLAGS[@]}" -c "$ROOT/$src" -o "$obj.tmp" && mv "$obj.tmp" "$obj" &
    PIDS+=($!)
  fi
done
FAILED=0
for pid in "${PIDS[@]}"; do wait "$pid" || FAILED=1; done
[ "$FAILED" -eq 0 ] || { echo "run_fuzz: compilation failed" >&2; exit 1; }
"$CXX" -fsanitize=fuzzer,address,undefined -o "$OUT/scene_loader_fuzz" "${OBJECTS[@]}" \
  -ltinygltf -ltinyobjloader -ltinyexr -lstb -ldraco -lmeshoptimizer -lwebp -lz -lpthread
echo "run_fuzz: built in $(( $(date +%s) - START )) s"

# ---- Seeds, mesh folder and dictionary ----
# One base folder for relative mesh paths: its meshes/ links every mesh of both seed sets, so
# scenes/*.json and tests/malformed/*.json find theirs.
BASE="$OUT/base"
rm -rf "$BASE"
mkdir -p "$BASE/meshes"
for m in "$ROOT"/scenes/meshes/* "$ROOT"/tests/malformed/meshes/*; do
  [ -e "$m" ] && ln -sfn "$m" "$BASE/meshes/$(basename "$m")"
done
DICT="$OUT/scene.dict"
{
  for k in format render width height spp max_depth seed russian_roulette_depth adaptive tolerance \
           min_spp batch camera position look_at up fov_y aperture_radius focus_distance background \
           materials type diffuse emissive conductor dielectric plastic albedo radiance two_sided \
           roughness ior absorption objects sphere center radius quad origin u v box min max mesh \
           file material transform matrix scale rotate translate lights point intensity \
           spot directional direction inner_angle outer_angle irradiance lights_from_file from_file \
           name index cameras perspective yfov aspectRatio znear KHR_lights_punctual innerConeAngle \
           outerConeAngle range color nodes camera extensions extensionsUsed extensionsRequired \
           meshes/smooth_shapes.glb meshes/truncated.glb meshes/bad_index.obj meshes/missing_bin.gltf; do
    printf '"\\"%s\\""\n' "$k"
  done
  cat <<'DICT_END'
"[0, 0, 0]"
"1e38"
"1e400"
"-1e-400"
"true"
"null"
"//"
"/*"
"*/"
"[[[["
"{\"a\": "
"NaN"
"glTF"
"JSON"
"BIN\x00"
DICT_END
} > "$DICT"

# ---- Replay every seed at full size (the fuzzing below truncates inputs to -max_len) ----
export PT_FUZZ_BASE_DIR="$BASE"
export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"
SEEDS=("$ROOT/tests/malformed" "$ROOT/scenes")
# One process per seed (a finding names its seed), $JOBS at a time; the log keeps the output
# of the seeds that failed.
: > "$OUT/replay.log"
: > "$OUT/replay_failed.txt"
export FUZZ_BIN="$OUT/scene_loader_fuzz" REPLAY_LOG="$OUT/replay.log" REPLAY_FAILED="$OUT/replay_failed.txt"
find "${SEEDS[@]}" -type f -print0 | sort -z | xargs -0 -n 1 -P "$JOBS" sh -c '
  if ! out=$("$FUZZ_BIN" -timeout=60 -rss_limit_mb=2560 "$1" 2>&1); then
    printf "%s\n" "$1" >> "$REPLAY_FAILED"
    printf "== %s\n%s\n" "$1" "$out" >> "$REPLAY_LOG"
  fi' replay
FINDINGS=$(wc -l < "$OUT/replay_failed.txt")
while IFS= read -r seed; do echo "run_fuzz: FINDING on seed ${seed#$ROOT/}" >&2; done < "$OUT/replay_failed.txt"
echo "run_fuzz: replayed $(find "${SEEDS[@]}" -type f | wc -l) seeds, $FINDINGS findings (log: $OUT/replay.log)"

# ---- Fuzz ----
echo "run_fuzz: fuzzing for $SECONDS_TO_RUN s, seeds: tests/malformed, scenes"
set +e
"$OUT/scene_loader_fuzz" "$OUT/corpus" "${SEEDS[@]}" \
  -max_total_time="$SECONDS_TO_RUN" -timeout=60 -rss_limit_mb=2560 -max_len=16384 \
  -dict="$DICT" -artifact_prefix="$OUT/artifacts/" -print_final_stats=1 \
  > "$OUT/fuzz.log" 2>&1
STATUS=$?
set -e
grep -E "^#[0-9]+.*(DONE|pulse)|stat::number_of_executed_units|stat::peak_rss_mb" "$OUT/fuzz.log" | tail -n 3 || true
if [ "$STATUS" -ne 0 ]; then
  echo "run_fuzz: FINDING while fuzzing (libFuzzer exit status $STATUS); log: $OUT/fuzz.log" >&2
  grep -E "ERROR|SUMMARY|runtime error|terminate|deadly|Test unit written" "$OUT/fuzz.log" | head -n 20 >&2 || true
  FINDINGS=$((FINDINGS + 1))
fi
if [ "$FINDINGS" -ne 0 ]; then
  echo "run_fuzz: $FINDINGS finding(s)" >&2
  exit 1
fi
echo "run_fuzz: no finding ($(grep -o 'stat::number_of_executed_units: [0-9]*' "$OUT/fuzz.log" | grep -o '[0-9]*$' || echo '?') inputs in $SECONDS_TO_RUN s)"
