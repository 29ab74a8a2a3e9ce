"""What the validation scripts that drive the executable share: a check counter that prints
each check, a run of the executable that stops the script when it fails, and the scripts'
command line `EXE SCRATCH PART`."""

import os
import subprocess
import sys
import time


class Checks:
    """check(ok, text): prints the check and counts the failures."""

    def __init__(self):
        self.failed = 0

    def __call__(self, ok, text):
        print(("  ok    " if ok else "  FAIL  ") + text, flush=True)
        if not ok:
            self.failed += 1


def run(exe, scratch, scene, name, sets, who):
    """Runs `exe run SCENE -o SCRATCH/NAME.h5 --set ...`; returns the output path. A failed run
    stops the script `who` with its output printed."""
    out = os.path.join(scratch, name + ".h5")
    cmd = [exe, "run", scene, "-o", out, "--overwrite", "-q"]
    for s in sets:
        cmd += ["--set", s]
    t0 = time.time()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(f"  run {name}: exit {p.returncode} in {time.time() - t0:.1f} s", flush=True)
    if p.returncode != 0:
        print(p.stdout)
        raise SystemExit(f"{who}: {' '.join(cmd)} failed with exit {p.returncode}")
    return out


def main(who, parts, argv, doc):
    """`who EXE SCRATCH PART`: runs parts[PART](exe, scratch, check); exit 1 if a check failed,
    2 for a bad command line."""
    if len(argv) != 4 or argv[3] not in parts:
        print(doc)
        return 2
    exe, scratch, which = argv[1], argv[2], argv[3]
    os.makedirs(scratch, exist_ok=True)
    check = Checks()
    t0 = time.time()
    parts[which](exe, scratch, check)
    print(f"{who} {which}: {check.failed} failed, {time.time() - t0:.0f} s")
    return 1 if check.failed else 0


if __name__ == "__main__":
    sys.exit(2)
