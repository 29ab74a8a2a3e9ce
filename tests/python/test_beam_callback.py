"""traverse.run(beam_scene, every=k, callback=f): f sees every k-th time step of a beam run (its
time, the modal state and the deflection at the output's nodes, as read-only arrays); False or
an exception stops the run as Ctrl-C stops `traverse run`, and `traverse run --restart` of the
stopped file ends with the uninterrupted run's file, bit for bit. For the beam with moving
loads (the cantilever), with a coupled mass and with a vehicle."""

import h5py
import numpy as np
import pytest

import traverse
from conftest import assert_raising_callback_stops_restartably, assert_same_datasets, exe_run, run_exe, scene_path

EVERY = 3
# Every time step an output step (the file's /time holds each step's time), few steps.
SCENES = {
    "moving_mass": ("cantilever.yaml", ["time.dt=1e-4", "output.every=1"]),
    "coupled_mass": ("coupled_bead.yaml", ["time.end=0.05", "output.every=1"]),
    "vehicle": ("two_axle_car.yaml", ["time.dt=1e-3", "time.end=0.1", "output.every=1"]),
}


def scene(kind):
    name, sets = SCENES[kind]
    return traverse.Scene.load(scene_path("beam", name), overrides=sets)


@pytest.fixture(scope="module")
def references(tmp_path_factory):
    """Each scene's uninterrupted run (the executable's): its path, step times, deflection field
    and node positions."""
    refs = {}
    for kind, (name, sets) in SCENES.items():
        path = tmp_path_factory.mktemp(kind) / "exe.h5"
        exe_run(scene_path("beam", name), path, sets)
        with h5py.File(path, "r") as f:
            n = int(f.attrs["steps_written"])
            refs[kind] = (str(path), f["time"][:n], f["fields/deflection"][:n], f["fields/position"][:n])
    return refs


@pytest.mark.parametrize("kind", sorted(SCENES))
def test_callback_sees_every_kth_step(tmp_path, references, kind):
    path, times, deflection, position = references[kind]
    seen = []
    result = traverse.run(scene(kind), output=tmp_path / "run.h5", every=EVERY, callback=seen.append)
    assert result.status == "complete" and not result.interrupted
    steps = len(times) - 1
    assert steps > 3 * EVERY, "enough steps to see several calls"
    assert [s.step for s in seen] == list(range(EVERY, steps + 1, EVERY))
    # The step's time is the run's t_k exactly; w is the deflection the file holds at step k,
    # at the nodes the file's positions give.
    assert [s.t for s in seen] == [times[s.step] for s in seen]
    modes = scene(kind)["beam.modes"]
    nodes = deflection.shape[1]
    for s in seen:
        assert s.q.shape == (modes,) and s.q_t.shape == (modes,), (s.q.shape, s.q_t.shape)
        assert s.x.shape == (nodes,) and s.w.shape == (nodes,)
        np.testing.assert_array_equal(s.w, deflection[s.step].reshape(nodes))
        np.testing.assert_array_equal(s.x, position[s.step][:, 0])
    assert any(np.any(s.w != 0.0) for s in seen), "the beam moves"
    # q_t is the rate of q: the central difference of q over two calls matches it (the beam's
    # slowest modes dominate, and 2 EVERY steps resolve them).
    dt = seen[1].t - seen[0].t
    rate = (seen[2].q - seen[0].q) / (seen[2].t - seen[0].t)
    scale = np.max(np.abs([s.q_t for s in seen[:3]]))
    assert dt > 0 and np.abs(rate - seen[1].q_t).max() < 0.1 * scale, (rate, seen[1].q_t)
    # Read-only (and copies: kept after the call they stay as they were).
    for name in ("q", "q_t", "x", "w"):
        a = getattr(seen[0], name)
        assert not a.flags.writeable, name
        with pytest.raises(ValueError):
            a[0] = 1.0
    assert "modes=" in repr(seen[0])
    assert_same_datasets(path, result.path)  # the callback changes nothing of the run


@pytest.mark.parametrize("kind", sorted(SCENES))
def test_false_stops_and_restart_completes(tmp_path, references, kind):
    path, times = references[kind][:2]
    stop_at = 2 * EVERY
    out = tmp_path / "stopped.h5"
    result = traverse.run(scene(kind), output=out, every=EVERY, callback=lambda s: s.step < stop_at)
    assert result.interrupted
    assert result.status.startswith("interrupted at t = ") and "stopped by the step callback" in result.status, result.status
    assert f"traverse run --restart {out}" in result.status
    assert result.steps == stop_at + 1 and result.time[-1] == times[stop_at]
    r = run_exe("run", "--restart", str(out), "-q")
    assert r.returncode == 0, r.stderr
    assert_same_datasets(path, out)


def test_exception_propagates_and_leaves_a_restartable_file(tmp_path, references):
    assert_raising_callback_stops_restartably(traverse, scene("moving_mass"), tmp_path / "raised.h5", EVERY,
                                              references["moving_mass"][0])
