"""examples/python/default_cable.py runs and draws its figure."""

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
