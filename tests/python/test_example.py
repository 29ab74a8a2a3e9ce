"""The examples of examples/python run and draw their figures."""

import math
import os
import re
import subprocess
import sys

import pytest

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


def test_fit_stiffness_example(tmp_path):
    """The fit recovers the modulus of the measurement to within the accuracy its search was
    asked for: minimize_scalar's bounded search stops with the minimiser inside a bracket of
    2 (sqrt(eps) |E| + xatol / 3) around its answer, so |E - E_true| <= xatol + 2 sqrt(eps) |E|
    (the measurement is a run of the same model: its misfit is least at the true modulus)."""
    try:
        import scipy.optimize  # noqa: F401
    except ImportError:
        pytest.fail(f"the example needs scipy for {sys.executable} (Debian: python3-scipy)")
    png = tmp_path / "fit.png"
    true_modulus, xatol = 3.0e8, 1.0e5
    script = os.path.join(SOURCE_DIR, "examples", "python", "fit_stiffness.py")
    r = subprocess.run([sys.executable, script, "-o", str(png), "--true-modulus", repr(true_modulus),
                        "--bounds", "1e8", "6e8", "--xatol", repr(xatol), "--set", "mesh.ds=0.05"],
                       capture_output=True, text=True, timeout=240)
    assert r.returncode == 0, r.stderr
    recovered = float(re.search(r"^recovered modulus: +(\S+) Pa$", r.stdout, re.M).group(1))
    tolerance = xatol + 2 * (2.0 ** -26) * recovered  # sqrt(eps) of a double is 2^-26
    assert abs(recovered - true_modulus) <= tolerance, r.stdout
    assert png.stat().st_size > 10_000, "a figure with curves, not an empty file"
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"


def run_example(name, *args):
    script = os.path.join(SOURCE_DIR, "examples", "python", name)
    r = subprocess.run([sys.executable, script, *args], capture_output=True, text=True, timeout=240)
    assert r.returncode == 0, r.stderr
    return r.stdout


def assert_png(path):
    assert path.stat().st_size > 10_000, "a figure with curves, not an empty file"
    with open(path, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"


def test_bridge_resonance_example(tmp_path):
    """The beam example's sweep peaks at the speed nearest the first resonance f_1 d (73.65 m/s
    for the shipped bridge and train: of 60, 65, ..., 90 m/s, 75)."""
    png = tmp_path / "bridge.png"
    out = run_example("bridge_resonance.py", "-o", str(png), "--speeds", "60:90:5")
    resonance = float(re.search(r"resonance speed f1 d = (\S+) m/s", out).group(1))
    peak = float(re.search(r"largest deflection \S+ mm at (\S+) m/s", out).group(1))
    assert abs(resonance - 73.65) < 0.01, out
    assert peak == 75.0, out
    assert_png(png)


def test_euler_buckling_example(tmp_path):
    """The statics example's pitchfork and buckled branch approach the elastica's closed form at
    second order in ds (measured 2.00 and 2.19 from ds = 0.04 to 0.02; asserted 2 +- 0.3)."""
    found = {}
    for ds in (0.04, 0.02):
        png = tmp_path / f"euler_{ds}.png"
        out = run_example("euler_buckling.py", "-o", str(png), "--set", f"mesh.ds={ds}")
        pitchfork = abs(float(re.search(r"relative difference (\S+)\)", out).group(1)))
        branch = float(re.search(r"largest distance from the closed form (\S+)", out).group(1))
        found[ds] = (pitchfork, branch)
        assert_png(png)
    for i, what in enumerate(("pitchfork load", "buckled branch")):
        order = math.log2(found[0.04][i] / found[0.02][i])
        assert abs(order - 2.0) <= 0.3, f"{what}: order {order:.2f} ({found})"
