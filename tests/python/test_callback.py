"""traverse.run(scene, every=k, callback=f): f sees every k-th time step (its time and the whole
rod as read-only arrays); False or an exception stops the run as Ctrl-C stops `traverse run`,
and `traverse run --restart` of the stopped file ends with the uninterrupted run's file, bit
for bit."""

import h5py
import numpy as np
import pytest

import traverse
from conftest import assert_raising_callback_stops_restartably, assert_same_datasets, exe_run, run_exe, scene_path

# Every time step an output step (the file's /time holds each step's time), a coarse mesh.
SETS = ["mesh.ds=0.05", "output.every=1", "output.fields=[r, kappa]"]
EVERY = 3


def scene():
    return traverse.Scene.load(scene_path("default.yaml"), overrides=SETS)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The uninterrupted run (the executable's), its step times and its fields."""
    path = tmp_path_factory.mktemp("reference") / "exe.h5"
    exe_run(scene_path("default.yaml"), path, SETS)
    with h5py.File(path, "r") as f:
        n = int(f.attrs["steps_written"])
        return str(path), f["time"][:n], f["fields/r"][:n], f["fields/kappa"][:n]


def test_callback_sees_every_kth_step(tmp_path, reference):
    _, times, r, kappa = reference
    seen = []

    def record(step):
        seen.append(step)

    result = traverse.run(scene(), output=tmp_path / "run.h5", every=EVERY, callback=record)
    assert result.status == "complete" and not result.interrupted
    steps = len(times) - 1
    assert [s.step for s in seen] == list(range(EVERY, steps + 1, EVERY))
    # The step's time is the run's t_k exactly, and the rod is the state written at step k.
    assert [s.t for s in seen] == [times[s.step] for s in seen]
    nodes = r.shape[1]
    for s in seen:
        assert s.r.shape == (nodes, 3) and s.directors.shape == (nodes, 3, 3)
        for name in ("u", "omega", "kappa", "n"):
            assert getattr(s, name).shape == (nodes, 3), name
        np.testing.assert_array_equal(s.r, r[s.step])
        np.testing.assert_array_equal(s.kappa, kappa[s.step])
        # Rows d1, d2, d3: an orthonormal frame at every node.
        np.testing.assert_allclose(s.directors @ s.directors.transpose(0, 2, 1), np.broadcast_to(np.eye(3), (nodes, 3, 3)),
                                   atol=1e-12)
    # Read-only (and copies: kept after the call they stay as they were).
    for name in ("r", "directors", "u", "omega", "kappa", "n"):
        a = getattr(seen[0], name)
        assert not a.flags.writeable, name
        with pytest.raises(ValueError):
            a[0, 0] = 1.0
    assert_same_datasets(reference[0], result.path)  # the callback changes nothing of the run


# What a callback may return to stop: Python's False, or numpy's (a comparison of arrays).
ANSWERS = {"bool": bool, "numpy": np.bool_}


@pytest.mark.parametrize("answer", sorted(ANSWERS))
def test_false_stops_and_restart_completes(tmp_path, reference, answer):
    stop_at = 2 * EVERY
    out = tmp_path / "stopped.h5"
    result = traverse.run(scene(), output=out, every=EVERY, callback=lambda s: ANSWERS[answer](s.step < stop_at))
    assert result.interrupted
    assert result.status.startswith("interrupted at t = ") and "stopped by the step callback" in result.status, result.status
    assert f"traverse run --restart {out}" in result.status
    assert result.steps == stop_at + 1 and result.time[-1] == reference[1][stop_at]
    r = run_exe("run", "--restart", str(out), "-q")
    assert r.returncode == 0, r.stderr
    n = assert_same_datasets(reference[0], out)
    print(f"stopped at step {stop_at}, restarted: {n} datasets equal to the uninterrupted run's bit for bit")


def test_exception_propagates_and_leaves_a_restartable_file(tmp_path, reference):
    assert_raising_callback_stops_restartably(traverse, scene(), tmp_path / "raised.h5", EVERY, reference[0])


def test_temporary_output_of_a_raising_callback_is_kept():
    def explode(step):
        raise KeyError("stop")

    with pytest.raises(KeyError) as e:
        traverse.run(scene(), callback=explode)
    path = e.value.__notes__[0].split("; ")[1].split(" is restartable")[0]
    assert traverse.read(path, allow_incomplete=True).status.startswith("interrupted")


def test_refused_where_there_are_no_time_steps():
    with pytest.raises(ValueError, match="callback= is for runs with time steps.*a continuation .statics. scene"):
        traverse.run(scene_path("statics", "euler_buckling.yaml"), callback=print)
    with pytest.raises(ValueError, match="every must be"):
        traverse.run(scene(), every=0, callback=print)
