"""Shared helpers of the Python module's tests: the executable of the same build (TRAVERSE_EXE),
the source tree (TRAVERSE_SOURCE_DIR), and a comparison of two output files."""

import os
import subprocess

import h5py
import numpy as np
import pytest

SOURCE_DIR = os.environ.get("TRAVERSE_SOURCE_DIR", os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
EXE = os.environ.get("TRAVERSE_EXE", "")

# Datasets that are the run's bookkeeping, not its results (as scripts/compare-runs.py skips
# them): wall times, timings and restart points.
SKIPPED = ("wall", "seconds", "timing", "restart")


def scene_path(*parts):
    return os.path.join(SOURCE_DIR, "inputs", *parts)


def run_exe(*args):
    """Runs the executable with `args`; returns the CompletedProcess (text output)."""
    if not EXE or not os.path.exists(EXE):
        pytest.fail(f"TRAVERSE_EXE is not the traverse executable: {EXE!r} (run through ctest)")
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    return subprocess.run([EXE, *args], capture_output=True, text=True, env=env, timeout=240)


def exe_run(scene, out, sets=(), code=0):
    """`traverse run SCENE -o OUT -q --set S ...` with the executable; asserts its exit code
    `code` and returns the CompletedProcess."""
    args = ["run", str(scene), "-o", str(out), "-q"]
    for s in sets:
        args += ["--set", s]
    r = run_exe(*args)
    assert r.returncode == code, r.stderr
    return r


def datasets(path):
    """Every dataset of the file outside /xdmf and the skipped bookkeeping: name -> array."""
    out = {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset) and not name.startswith("xdmf/") and not any(s in name for s in SKIPPED):
                out[name] = obj[()]
        f.visititems(visit)
    return out


def assert_same_datasets(a, b):
    """The two files hold the same datasets with the same dtypes and shapes, equal bit for
    bit (NaN where the other has NaN). Returns the number of datasets compared."""
    da, db = datasets(a), datasets(b)
    assert sorted(da) == sorted(db), f"datasets differ: only in {a}: {sorted(set(da) - set(db))}, only in {b}: {sorted(set(db) - set(da))}"
    for name in sorted(da):
        x, y = np.asarray(da[name]), np.asarray(db[name])
        assert x.dtype == y.dtype, f"{name}: dtype {x.dtype} against {y.dtype}"
        assert x.shape == y.shape, f"{name}: shape {x.shape} against {y.shape}"
        if x.dtype.kind in "fiub":
            # Bit for bit: the same bytes (NaN where the other has NaN, signed zeros alike).
            if x.tobytes() != y.tobytes():
                diff = np.nanmax(np.abs(x.astype(float) - y.astype(float))) if x.size else 0.0
                pytest.fail(f"{name}: values differ (largest difference {diff:.3e})")
        else:
            assert np.array_equal(x, y), f"{name}: values differ"
    return len(da)


def assert_raising_callback_stops_restartably(traverse, scene, out, every, reference):
    """A callback that raises after `every` steps: the exception propagates with a note naming
    the restartable file `out`, which holds the steps up to there and, restarted by the
    executable, equals `reference` bit for bit."""

    class Enough(Exception):
        pass

    def explode(step):
        if step.step >= every:
            raise Enough(f"at t = {step.t}")

    with pytest.raises(Enough) as e:
        traverse.run(scene, output=out, callback=explode)
    assert any(str(out) in note and "restartable" in note for note in e.value.__notes__), e.value.__notes__
    out_file = traverse.read(out, allow_incomplete=True)
    assert out_file.status.startswith("interrupted at t = ") and out_file.steps_written == every + 1
    r = run_exe("run", "--restart", str(out), "-q")
    assert r.returncode == 0, r.stderr
    assert_same_datasets(reference, out)
