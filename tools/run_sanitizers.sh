#!/usr/bin/env bash
# Builds the CPU renderer and its tests with AddressSanitizer + UndefinedBehaviorSanitizer
# (PT_SANITIZE=ON) in build-asan/ and runs the test suite there with ctest. Exits non-zero when
# the build fails, a test fails, or a sanitizer reports anything (UBSan halts on the first
# report, so it fails its test; ASan and LeakSanitizer fail theirs; child `pathtracer`
# processes started by the CLI tests are sanitized too).
#
#   tools/run_sanitizers.sh            (build-asan is reused: a second run only rebuilds changes)
#
# It is also the configuration without the optional components (-DPT_ENABLE_CUDA=OFF
# -DPT_ENABLE_MPI=OFF): the suite there checks that everything works without them and that a
# start by mpirun is refused (tests/mpi_run_test.cpp, NoMpiBuild); the MPI tests themselves run
# in the main build.
#
# Build type "Asan": -O1 -g1 (line tables for readable reports, and about half the compile time
# of -O2 -g on two cores). From scratch on 2 idle cores: ~5 minutes to build and ~3.5 minutes of
# tests.
#
# Left out by default (PT_SANITIZE_EXCLUDE replaces the list; '' runs everything), to keep CI
# under its time (each still runs in the main build):
# - MalformedScenes.CliExitsTwoAndWritesNothing starts the CLI once per malformed file (167
#   sanitized process starts, ~50 s); the same files go through the same loader in-process under
#   the sanitizers (MalformedScenes.EveryFileIsASceneErrorNamingFileAndField,
#   FromStringGivesTheSameErrors) and the CLI's refusal path is run sanitized by
#   GltfSceneErrors.CliExitsTwoNamingTheFileAndWritesNothing and CliRun.BadCommandLineExitsOne.
# - Ten statistical or brute-force tests that repeat one code path over many inputs (259 s of
#   CPU under ASan, 40% of the stage): the same walks, BSDFs and integrators run
#   sanitized in the many smaller tests (AxisRays.*, BvhTraversal.*, BvhWide.* others,
#   *.WhiteFurnace*, HardTransport.*, Specialization.*).
# Every other test runs well under 60 s here, and the one wall-clock assertion
# (BvhBuild.BuildsQuicklyAt270kTriangles) is compiled out under ASan by the test itself.
#
# Without OpenVDB and the Python module too (as without CUDA and MPI): their absence is what
# this configuration proves works (a .vdb medium is a clear error: MediaVdb.WithoutOpenVdbGridFilesAreAClearError), and
# OpenVDB's headers are the slowest source to compile (the main build reads .vdb files).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="$ROOT/build-asan"
JOBS="${JOBS:-$(nproc 2>/dev/null || echo 2)}"
EXCLUDE="${PT_SANITIZE_EXCLUDE-^(MalformedScenes\.CliExitsTwoAndWritesNothing|BvhTraversal\.MatchesBruteForceOnSoups|BvhWide\.NearestChildFirstWalkMatchesBruteForce|BvhWide\.ClosestHitOnCoincidentSurfacesIsIndependentOfTheTree|IntegratorAgreement\.MisBsdfNeeAgreeInTheMeanOnCornellBox|GltfLayeredTest\.SamplingMatchesPdf|GltfPbrTest\.SamplingMatchesPdf|GltfPbrTest\.OpaqueWhiteFurnaceNeverCreatesEnergy|RoughDielectricTest\.SamplingMatchesPdfOutsideAndInside|Specialization\.EveryProjectSceneIsBitIdenticalToTheGeneralVariant|Instancing\.TwoLevelHitsMatchBruteForceInObjectAndWorldSpace)$}"

START=$(date +%s)
# Unix Makefiles (CMake's default, what most users build with) here, Ninja in the main build:
# CI builds with both generators. A build-asan/ left by an earlier Ninja configuration is
# started afresh (CMake refuses to switch a build tree's generator).
if [ -f "$BUILD/CMakeCache.txt" ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Unix Makefiles$' "$BUILD/CMakeCache.txt"; then
  rm -rf "$BUILD"
fi
cmake -S "$ROOT" -B "$BUILD" -G "Unix Makefiles" -DPT_SANITIZE=ON -DPT_ENABLE_CUDA=OFF -DPT_ENABLE_MPI=OFF \
  -DPT_ENABLE_OPENVDB=OFF -DPT_ENABLE_PYTHON=OFF -DPT_HOST_ISA=baseline \
  -DCMAKE_BUILD_TYPE=Asan -DCMAKE_CXX_FLAGS_ASAN="-O1 -g1 -fno-omit-frame-pointer" >/dev/null
# The suite and what it runs (pathtracer, make_mesh_glb, make_sky), not the benchmark tools.
cmake --build "$BUILD" -j "$JOBS" --target pt_tests pathtracer
BUILT=$(date +%s)
echo "run_sanitizers: built in $((BUILT - START)) s"

# halt_on_error: a UBSan report aborts its process (GCC's default is to print and go on).
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:${UBSAN_OPTIONS:-}"
export ASAN_OPTIONS="detect_leaks=1:check_initialization_order=1:strict_init_order=1:${ASAN_OPTIONS:-}"
set +e
CTEST_ARGS=(--test-dir "$BUILD" -j "$JOBS" --output-on-failure --timeout 300)
if [ -n "$EXCLUDE" ]; then CTEST_ARGS+=(-E "$EXCLUDE"); fi
ctest "${CTEST_ARGS[@]}" 2>&1 | tee "$BUILD/sanitizers.log"
STATUS=${PIPESTATUS[0]}
set -e
echo "run_sanitizers: tests ran in $(( $(date +%s) - BUILT )) s; excluded: ${EXCLUDE:-none}"
REPORTS=$(grep -cE "ERROR: (Address|Leak)Sanitizer|runtime error:" "$BUILD/sanitizers.log" || true)
if [ "$STATUS" -ne 0 ] || [ "$REPORTS" -ne 0 ]; then
  echo "run_sanitizers: FAILED (ctest status $STATUS, $REPORTS sanitizer reports); log: $BUILD/sanitizers.log" >&2
  exit 1
fi
echo "run_sanitizers: clean"
