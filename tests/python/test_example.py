"""The examples of examples/python run and draw their figures."""

import os
import subprocess
import sys

from conftest import SOURCE_DIR


def test_default_cable_example(tmp_path):
    png = tmp_path / "cable.png"
    kept = tmp_path / "cable.h5"
    script = os.path.join(SOURCE_DIR, "examples", "python", "default_cable.py")
    r = subprocess.run([sys.executable, script, "-o", str(png), "--keep", str(kept), "--set", "mesh.ds=0.05"],
                       capture_output=True, text=True, timeout=240)
    assert r.returncode == 0, r.stderr
    assert png.stat().st_size > 10_000, "a figure with a curve, not an empty file"
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    import traverse

    out = traverse.read(kept)
    length = traverse.Scene.load(os.path.join(SOURCE_DIR, "inputs", "default.yaml"))["rod.length"]
    assert out.status == "complete" and out.s.size == round(length / 0.05) + 1, "the run had the --set given"


def test_speed_sweep_example(tmp_path):
    png = tmp_path / "sweep.png"
    kept = tmp_path / "sweep"
    script = os.path.join(SOURCE_DIR, "examples", "python", "speed_sweep.py")
    r = subprocess.run([sys.executable, script, "-o", str(png), "--keep", str(kept), "--speeds", "1:4:1.5",
                        "--set", "mesh.ds=0.05"], capture_output=True, text=True, timeout=240)
    assert r.returncode == 0, r.stderr
    assert png.stat().st_size > 10_000, "a figure with curves, not an empty file"
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    import traverse

    rows = traverse.reader.sweep_index(kept)
    assert [row["loads.F.speed"] for row in rows] == ["1.0", "2.5", "4.0"]
    assert all(row["status"] == "complete" for row in rows), rows
