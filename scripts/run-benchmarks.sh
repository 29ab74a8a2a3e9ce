#!/usr/bin/env bash
# Build and run the rod benchmarks (and the beam one), then regenerate the tables of
# docs/benchmarks.md and the figures docs/figures/bench_*.png from the CSV files.
#
#   bash scripts/run-benchmarks.sh [--quick] [--million] [--report-only]
#
#   --quick        smaller sweep (N <= 10^4, no 20 N / 2-rank accuracy runs, arches down to
#                  ds = 0.005 only): a few minutes
#   --million      also N = 10^6 nodes with the default solver on 1 and 2 ranks (about 15 GB of
#                  memory; about 6 minutes per run, most of it the static initial state)
#   --report-only  only regenerate docs/benchmarks.md and the figures from existing CSV
# Environment: BUILD (default build/), OUT (default $BUILD/bench), JOBS (make -j, default 1).
# Benchmarks are never ctest tests; every number is a wall time or a ratio measured within
# one run, so the machine's load matters: rerun on a quiet machine for stable numbers.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-$ROOT/build}
OUT=${OUT:-$BUILD/bench}
JOBS=${JOBS:-1}
QUICK=0
MILLION=0
REPORT_ONLY=0
for a in "$@"; do
  case "$a" in
    --quick) QUICK=1 ;;
    --million) MILLION=1 ;;
    --report-only) REPORT_ONLY=1 ;;
    *) echo "usage: $0 [--quick] [--million] [--report-only]" >&2; exit 2 ;;
  esac
done

MPIRUN=(mpirun -n 2)
if [ "$(id -u)" = 0 ]; then MPIRUN=(mpirun --allow-run-as-root --oversubscribe -n 2); fi

if [ "$REPORT_ONLY" = 0 ]; then
  if [ ! -f "$BUILD/CMakeCache.txt" ]; then
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DTRAVERSE_BUILD_BENCHMARKS=ON
  else
    cmake -S "$ROOT" -B "$BUILD" -DTRAVERSE_BUILD_BENCHMARKS=ON > /dev/null
  fi
  make -C "$BUILD" -j"$JOBS" bench_rod bench_beam traverse
  BR="$BUILD/tests/benchmarks/rod/bench_rod"
  BB="$BUILD/tests/benchmarks/beam/bench_beam"
  mkdir -p "$OUT"
  rm -f "$OUT"/accuracy.csv "$OUT"/cost.csv "$OUT"/arches.csv "$OUT"/planar.csv "$OUT"/*.txt

  echo "== beam: run time against error" | tee "$OUT/beam.txt"
  "$BB" | tee -a "$OUT/beam.txt"

  echo "== rod: cost per step and per Newton iteration against the block-tridiagonal LU floor"
  SIZES=(101 316 1001 3163 10001)
  BIG=()
  if [ "$QUICK" = 0 ]; then BIG=(31624 100001); fi
  "$BR" cost-header | tee "$OUT/cost.txt"
  for n in "${SIZES[@]}" "${BIG[@]}"; do
    for s in auto auto:modified KLU2 KLU2:modified; do
      "$BR" cost --nodes "$n" --solver "$s" --label scaling --csv "$OUT/cost.csv" | tee -a "$OUT/cost.txt"
    done
  done
  for n in "${SIZES[@]}"; do
    for s in KLU2:stratimikos-klu2 GMRES+SCHWARZ GMRES+ILUT; do
      "$BR" cost --nodes "$n" --solver "$s" --label solvers --csv "$OUT/cost.csv" | tee -a "$OUT/cost.txt"
    done
  done
  echo "== rod: strong scaling, 1 and 2 ranks"
  STRONG=(10001)
  if [ "$QUICK" = 0 ]; then STRONG=(10001 100001); fi
  for n in "${STRONG[@]}"; do
    for s in auto auto:modified GMRES+BLOCK_TRIDIAGONAL GMRES+SCHWARZ; do
      "$BR" cost --nodes "$n" --solver "$s" --label strong --csv "$OUT/cost.csv" | tee -a "$OUT/cost.txt"
      "${MPIRUN[@]}" "$BR" cost --nodes "$n" --solver "$s" --label strong --csv "$OUT/cost.csv" | tee -a "$OUT/cost.txt"
    done
  done
  if [ "$MILLION" = 1 ]; then
    "$BR" cost --nodes 1000001 --solver auto --steps 3 --label strong --csv "$OUT/cost.csv" | tee -a "$OUT/cost.txt"
    "${MPIRUN[@]}" "$BR" cost --nodes 1000001 --solver auto --steps 3 --label strong --csv "$OUT/cost.csv" | tee -a "$OUT/cost.txt"
  fi
  echo "== rod: planar path against the 3D path (hanging cable, both stepped alternately in one process)"
  for n in 101 1001; do
    for s in auto KLU2; do
      "$BR" planar --nodes "$n" --solver "$s" --label planar --csv "$OUT/planar.csv" | tee -a "$OUT/planar.txt"
    done
  done
  "${MPIRUN[@]}" "$BR" planar --nodes 1001 --solver auto --label planar --csv "$OUT/planar.csv" | tee -a "$OUT/planar.txt"
  echo "== rod: run time against error (hanging cable)"
  "$BR" accuracy --force 2 --csv "$OUT/accuracy.csv" | tee "$OUT/accuracy_F2_np1.txt"
  if [ "$QUICK" = 0 ]; then
    "$BR" accuracy --force 2 --solvers KLU2:modified --csv "$OUT/accuracy.csv" | tee "$OUT/accuracy_F2_np1_modified.txt"
    "$BR" accuracy --force 20 --solvers KLU2,GMRES+SCHWARZ --csv "$OUT/accuracy.csv" | tee "$OUT/accuracy_F20_np1.txt"
    "${MPIRUN[@]}" "$BR" accuracy --force 2 --csv "$OUT/accuracy.csv" | tee "$OUT/accuracy_F2_np2.txt"
  fi
  echo "== arches: run time against error (shallow arch 5 m/s, deep arch 0.05 m/s; planar and 3D; two solvers)"
  QA=()
  if [ "$QUICK" = 1 ]; then QA=(--quick); fi
  /usr/bin/python3 "$ROOT/tests/benchmarks/arches/bench_arches.py" "$BUILD/traverse" "${QA[@]}" \
    --csv "$OUT/arches.csv" | tee "$OUT/arches.txt"

fi

echo "== report: docs/benchmarks.md tables and docs/figures/bench_*.png"
/usr/bin/python3 - "$OUT" "$ROOT" <<'PY'
import csv, math, os, re, sys
out, root = sys.argv[1], sys.argv[2]
def rows(name):
    p = os.path.join(out, name)
    return list(csv.DictReader(open(p))) if os.path.exists(p) else []
acc, cost, arches, planar = rows("accuracy.csv"), rows("cost.csv"), rows("arches.csv"), rows("planar.csv")
f = lambda x, d=3: f"{float(x):.{d}g}"
md = []
if acc:
    md.append("### Run time against error (hanging cable, midspan height)\n")
    md.append("Error: max over the ds = 0.04 grid times of |h(t) - h_ref(t)|, h_ref from the ds = "
              f"{float(acc[0]['reference_ds']):g} run (same ranks, first solver of the run). Run time: the time "
              "steps only (static state and set-up excluded).\n")
    md.append("| F [N] | ranks | solver | ds | steps | run [s] | Newton its | lin. its / Newton | max abs(dh) [m] |")
    md.append("|---|---|---|---|---|---|---|---|---|")
    for r in acc:
        n = int(r["newton"])
        md.append(f"| {f(r['force'])} | {r['ranks']} | {r['solver']} | {float(r['ds']):g} | {r['steps']} | "
                  f"{float(r['run_seconds']):.3g} | {n} | {int(r['linear'])/max(n,1):.1f} | {float(r['error']):.2e} |")
    md.append("")
if arches:
    md.append("### Run time against error (hinged arches)\n")
    md.append("`tests/benchmarks/arches/bench_arches.py`: the shipped scenes at ds = 0.04 .. (dt = ds / v); "
              "error: max over the coarsest run's output times of |q(t) - q_ref(t)|, q_ref from the ds = "
              f"{float(arches[0]['reference_ds']):g} run of the same variant. Run time: the executable's time "
              "stepping (probes only, no restart points between steps).\n")
    md.append("| case | quantity | solver | path | ranks | ds | steps | run [s] | Newton its | max abs(dq) [m] | observed order |")
    md.append("|---|---|---|---|---|---|---|---|---|---|---|")
    prev = {}
    for r in arches:
        key = (r["case"], r["quantity"], r["solver"], r["path"], r["ranks"])
        e = float(r["error"])
        order = f"{math.log2(prev[key] / e):.2f}" if key in prev and e > 0 else ""
        prev[key] = e
        md.append(f"| {r['case']} | {r['quantity']} | {r['solver']} | {r['path']} | {r['ranks']} | {float(r['ds']):g} | "
                  f"{r['steps']} | {float(r['run_seconds']):.3g} | {r['newton']} | {e:.2e} | {order} |")
    md.append("")
if planar:
    md.append("### Planar path against the 3D path (hanging cable, F = 2 N)\n")
    md.append("`bench_rod planar`: the same scene stepped on both paths, one time step of each in turn, "
              "so both see the same machine load; speed-up = 3D time / planar time over the whole run "
              "(and of the median time per Newton iteration).\n")
    md.append("| solver | ranks | nodes | steps | Newton its | 3D run [s] | planar run [s] | speed-up | speed-up, median | "
              "assembly / Newton 3D, planar [s] | lin. set-up / Newton 3D, planar [s] |")
    md.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for key in dict.fromkeys((r["solver"], r["ranks"], r["nodes"]) for r in planar):
        sel = [r for r in planar if (r["solver"], r["ranks"], r["nodes"]) == key]
        d3 = [r for r in sel if r["path"] == "3D"]; d2 = [r for r in sel if r["path"] == "planar"]
        if not d3 or not d2: continue
        a, b = d3[-1], d2[-1]
        md.append(f"| {key[0]} | {key[1]} | {key[2]} | {a['steps']} | {a['newton']} | {float(a['run_seconds']):.3g} | "
                  f"{float(b['run_seconds']):.3g} | {float(a['run_seconds'])/float(b['run_seconds']):.2f} | "
                  f"{float(a['median_newton_seconds'])/float(b['median_newton_seconds']):.2f} | "
                  f"{float(a['assembly_seconds_per_newton']):.3g}, {float(b['assembly_seconds_per_newton']):.3g} | "
                  f"{float(a['linear_setup_seconds_per_newton']):.3g}, {float(b['linear_setup_seconds_per_newton']):.3g} |")
    md.append("")
def fit(points):  # least-squares slope of log(cost) against log(N)
    if len(points) < 2: return float("nan")
    xs = [math.log(p[0]) for p in points]; ys = [math.log(p[1]) for p in points]
    mx, my = sum(xs)/len(xs), sum(ys)/len(ys)
    return sum((x-mx)*(y-my) for x, y in zip(xs, ys)) / sum((x-mx)**2 for x in xs)
if cost:
    md.append("### Cost per step and per Newton iteration against the floor\n")
    md.append("floor = one block-tridiagonal LU (12x12 dense Eigen blocks, N blocks: factorise + solve) "
              "measured in the same process; ratio = (time per Newton iteration) / floor.\n")
    md.append("| label | solver | ranks | nodes | s / step | Newton / step | s / Newton | floor [s] | ratio | "
              "assembly / Newton [s] | lin. set-up / Newton [s] | lin. its / Newton | maxrss kB / node |")
    md.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in cost:
        md.append(f"| {r['label']} | {r['solver']} | {r['ranks']} | {r['nodes']} | {float(r['step_seconds']):.3g} | "
                  f"{float(r['newton_per_step']):.2f} | {float(r['newton_seconds']):.3g} | {float(r['floor_seconds']):.3g} | "
                  f"{float(r['ratio']):.2f} | {float(r['assembly_seconds_per_newton']):.3g} | "
                  f"{float(r['linear_setup_seconds_per_newton']):.3g} | {float(r['linear_per_newton']):.1f} | "
                  f"{float(r['kb_per_node']):.1f} |")
    md.append("")
    md.append("Growth exponents (least-squares slope of log cost against log N; every 1-rank run of the solver, "
              "labels scaling and strong):\n")
    md.append("| solver | range of N | exponent, s / step | exponent, s / Newton iteration | exponent, floor |")
    md.append("|---|---|---|---|---|")
    for s in sorted({r["solver"] for r in cost if r["label"] == "scaling"}):
        pts = sorted([r for r in cost if r["label"] in ("scaling", "strong") and r["solver"] == s and r["ranks"] == "1"],
                     key=lambda r: int(r["nodes"]))
        big = [r for r in pts if int(r["nodes"]) >= 1000]
        for sel, rng in ((pts, "all"), (big, ">= 10^3")):
            if len(sel) < 2: continue
            e = fit([(int(r["nodes"]), float(r["step_seconds"])) for r in sel])
            en = fit([(int(r["nodes"]), float(r["newton_seconds"])) for r in sel])
            ef = fit([(int(r["nodes"]), float(r["floor_seconds"])) for r in sel])
            md.append(f"| {s} | {rng} ({sel[0]['nodes']} .. {sel[-1]['nodes']}) | {e:.3f} | {en:.3f} | {ef:.3f} |")
    md.append("")
    st = [r for r in cost if r["label"] == "strong"]
    if st:
        md.append("Strong scaling (same solver on 1 and 2 ranks; speed-up = 1-rank s/step over 2-rank s/step):\n")
        md.append("| solver | nodes | s / step, 1 rank | s / step, 2 ranks | speed-up | lin. its / Newton (1, 2) |")
        md.append("|---|---|---|---|---|---|")
        for s in sorted({r["solver"] for r in st}):
            for n in sorted({int(r["nodes"]) for r in st}):
                one = [r for r in st if r["solver"] == s and int(r["nodes"]) == n and r["ranks"] == "1"]
                two = [r for r in st if r["solver"] == s and int(r["nodes"]) == n and r["ranks"] == "2"]
                if one and two:
                    a, b = float(one[-1]["step_seconds"]), float(two[-1]["step_seconds"])
                    md.append(f"| {s} | {n} | {a:.3g} | {b:.3g} | {a/b:.2f} | "
                              f"{float(one[-1]['linear_per_newton']):.1f}, {float(two[-1]['linear_per_newton']):.1f} |")
        md.append("")
text = "\n".join(md)
doc = os.path.join(root, "docs", "benchmarks.md")
begin, end = "<!-- BEGIN GENERATED TABLES -->", "<!-- END GENERATED TABLES -->"
if os.path.exists(doc):
    d = open(doc).read()
    if begin in d and end in d:
        d = d[:d.index(begin) + len(begin)] + "\n" + text + "\n" + d[d.index(end):]
    else:
        d += "\n" + begin + "\n" + text + "\n" + end + "\n"
else:
    d = "# Benchmarks\n\n" + begin + "\n" + text + "\n" + end + "\n"
open(doc, "w").write(d)
print(f"wrote the tables into {doc}")
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib missing: no figures (apt-get install python3-matplotlib)"); sys.exit(0)
figs = os.path.join(root, "docs", "figures"); os.makedirs(figs, exist_ok=True)
if acc:
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, F in zip(axes, sorted({float(r["force"]) for r in acc})):
        for key in sorted({(r["ranks"], r["solver"]) for r in acc if float(r["force"]) == F}):
            sel = [r for r in acc if float(r["force"]) == F and (r["ranks"], r["solver"]) == key]
            ax.loglog([float(r["run_seconds"]) for r in sel], [float(r["error"]) for r in sel], "o-",
                      label=f"{key[1]}, {key[0]} rank(s)")
        ax.set_xlabel("run time [s]"); ax.set_ylabel("max |h - h_ref| [m]"); ax.set_title(f"hanging cable, F = {F:g} N")
        ax.grid(True, which="both", alpha=0.3); ax.legend(fontsize=7)
    fig.tight_layout(); fig.savefig(os.path.join(figs, "bench_rod_accuracy.png"), dpi=110); plt.close(fig)
if cost:
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    sc = [r for r in cost if r["ranks"] == "1" and r["label"] in ("scaling", "solvers")]
    for s in sorted({r["solver"] for r in sc}):
        sel = sorted([r for r in sc if r["solver"] == s], key=lambda r: int(r["nodes"]))
        axes[0].loglog([int(r["nodes"]) for r in sel], [float(r["step_seconds"]) for r in sel], "o-", label=s)
        axes[1].semilogx([int(r["nodes"]) for r in sel], [float(r["ratio"]) for r in sel], "o-", label=s)
    # One floor per N (the median of the runs' floors: each run measures its own).
    by_n = {}
    for r in sc: by_n.setdefault(int(r["nodes"]), []).append(float(r["floor_seconds"]))
    fl = [(n, sorted(v)[len(v) // 2]) for n, v in sorted(by_n.items())]
    axes[0].loglog([n for n, _ in fl], [t for _, t in fl], "k--", label="floor (block-tridiagonal LU, median of the runs)")
    axes[0].set_xlabel("nodes N"); axes[0].set_ylabel("s / step"); axes[0].legend(fontsize=7); axes[0].grid(True, which="both", alpha=0.3)
    axes[1].axhline(3.0, color="k", ls=":", label="target 3")
    axes[1].set_xlabel("nodes N"); axes[1].set_ylabel("(s / Newton iteration) / floor"); axes[1].legend(fontsize=7)
    axes[1].grid(True, which="both", alpha=0.3)
    fig.tight_layout(); fig.savefig(os.path.join(figs, "bench_rod_cost.png"), dpi=110); plt.close(fig)
print("figures in docs/figures/bench_rod_*.png")
PY
