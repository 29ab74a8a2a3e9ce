#!/bin/bash
# Start-up and sweep figures of issue 16 (docs/benchmarks.md, "Start-up and sweeps"): the
# median wall and CPU time (user + system, children included) of
#   traverse --version, traverse check inputs/default.yaml, the cable run (inputs/default.yaml)
#   at ds = 0.04, 0.02 and the scene's 0.01 (26, 51, 101 nodes; output every step)
# for each executable given (e.g. the build of main and this one), then the F = 2 N resonance
# sweep (20 speeds, postprocessing/hanging_cable.py's) on 1 and 2 ranks with the last one.
# Usage: bash scripts/bench-startup.sh [-n RUNS] [--no-sweep] EXE [EXE ...]
set -euo pipefail
cd "$(dirname "$0")/.."
runs=9
sweep=1
exes=()
while [ $# -gt 0 ]; do
  case "$1" in
    -n) runs="$2"; shift 2 ;;
    --no-sweep) sweep=0; shift ;;
    *) exes+=("$1"); shift ;;
  esac
done
[ ${#exes[@]} -gt 0 ] || { echo "usage: bash scripts/bench-startup.sh [-n RUNS] [--no-sweep] EXE [EXE ...]" >&2; exit 2; }
py=/usr/bin/python3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# median wall and CPU (user + system of the process and its children) of RUNS runs of the
# command, each timed to the microsecond (time.perf_counter, getrusage of the children)
measure() {
  $py - "$runs" "$@" <<'PY'
import resource, statistics, subprocess, sys, time
runs, cmd = int(sys.argv[1]), sys.argv[2:]
wall, cpu = [], []
for _ in range(runs):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall.append(time.perf_counter() - t0)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu.append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
print("%.4f %.4f" % (statistics.median(wall), statistics.median(cpu)))
PY
}

# The cable runs simulate the scene's whole crossing, t = 0 .. 0.275165 s.
echo "| executable | command | wall [s] | CPU [s] | simulated / wall |"
echo "|---|---|---|---|---|"
for exe in "${exes[@]}"; do
  for cmd in "--version" "check inputs/default.yaml" \
             "run inputs/default.yaml --set mesh.ds=0.04 -o $work/cable.h5 --overwrite -q" \
             "run inputs/default.yaml --set mesh.ds=0.02 -o $work/cable.h5 --overwrite -q" \
             "run inputs/default.yaml -o $work/cable.h5 --overwrite -q"; do
    # shellcheck disable=SC2086
    read -r wall cpu < <(measure "$exe" $cmd)
    ratio=""
    [ "${cmd%% *}" = run ] && ratio=$($py -c "print('%.2f' % (0.275165 / $wall))")
    echo "| $exe | traverse ${cmd%% -o *} | $wall | $cpu | $ratio |"
  done
done

[ "$sweep" = 1 ] || exit 0
exe="${exes[-1]}"
speeds=$($py -c 'V1 = 7.268366068467048; print(",".join(repr(round(0.1 * k, 2) * V1) for k in range(1, 21)))')
ends=$($py -c 'V1 = 7.268366068467048; T1 = 2 / V1
print(",".join(repr(1 / (round(0.1 * k, 2) * V1) + 2 * T1) for k in range(1, 21)))')
args=(sweep inputs/rod/hanging_cable_F2_a0.5.yaml --vary "loads.F.speed=$speeds" --with "time.end=$ends"
      --set "output.fields=[]" --overwrite -q)
for ranks in 1 2; do
  launch=()
  # --bind-to none: Open MPI binds 2 ranks to one core each by default, which on a machine
  # shared with other work pins a rank to a busy core; one process alone is never bound.
  [ "$ranks" = 1 ] || launch=(mpirun --allow-run-as-root --oversubscribe --bind-to none -n "$ranks")
  read -r wall cpu < <(runs=3 measure "${launch[@]}" "$exe" "${args[@]}" -o "$work/sweep$ranks")
  echo "resonance sweep (F = 2 N, 20 speeds) on $ranks rank(s): wall $wall s, CPU $cpu s"
  eval "wall$ranks=$wall"
done
$py -c "print('resonance sweep: 2 ranks %.2fx faster than 1 (wall)' % ($wall1 / $wall2))"
