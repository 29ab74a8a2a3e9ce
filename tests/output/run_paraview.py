"""Runs check_paraview.py in Debian's ParaView (pvbatch) on a display of its own: starts
Xvfb on a free display number, runs pvbatch there, stops that Xvfb. The expected values
(times, nodes, a step's points and arrays, the load's position) come from the HDF5 files
(h5py) and are handed to pvbatch as JSON.
Usage: run_paraview.py PVBATCH ROD.xmf BEAM.xmf OUT_DIR      (exit status 1 on any failure)
"""
import json
import os
import shutil
import subprocess
import sys
import time

import h5py
import numpy as np


def fail(msg):
    print("FAILED: " + msg)
    sys.exit(1)


def expected(xmf):
    xmf = os.path.abspath(xmf)
    with h5py.File(os.path.splitext(xmf)[0] + ".h5", "r") as f:
        steps = int(f.attrs["steps_written"])
        k = steps // 2
        x = f["xdmf"]
        geometry = x.attrs["geometry"]
        arrays = {"s": f["mesh/s"][()].tolist()}
        for a in x.attrs["arrays"].split(","):
            arrays[a] = f[f"xdmf/{a}/{k}"][()].tolist()
        s = f["mesh/s"][()]
        sigma = float(np.atleast_2d(f["sigma"][k])[0, 0]) if f["sigma"].ndim == 2 else float(f["sigma"][k])
        j = min(int(np.searchsorted(s, sigma, side="right")) - 1, len(s) - 2)
        xi = (sigma - s[j]) / (s[j + 1] - s[j])
        g = f[f"xdmf/{geometry}/{k}"][()]
        return {"xmf": xmf, "times": f["time"][:steps].tolist(), "step": k, "nodes": len(s),
                "points": g.tolist(), "arrays": arrays, "load": ((1 - xi) * g[j] + xi * g[j + 1]).tolist(),
                "sigma": sigma}


def main():
    pvbatch, rod, beam, out = sys.argv[1:5]
    if shutil.which(pvbatch) is None and not os.access(pvbatch, os.X_OK):
        fail(f"pvbatch not found ({pvbatch}); install the Debian packages paraview and python3-paraview")
    xvfb = shutil.which("Xvfb")
    if xvfb is None:
        fail("Xvfb not found; install the Debian package xvfb")
    os.makedirs(out, exist_ok=True)
    spec = os.path.join(out, "expected.json")
    with open(spec, "w") as fh:
        json.dump({"runs": [expected(rod), expected(beam)], "out": os.path.abspath(out)}, fh)
    display = next((n for n in range(91, 200) if not os.path.exists(f"/tmp/.X{n}-lock")
                    and not os.path.exists(f"/tmp/.X11-unix/X{n}")), None)
    if display is None:
        fail("no free X display number in 91..199")
    server = subprocess.Popen([xvfb, f":{display}", "-ac", "-nolisten", "tcp", "-screen", "0", "1280x1024x24"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        for _ in range(100):
            if os.path.exists(f"/tmp/.X11-unix/X{display}") or server.poll() is not None:
                break
            time.sleep(0.1)
        if server.poll() is not None:
            fail(f"Xvfb :{display} exited at once ({server.returncode})")
        time.sleep(1.0)  # the socket appears before the server answers GLX requests
        env = dict(os.environ, DISPLAY=f":{display}")
        here = os.path.dirname(os.path.abspath(__file__))
        rc = subprocess.call([pvbatch, os.path.join(here, "check_paraview.py"), spec], env=env)
    finally:
        server.terminate()
        try:
            server.wait(timeout=10)
        except subprocess.TimeoutExpired:
            server.kill()
    sys.exit(rc)


if __name__ == "__main__":
    main()
