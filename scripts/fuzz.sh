#!/usr/bin/env bash
# Fuzz the scene reader + validator and the up-front limits of a run (tests/fuzz/fuzz_scene.cpp)
# with libFuzzer for a given time.
#   bash scripts/fuzz.sh [SECONDS]        default 600; builds in $TRAVERSE_FUZZ_BUILD_DIR
#                                         (default build-fuzz/ in the repository) with clang, then runs
# Needs clang and libclang-rt-14-dev (Debian 12: apt-get install clang libclang-rt-14-dev).
# Extreme-value inputs are also run by a traverse executable: $TRAVERSE_FUZZ_EXE, default
# build/traverse of the repository (built in Release if missing; TRAVERSE_FUZZ_EXE= runs
# none). The fuzzer runs at low priority (nice) so that it can share a machine.
# New inputs found go to $TRAVERSE_FUZZ_BUILD_DIR/corpus (the checked-in seeds in
# tests/fuzz/corpus/scene are read, never written); crashes, leaks, hangs and broken run
# contracts are written as crash-*/leak-*/timeout-* files in $TRAVERSE_FUZZ_BUILD_DIR/artifacts/.
# Reproduce one: TRAVERSE_FUZZ_EXE=build/traverse $TRAVERSE_FUZZ_BUILD_DIR/tests/fuzz/fuzz_scene FILE
set -euo pipefail
seconds=${1:-600}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TRAVERSE_FUZZ_BUILD_DIR:-$here/build-fuzz}
jobs=${TRAVERSE_JOBS:-1}
if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DTRAVERSE_FUZZ=ON -DTRAVERSE_BUILD_BENCHMARKS=OFF
fi
nice cmake --build "$build" -j "$jobs" --target fuzz_scene
exe=${TRAVERSE_FUZZ_EXE-$here/build/traverse}
if [ -n "$exe" ] && [ ! -x "$exe" ] && [ "$exe" = "$here/build/traverse" ]; then
  [ -f "$here/build/CMakeCache.txt" ] || cmake -S "$here" -B "$here/build" -DCMAKE_BUILD_TYPE=Release
  nice cmake --build "$here/build" -j "$jobs" --target traverse
fi
export TRAVERSE_FUZZ_EXE=$exe
export OMPI_MCA_ess_singleton_isolated=1   # singleton MPI runs without starting a daemon (faster)
mkdir -p "$build/corpus" "$build/artifacts"
# -timeout: an input taking over 30 s is a hang (a run of the executable is killed after 15 s
# and reported by the target itself); -rss_limit_mb: memory blow-ups are findings.
# TRAVERSE_FUZZ_KEEP_GOING=1: fork mode, which records a finding and goes on fuzzing (the
# default stops at the first finding, as libFuzzer does).
keep_going=()
if [ "${TRAVERSE_FUZZ_KEEP_GOING:-0}" = 1 ]; then
  keep_going=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1)
fi
exec nice "$build/tests/fuzz/fuzz_scene" "$build/corpus" "$here/tests/fuzz/corpus/scene" \
  -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 -max_len=8192 \
  -artifact_prefix="$build/artifacts/" -print_final_stats=1 "${keep_going[@]}"
