#!/bin/bash
# Whole-process figures (docs/benchmarks.md, "Whole runs"): the median wall and CPU time
# (user + system, children included) of
#   traverse --version, traverse check inputs/default.yaml, the cable run (inputs/default.yaml)
#   at ds = 0.04, 0.02 and the scene's 0.01 (26, 51, 101 nodes; output every step), the
#   shallow arch at v = 2 m/s (inputs/arch/shallow_arch_v2.0.yaml: the arch's formation and
#   0.5 s of snap-through)
# for each executable given (e.g. the build of main and this one; the executables take turns,
# run by run, so that their medians see the same load), then the F = 2 N resonance
# sweep (20 speeds, postprocessing/hanging_cable.py's) with the last one: in one process and on
# 1 and on 2 MPI ranks (mpirun -n 1, -n 2), in turn.
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

# median wall and CPU (user + system of the process and its children) of RUNS runs of each
# command given (one per argument, words split on spaces), the commands run in turn (run k of
# every command, then run k + 1 ...), so that all see the same machine load; each timed to the
# microsecond (time.perf_counter, getrusage of the children). One line per command: wall, CPU
# and, for a sweep, the median of the wall time the sweep reports for itself ("sweep done: ...
# in S s": from the sweep's start to its index written, without the process's start-up, MPI's
# and the launcher's), else "-".
measure() {
  $py - "$runs" "$@" <<'PY'
import re, resource, statistics, subprocess, sys, time
runs, cmds = int(sys.argv[1]), [c.split() for c in sys.argv[2:]]
wall, cpu, own = [[] for _ in cmds], [[] for _ in cmds], [[] for _ in cmds]
for _ in range(runs):
    for i, cmd in enumerate(cmds):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        wall[i].append(time.perf_counter() - t0)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu[i].append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
        m = re.search(r"^sweep done: .* in ([0-9.]+) s ->", p.stdout, re.M)
        if m: own[i].append(float(m.group(1)))
for w, c, o in zip(wall, cpu, own):
    print("%.4f %.4f %s" % (statistics.median(w), statistics.median(c), "%.4f" % statistics.median(o) if o else "-"))
PY
}

# The cable runs simulate the scene's whole crossing, t = 0 .. 0.275165 s; the shallow arch at
# v = 2 m/s (its formation included) t = 0 .. 0.5 s. Each command runs with every executable in
# turn (the executables' medians are from the same minutes). A command is "simulated time|args".
echo "| executable | command | wall [s] | CPU [s] | simulated / wall |"
echo "|---|---|---|---|---|"
for entry in "|--version" "|check inputs/default.yaml" \
             "0.275165|run inputs/default.yaml --set mesh.ds=0.04 -o $work/cable.h5 --overwrite -q" \
             "0.275165|run inputs/default.yaml --set mesh.ds=0.02 -o $work/cable.h5 --overwrite -q" \
             "0.275165|run inputs/default.yaml -o $work/cable.h5 --overwrite -q" \
             "0.5|run inputs/arch/shallow_arch_v2.0.yaml -o $work/arch.h5 --overwrite -q"; do
  simulated="${entry%%|*}"
  cmd="${entry#*|}"
  cmds=()
  for exe in "${exes[@]}"; do cmds+=("$exe $cmd"); done
  mapfile -t results < <(measure "${cmds[@]}")
  for k in "${!exes[@]}"; do
    read -r wall cpu _ <<< "${results[$k]}"
    ratio=""
    [ -n "$simulated" ] && ratio=$($py -c "print('%.2f' % ($simulated / $wall))")
    echo "| ${exes[$k]} | traverse ${cmd%% -o *} | $wall | $cpu | $ratio |"
  done
done

[ "$sweep" = 1 ] || exit 0
exe="${exes[-1]}"
speeds=$($py -c 'V1 = 7.268366068467048; print(",".join(repr(round(0.1 * k, 2) * V1) for k in range(1, 21)))')
ends=$($py -c 'V1 = 7.268366068467048; T1 = 2 / V1
print(",".join(repr(1 / (round(0.1 * k, 2) * V1) + 2 * T1) for k in range(1, 21)))')
# Not -q: the sweep's closing line gives its own wall time.
args=(sweep inputs/rod/hanging_cable_F2_a0.5.yaml --vary "loads.F.speed=$speeds" --with "time.end=$ends"
      --set "output.fields=[]" --overwrite)
# --bind-to none: Open MPI binds 2 ranks to one core each by default, which on a machine
# shared with other work pins a rank to a busy core; one process alone is never bound.
# The three sweeps run in turn, 5 times each.
mpirun="mpirun --allow-run-as-root --oversubscribe --bind-to none"
mapfile -t results < <(runs=5 measure "$exe ${args[*]} -o $work/sweep1" \
  "$mpirun -n 2 $exe ${args[*]} -o $work/sweep2" "$mpirun -n 1 $exe ${args[*]} -o $work/sweep3")
k=0
for how in "one process" "2 MPI ranks (mpirun -n 2)" "1 MPI rank (mpirun -n 1)"; do
  read -r wall cpu own <<< "${results[$k]}"
  echo "resonance sweep (F = 2 N, 20 speeds) in $how: wall $wall s, CPU $cpu s; the sweep's own wall $own s"
  eval "wall$k=$wall own$k=$own"
  k=$((k + 1))
done
$py -c "print('resonance sweep, wall: mpirun -n 2 %.2fx faster than one process, %.2fx faster than mpirun -n 1' % ($wall0 / $wall1, $wall2 / $wall1))"
$py -c "print('resonance sweep, its own wall (start-up, MPI and launcher excluded): mpirun -n 2 %.2fx faster than one process, %.2fx faster than mpirun -n 1' % ($own0 / $own1, $own2 / $own1))"
