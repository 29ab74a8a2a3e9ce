#!/usr/bin/env python3
"""Checks the sample files of tests/output/sample_writer.cpp through
postprocessing/traverse_io.py: exact values (same formulas as tests/output/sample_run.hpp),
metadata, status handling, the command-line summary and the XDMF sidecar.

Usage: check_roundtrip.py SAMPLE.h5 SAMPLE_FAILED.h5   (exit status 1 on any failure)
"""
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
IO_DIR = os.path.join(HERE, "..", "..", "postprocessing")
sys.path.insert(0, IO_DIR)
import traverse_io  # noqa: E402

NODES, LOADS, STEPS = 7, 2, 5
FIELD_COMPS = {"w": 1, "r": 3, "strain": 6}
FIELD_INDEX = {"w": 0, "r": 1, "strain": 2}

passed, failed = 0, 0


def check(cond, what):
    global passed, failed
    if cond:
        passed += 1
    else:
        failed += 1
        print(f"FAILED: {what}")


def expected_field(f, steps):
    k = np.arange(steps, dtype=float)[:, None, None]
    i = np.arange(NODES, dtype=float)[None, :, None]
    c = np.arange(FIELD_COMPS[f], dtype=float)[None, None, :]
    return 1000.0 * FIELD_INDEX[f] + 10.0 * k + 0.5 * i + 0.0625 * c


def check_values(out, steps):
    k = np.arange(steps, dtype=float)
    check(out.steps_written == steps, f"steps_written {out.steps_written} == {steps}")
    check(np.array_equal(out.time, 0.25 * k), "time values")
    sig = 0.5 * k[:, None] + 10.0 * np.arange(LOADS)[None, :]
    check(out.sigma.shape == (steps, LOADS) and np.array_equal(out.sigma, sig), "sigma values")
    check(np.array_equal(out.s, 0.125 * np.arange(NODES)), "arclength /mesh/s")
    check(np.array_equal(out.probes["midspan_w"], k), "probe midspan_w")
    react = 100.0 + k[:, None] + 0.25 * np.arange(3)[None, :]
    check(out.probes["reaction"].shape == (steps, 3) and
          np.array_equal(out.probes["reaction"], react), "probe reaction")
    for f in FIELD_COMPS:
        v = out.field(f)
        check(v.shape == (steps, NODES, FIELD_COMPS[f]), f"field {f} shape {v.shape}")
        check(np.array_equal(v, expected_field(f, steps)), f"field {f} values")
        check(np.array_equal(out.field(f, step=-1), expected_field(f, steps)[-1]),
              f"field {f} last step")


def check_xdmf(h5_path, steps):
    xmf = os.path.splitext(h5_path)[0] + ".xmf"
    try:
        root = ET.parse(xmf).getroot()
    except ET.ParseError as e:
        check(False, f"{xmf} is well-formed XML: {e}")
        return
    check(root.tag == "Xdmf" and root.get("Version") == "3.0", "XDMF 3 root element")
    grids = root.findall("./Domain/Grid[@Name='structure']/Grid")
    check(len(grids) == steps, f"{len(grids)} XDMF grids == {steps} steps")
    times = [float(g.find("Time").get("Value")) for g in grids]
    check(times == [0.25 * k for k in range(steps)], "XDMF time values")
    bad = []
    with h5py.File(h5_path, "r") as f:
        for item in root.iter("DataItem"):
            if item.get("Format") != "HDF":
                continue
            name = item.text.strip().split(":", 1)[1]
            dims = tuple(int(x) for x in item.get("Dimensions").split())
            if name not in f or f[name].shape != dims:
                bad.append(f"{name} {dims}")
    check(not bad, f"XDMF data items match datasets: {bad[:3]}")
    names = {a.get("Name") for a in grids[-1].iter("Attribute")} if grids else set()
    want = {"s", "w", "r"} | {f"strain_{c}" for c in ("g1", "g2", "g3", "k1", "k2", "k3")}
    check(names == want, f"XDMF attributes {sorted(names)}")


def main(argv):
    if len(argv) != 3:
        print(__doc__)
        return 1
    sample, failed_file = argv[1], argv[2]

    out = traverse_io.load(sample)
    check(out.status == "complete", "status complete")
    check(out.attrs["model"] == "rod", "model attribute")
    check(out.attrs["traverse_version"] == "0.1.0-test", "traverse_version attribute")
    check(out.attrs["scene"].startswith("model: rod\nloads:\n") and
          len(out.attrs["scene"].encode()) >= 100000, "scene attribute (> 64 KiB)")
    check(out.units("time") == "s" and out.units("sigma") == "m" and out.units("s") == "m",
          "units of time, sigma, s")
    check(out.units("reaction") == "N" and out.components("reaction") == ["x", "y", "z"],
          "probe metadata")
    check(out.description("midspan_w") == "vertical deflection at midspan", "probe description")
    check(out.units("fields/strain") == "1" and
          out.components("strain") == ["g1", "g2", "g3", "k1", "k2", "k3"], "field metadata")
    check_values(out, STEPS)
    check(out.restart_time == 1.0, "restart time")
    st = out.restart.get("state")
    check(st is not None and np.array_equal(
        st, np.arange(NODES)[:, None] + 0.5 * np.arange(2)[None, :] + 4.0), "restart per-node array")
    check(np.array_equal(out.restart.get("loads"), [1.5, 2.5, 4.0]), "restart replicated array")
    check_xdmf(sample, STEPS)

    try:
        traverse_io.load(failed_file)
        check(False, "a failed run is refused without allow_incomplete")
    except traverse_io.IncompleteOutputError as e:
        check("failed: Newton iteration diverged" in str(e) and "allow_incomplete" in str(e),
              f"refusal message: {e}")
    bad = traverse_io.load(failed_file, allow_incomplete=True)
    check(bad.status == "failed: Newton iteration diverged", "failed status text")
    check_values(bad, 2)
    check_xdmf(failed_file, 2)

    cli = os.path.join(IO_DIR, "traverse_io.py")
    r = subprocess.run([sys.executable, cli, sample], capture_output=True, text=True)
    check(r.returncode == 0 and "status:        complete" in r.stdout and "strain" in r.stdout,
          f"command-line summary (rc {r.returncode}): {r.stderr}")
    r = subprocess.run([sys.executable, cli, failed_file, "--check"], capture_output=True, text=True)
    check(r.returncode == 2 and "failed: Newton" in r.stdout, "command-line --check on a failed run")

    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
