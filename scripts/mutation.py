#!/usr/bin/env python3
"""Mutation check: does the test suite bite? Applies a handful of small, plausible faults, one
at a time, to a copy of the sources, rebuilds only what the fault's tests need (a build
directory of its own; ccache is used when it is installed) and runs those tests. Every fault
must make at least one of them fail. docs/reliability.md ("Mutation check") lists the faults
and the tests that caught them.

  python3 scripts/mutation.py [--work DIR] [--jobs N] [--only NAME ...]

DIR (default: build-mutation beside the sources) holds the copy (DIR/src) and its build
(DIR/build); the copy is refreshed from the work tree (the tracked files, as they are now) at
every start. The unmutated copy is built and its tests run first: they must pass. Exit 0
when every fault was caught, 1 otherwise; the table of faults and failing tests is printed.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys

# name, file, the text replaced (exactly once), its replacement, the targets to build, the
# ctest selection (a regex of test names), what the fault is.
FAULTS = [
    ("coriolis-sign", "src/beam/beam_simulation.cpp",
     "f -= inertia_[ks] * (2.0 * v * d1v + v * v * d2 + a * d1);",
     "f -= inertia_[ks] * (-2.0 * v * d1v + v * v * d2 + a * d1);",
     ["test_beam_dynamics", "test_coupled_mass_beam"], "^test_beam_dynamics$|^test_coupled_mass_beam$",
     "beam, moving mass: the sign of the Coriolis term 2 M v w_x,t"),
    ("centrifugal-dropped", "src/beam/beam_simulation.cpp",
     "f -= inertia_[ks] * (2.0 * v * d1v + v * v * d2 + a * d1);",
     "f -= inertia_[ks] * (2.0 * v * d1v + a * d1);",
     ["test_beam_dynamics", "test_coupled_mass_beam"], "^test_beam_dynamics$|^test_coupled_mass_beam$",
     "beam, moving mass: the centrifugal term M v^2 w_xx dropped"),
    ("output-every-off-by-one", "src/app/run_beam.cpp",
     "p.output_every = checked.output_every;",
     "p.output_every = checked.output_every + 1;",
     ["traverse", "test_cli"], "^test_cli$",
     "beam runs: output.every off by one (every k + 1 steps)"),
    ("override-order", "src/scene/schema.cpp",
     "for (const auto& o : overrides) {",
     "for (auto it = overrides.rbegin(); it != overrides.rend(); ++it) {\n    const auto& o = *it;",
     ["traverse", "test_cli", "test_scene"], "^test_cli$|^test_scene$",
     "--set: the first of two overrides of a key wins instead of the last (a later --set ignored)"),
    ("sliding-end-row", "src/rod/end_condition.cpp",
     "slide_rows(c.axis, 0.0, 5, v.u, v.n, R, G, r, J);",
     "slide_rows(c.axis, 0.0, 4, v.u, v.n, R, G, r, J);",
     ["test_rod_dynamics", "test_roller_end", "test_cable_vs_beam"],
     "^test_rod_dynamics$|^test_roller_end$|^test_cable_vs_beam$",
     "rod, sliding end: the axial-force condition written into the wrong row (4, a moment row, for 5)"),
]


def run(cmd, cwd=None, log=None):
    """Runs cmd; returns (exit code, output)."""
    p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=ENV)
    if log:
        with open(log, "a") as fh:
            fh.write("$ " + " ".join(cmd) + "\n" + p.stdout + "\n")
    return p.returncode, p.stdout


def copy_sources(repo, dest):
    """The tracked files of the work tree, as they are now, into dest; only the files that
    differ are copied (the others keep their time stamps and are not rebuilt)."""
    files = subprocess.run(["git", "-C", repo, "ls-files", "-z"], stdout=subprocess.PIPE, check=True).stdout
    for rel in filter(None, files.decode().split("\0")):
        src, dst = os.path.join(repo, rel), os.path.join(dest, rel)
        if not os.path.isfile(src):
            continue
        if os.path.exists(dst):
            with open(src, "rb") as a, open(dst, "rb") as b:
                if a.read() == b.read():
                    continue
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        shutil.copyfile(src, dst)  # a new time stamp: make rebuilds what depends on it
        shutil.copymode(src, dst)


def failed_tests(output):
    """The names ctest lists as failed, each with the GoogleTest cases that failed in it."""
    tail = output.split("The following tests FAILED:", 1)
    if len(tail) < 2:
        return []
    cases = sorted(set(re.findall(r"^\S*\[  FAILED  \]\S* (\w+\.\w+)", output, re.M)))
    names = re.findall(r"^\s*\d+ - (\S+)", tail[1], re.M)
    return names + ([f"({', '.join(cases)})"] if cases else [])


def check_fault(fault, src, build, jobs, log):
    """Applies one fault, builds, runs its tests, reverts. Returns (caught, what failed)."""
    name, rel, old, new, targets, tests, _ = fault
    path = os.path.join(src, rel)
    with open(path) as fh:
        text = fh.read()
    if text.count(old) != 1:
        return False, f"the text to mutate occurs {text.count(old)} times in {rel} (the sources changed?)"
    try:
        with open(path, "w") as fh:
            fh.write(text.replace(old, new))
        rc, out = run(["cmake", "--build", build, "-j", str(jobs), "--target"] + targets, log=log)
        if rc != 0:
            return False, "the mutant does not build (an invalid fault): see the log"
        rc, out = run(["ctest", "--output-on-failure", "-R", tests], cwd=build, log=log)
        failed = failed_tests(out)
        return rc != 0, ", ".join(failed) if failed else ("(ctest exit %d)" % rc if rc else "nothing failed")
    finally:
        with open(path, "w") as fh:
            fh.write(text)


ENV = dict(os.environ)


def main():
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--work", default=os.path.join(repo, "build-mutation"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", nargs="*", help="names of the faults to apply (default: all)")
    a = ap.parse_args()
    faults = [f for f in FAULTS if not a.only or f[0] in a.only]
    src, build = os.path.join(a.work, "src"), os.path.join(a.work, "build")
    # ccache: paths below the work folder hashed relative to it, so that later runs hit.
    ENV.update(CCACHE_BASEDIR=os.path.abspath(a.work), CCACHE_NOHASHDIR="1")
    log = os.path.join(a.work, "mutation.log")
    os.makedirs(src, exist_ok=True)
    open(log, "w").close()
    copy_sources(repo, src)
    cfg = ["cmake", "-S", src, "-B", build, "-DCMAKE_BUILD_TYPE=Release"]
    if shutil.which("ccache"):
        cfg += ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache", "-DCMAKE_C_COMPILER_LAUNCHER=ccache"]
    if run(cfg, log=log)[0] != 0:
        sys.exit(f"mutation: configuring {build} failed (see {log})")
    targets = sorted({t for f in faults for t in f[4]})
    selection = "|".join(f[5] for f in faults)
    print(f"mutation: building the unmutated copy ({', '.join(targets)}) in {build}", flush=True)
    if run(["cmake", "--build", build, "-j", str(a.jobs), "--target"] + targets, log=log)[0] != 0:
        sys.exit(f"mutation: the unmutated copy does not build (see {log})")
    rc, out = run(["ctest", "--output-on-failure", "-R", selection], cwd=build, log=log)
    if rc != 0:
        sys.exit(f"mutation: the tests fail without a fault ({', '.join(failed_tests(out))}); see {log}")
    rows = []
    for f in faults:
        print(f"mutation: {f[0]}: {f[6]}", flush=True)
        caught, what = check_fault(f, src, build, a.jobs, log)
        rows.append((f[0], caught, what))
        print(f"  {'caught by' if caught else 'NOT CAUGHT:'} {what}", flush=True)
    print("\n| fault | caught | failing tests |\n| --- | --- | --- |")
    for name, caught, what in rows:
        print(f"| {name} | {'yes' if caught else 'NO'} | {what} |")
    # Rebuild the unmutated targets so that the build directory matches the sources again.
    run(["cmake", "--build", build, "-j", str(a.jobs), "--target"] + targets, log=log)
    sys.exit(0 if all(c for _, c, _ in rows) else 1)


if __name__ == "__main__":
    main()
