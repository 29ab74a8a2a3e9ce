"""Runs the pvpython recipe of docs/output.md exactly as printed there (the ```python block
after the line "<!-- tested by tests/output/run_recipe.py -->") with pvbatch, on an Xvfb
display of its own, in a folder holding out/default.h5 (a copy of the fixture's rod run) and
the sidecar `traverse xdmf` writes for it; checks its output and its picture.
Usage: run_recipe.py PVBATCH DOC.md ROD.h5 TRAVERSE OUT_DIR     (exit status 1 on any failure)
"""
import os
import re
import shutil
import subprocess
import sys

import h5py
import matplotlib.image
import numpy as np

from run_paraview import fail, require_pvbatch, run_pvbatch


def main():
    pvbatch, doc, rod, exe, out = sys.argv[1:6]
    require_pvbatch(pvbatch)
    text = open(doc).read()
    m = re.search(r"<!-- tested by tests/output/run_recipe.py -->\s*```python\n(.*?)```", text, re.S)
    if m is None:
        fail(f"{doc}: no python block after the marker line")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(os.path.join(out, "out"))
    shutil.copy(rod, os.path.join(out, "out", "default.h5"))
    if subprocess.call([exe, "xdmf", "out/default.h5"], cwd=out) != 0:
        fail("traverse xdmf out/default.h5 failed")
    with open(os.path.join(out, "recipe.py"), "w") as fh:
        fh.write(m.group(1))
    run = run_pvbatch(pvbatch, ["recipe.py"], cwd=out, capture=True)
    print(run.stdout)
    passed, failed = 0, 0

    def check(cond, what):
        nonlocal passed, failed
        passed, failed = passed + bool(cond), failed + (not cond)
        if not cond:
            print("FAILED: " + what)

    with h5py.File(rod, "r") as f:
        steps, nodes = int(f.attrs["steps_written"]), f["mesh/s"].shape[0]
    messages = "\n".join(line for line in run.stderr.splitlines() if "0x" not in line)
    check(run.returncode == 0, f"the recipe exits with {run.returncode}: {messages[-3000:]}")
    check(f"{steps} output steps; {nodes + 1} points (cable and load)" in run.stdout,
          f"it prints the steps and points of the run ({steps}, {nodes} + 1)")
    png = os.path.join(out, "cable.png")
    check(os.path.exists(png), "it saves cable.png")
    if os.path.exists(png):
        img = matplotlib.image.imread(png)[..., :3]
        ink = np.abs(img - img[0, 0]).sum(axis=-1) > 0.1
        cols = np.nonzero(ink.any(axis=0))[0]
        check(0.001 < ink.mean() < 0.5, f"cable.png: {100 * ink.mean():.2f} % of the pixels drawn")
        check(cols.size > 0 and cols[-1] - cols[0] > 0.4 * img.shape[1], "cable.png: the cable spans the picture")
        colours = len(np.unique(np.round(img[ink] * 255).astype(int), axis=0))
        check(colours >= 20, f"cable.png: {colours} colours: coloured by s")
    print(f"{passed} passed, {failed} failed")
    sys.exit(0 if failed == 0 else 1)


if __name__ == "__main__":
    main()
