#!/usr/bin/env bash
# Fuzz the scene reader + validator (tests/fuzz/fuzz_scene.cpp) with libFuzzer for a given time.
#   bash scripts/fuzz.sh [SECONDS]        default 600; builds in $TRAVERSE_FUZZ_BUILD_DIR
#                                         (default build-fuzz/ in the repository) with clang, then runs
# Needs clang and libclang-rt-14-dev (Debian 12: apt-get install clang libclang-rt-14-dev).
# New inputs found go to $TRAVERSE_FUZZ_BUILD_DIR/corpus (the checked-in seeds in
# tests/fuzz/corpus/scene are read, never written); crashes, leaks and hangs are written
# as crash-*/leak-*/timeout-* files in $TRAVERSE_FUZZ_BUILD_DIR/artifacts/.
# Reproduce one: $TRAVERSE_FUZZ_BUILD_DIR/tests/fuzz/fuzz_scene FILE
set -euo pipefail
seconds=${1:-600}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TRAVERSE_FUZZ_BUILD_DIR:-$here/build-fuzz}
jobs=${TRAVERSE_JOBS:-1}
if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DTRAVERSE_FUZZ=ON -DTRAVERSE_BUILD_BENCHMARKS=OFF
fi
cmake --build "$build" -j "$jobs" --target fuzz_scene
mkdir -p "$build/corpus" "$build/artifacts"
# -timeout: an input taking over 5 s is a hang; -rss_limit_mb: memory blow-ups are findings.
exec "$build/tests/fuzz/fuzz_scene" "$build/corpus" "$here/tests/fuzz/corpus/scene" \
  -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 -max_len=8192 \
  -artifact_prefix="$build/artifacts/" -print_final_stats=1
