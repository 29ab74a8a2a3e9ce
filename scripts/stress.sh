#!/usr/bin/env bash
# Full-size numerical stress suite (docs/reliability.md): the ctest label `stress` tests at
# full size (TRAVERSE_STRESS_FULL=1: rod long runs with N = 100 and 1e5 steps, the cable at
# ds = 0.01 m, ds = 1e-4 m, tight-tolerance comparison). Hours on one core.
#   bash scripts/stress.sh [BUILD_DIR]      default build/ (configured by scripts/setup.sh)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-${TRAVERSE_BUILD_DIR:-$here/build}}
cmake --build "$build" -j "${TRAVERSE_JOBS:-2}" --target traverse test_stress_long_runs test_stress_cli
export TRAVERSE_STRESS_FULL=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd "$build"
ctest -L stress --output-on-failure -V --timeout 86400
