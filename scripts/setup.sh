#!/usr/bin/env bash
# traverse set-up on Debian 12 (run as root, or with sudo available):
#   bash scripts/setup.sh demo   install what is missing, build (Release), run the default
#                                scene and draw its figure (out/default.h5, out/default.png)
#   bash scripts/setup.sh test   install what is missing, build, run the whole test suite
#   bash scripts/setup.sh build  install what is missing and build only
#   bash scripts/setup.sh sanitize  build with AddressSanitizer + UndefinedBehaviorSanitizer in
#                                build-asan/ (TRAVERSE_SANITIZE=ON, RelWithDebInfo made -O1 -g1)
#                                and run the whole test suite there (slow: docs/reliability.md)
# Packages: .ci/debian-packages.txt. Build tree: build/ (override with TRAVERSE_BUILD_DIR).
set -euo pipefail
mode=${1:-build}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${TRAVERSE_BUILD_DIR:-$here/build}
jobs=${TRAVERSE_JOBS:-$(nproc 2>/dev/null || echo 2)}

case "$mode" in demo|test|build|sanitize) ;; *) echo "usage: bash scripts/setup.sh demo|test|build|sanitize" >&2; exit 2 ;; esac

# 1. Debian packages: install only what is missing; refresh the package lists only then.
sudo_cmd=""
if [ "$(id -u)" -ne 0 ]; then sudo_cmd="sudo"; fi
# demo: the packages above the line "# -- the tests" (build, run, figure); the others: all.
if [ "$mode" = demo ]; then
  mapfile -t wanted < <(sed '/^# -- the tests/,$d' "$here/.ci/debian-packages.txt" | grep -vE '^\s*(#|$)')
else
  mapfile -t wanted < <(grep -vE '^\s*(#|$)' "$here/.ci/debian-packages.txt")
fi
missing=()
for p in "${wanted[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then missing+=("$p"); fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${#missing[@]} missing Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $sudo_cmd apt-get update -q
  $sudo_cmd apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# 2. Configure and build (Release; sanitize: ASan/UBSan, -O1 -g1 (cmake/TraverseWarnings.cmake), own tree).
if [ "$mode" = sanitize ]; then
  build=${TRAVERSE_ASAN_BUILD_DIR:-$here/build-asan}
  cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTRAVERSE_SANITIZE=ON -DTRAVERSE_BUILD_BENCHMARKS=OFF
elif [ "$mode" = demo ]; then  # the executable only
  cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DTRAVERSE_BUILD_TESTS=OFF -DTRAVERSE_BUILD_BENCHMARKS=OFF \
    -DTRAVERSE_BUILD_PYTHON=OFF
else  # everything (also after a demo configured the same tree without it)
  cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DTRAVERSE_BUILD_TESTS=ON -DTRAVERSE_BUILD_BENCHMARKS=ON \
    -DTRAVERSE_BUILD_PYTHON=ON
fi
# The demo needs only the executable; the tests need everything.
if [ "$mode" = demo ]; then
  cmake --build "$build" -j "$jobs" --target traverse
else
  cmake --build "$build" -j "$jobs"
fi

# 3. Run.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
case "$mode" in
  demo)
    mkdir -p "$here/out"
    "$build/traverse" run "$here/inputs/default.yaml" -o "$here/out/default.h5" --overwrite
    /usr/bin/python3 "$here/postprocessing/plot_default.py" "$here/out/default.h5" -o "$here/out/default.png"
    echo "setup: output in out/default.h5, figure in out/default.png"
    ;;
  test)
    cd "$build"
    # Retries a test needed (pvbatch's connection to its Xvfb) are noted here and shown below.
    rm -f Testing/test-notes.txt
    status=0
    ctest --output-on-failure -j "$jobs" || status=$?
    if [ -s Testing/test-notes.txt ]; then
      echo "setup: retries the tests needed:"
      cat Testing/test-notes.txt
    fi
    exit "$status"
    ;;
  sanitize)
    # Memory errors, undefined behaviour and leaks fail the test that hit them. Open MPI
    # unloads its components in MPI_Finalize, so with ASan's fast unwinder their allocations
    # kept until exit are leaks of "<unknown module>"; fast_unwind_on_malloc=0 records whole
    # stacks, which reach libmpi / libopen-rte and are suppressed by scripts/lsan.supp. That
    # makes the Trilinos-heavy tests several times slower (about 50 min instead of 10 here,
    # docs/reliability.md); ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 for the quick run.
    export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:fast_unwind_on_malloc=0:abort_on_error=1}
    export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$here/scripts/lsan.supp:print_suppressions=0}
    export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
    cd "$build"
    ctest --output-on-failure -j "$jobs" -LE benchmark
    ;;
  build) ;;
esac
