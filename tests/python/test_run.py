"""traverse.run against the executable of the same build: the same output file dataset by
dataset, bit for bit, for a rod, a beam and a statics scene; repeated runs in one process;
the Result's arrays as the file holds them."""

import os
import re

import h5py
import numpy as np
import pytest

import traverse
from conftest import assert_same_datasets, exe_run, run_exe, scene_path

# (scene, --set strings). Each runs in about a second.
CASES = {
    "default": ("default.yaml", []),
    "beam_cantilever": (os.path.join("beam", "cantilever.yaml"), []),
    "statics_euler_buckling": (os.path.join("statics", "euler_buckling.yaml"), []),
}


def run_both(tmp_path, case):
    """Runs the case with the executable and with the module; returns both paths and the
    Result."""
    rel, sets = CASES[case]
    path = scene_path(rel)
    exe_out, py_out = str(tmp_path / "exe.h5"), str(tmp_path / "module.h5")
    exe_run(path, exe_out, sets)
    result = traverse.run(traverse.Scene.load(path, overrides=sets), output=py_out)
    return exe_out, py_out, result


@pytest.mark.parametrize("case", sorted(CASES))
def test_same_file_as_the_executable(tmp_path, case):
    exe_out, py_out, result = run_both(tmp_path, case)
    n = assert_same_datasets(exe_out, py_out)
    print(f"{case}: {n} datasets equal bit for bit, {result.steps} output steps")
    assert result.status == "complete"
    with h5py.File(exe_out, "r") as a, h5py.File(py_out, "r") as b:
        # The same root attributes (model, status, steps or points, the validated scene, the
        # initial state...), but for the command line that made the file.
        keys = sorted(set(a.attrs) | set(b.attrs))
        assert keys == sorted(a.attrs) == sorted(b.attrs), keys
        for key in keys:
            if key != "command_line":
                assert a.attrs[key] == b.attrs[key], key
        assert b.attrs["command_line"].startswith("traverse.run(")
    # The ParaView sidecar where the executable writes one (time-series runs).
    sidecar = [os.path.exists(os.path.splitext(p)[0] + ".xmf") for p in (exe_out, py_out)]
    assert sidecar[0] == sidecar[1] == (result.kind == "time_series"), sidecar


def test_result_arrays_are_the_files(tmp_path):
    _, py_out, result = run_both(tmp_path, "default")
    with h5py.File(py_out, "r") as f:
        n = int(f.attrs["steps_written"])
        assert result.steps == n > 1
        np.testing.assert_array_equal(result.time, f["time"][:n])
        np.testing.assert_array_equal(result.sigma, f["sigma"][:n])
        np.testing.assert_array_equal(result.probes["midspan"], f["probes/midspan"][:n])
        assert list(result.fields) == ["r"] and "r" in result.fields
        r = f["fields/r"][:n]
    np.testing.assert_array_equal(result.fields["r"], r)
    assert result.fields["r"].shape == (n, result.s.size, 3)
    assert result.attrs["status"] == "complete"
    assert "steps written: " + str(n) in result.summary()


def test_continuation_result_is_the_file(tmp_path):
    _, py_out, result = run_both(tmp_path, "statics_euler_buckling")
    assert result.kind == "continuation"
    with h5py.File(py_out, "r") as f:
        n = int(f.attrs["points_written"])
        assert result.steps == n > 1
        assert sorted(result.continuation) == sorted(f["continuation"])
        for name in f["continuation"]:
            np.testing.assert_array_equal(result.continuation[name], f["continuation"][name][:n])
        assert result.parameter == traverse.Scene.load(scene_path(CASES["statics_euler_buckling"][0]))["continuation.parameter"]
        assert result.bifurcations["type"] == [t.decode() for t in f["bifurcations/type"][()]]
        np.testing.assert_array_equal(result.states["final"]["r"], f["states/final/r"][()])
    with pytest.raises(AttributeError):
        result.time


def test_repeated_runs_leave_no_state(tmp_path):
    """A rod run, a beam run, a statics run and the rod run again in one process: the two
    rod runs' files are equal bit for bit (nothing of a run is left for the next)."""
    rod = traverse.Scene.load(scene_path("default.yaml"), overrides=["mesh.ds=0.05"])
    first = traverse.run(rod)
    traverse.run(traverse.Scene.load(scene_path("beam", "cantilever.yaml")))
    traverse.run(scene_path("statics", "euler_buckling.yaml"))
    second = traverse.run(rod)
    assert first.path != second.path
    n = assert_same_datasets(first.path, second.path)
    print(f"two rod runs in one process: {n} datasets equal bit for bit")


def test_temporary_output_is_owned_by_the_result():
    scene = traverse.Scene.load(scene_path("beam", "cantilever.yaml"))
    result = traverse.run(scene)
    path = result.path
    assert os.path.exists(path)
    del result
    assert not os.path.exists(path), "the temporary output goes with its Result"


def test_existing_output_refused_like_the_executable(tmp_path):
    path = scene_path("beam", "cantilever.yaml")
    out = str(tmp_path / "taken.h5")
    traverse.run(traverse.Scene.load(path), output=out)
    before = os.path.getmtime(out)
    with pytest.raises(traverse.OutputError) as e:
        traverse.run(traverse.Scene.load(path), output=out)
    r = run_exe("run", path, "-o", out, "-q")
    assert r.returncode == 2
    assert r.stderr.strip() == f"traverse: bad output path: {e.value}"
    assert os.path.getmtime(out) == before
    # overwrite=True replaces it, as --overwrite does.
    assert traverse.run(traverse.Scene.load(path), output=out, overwrite=True).status == "complete"


def _resident_kb():
    """The process's resident memory now [KB] (Linux: /proc/self/statm), not its peak."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") // 1024


def test_memory_does_not_grow_over_100_runs():
    # After ten runs (libraries, MPI and Kokkos in place) the resident memory stays put: a run
    # that left 40 kB behind (a 101-node rod's nodes and blocks are about 1 MB) would add
    # 3.6 MB over the next 90.
    scene = traverse.Scene.load(scene_path("default.yaml"), overrides=["time.end=0.02"])
    resident = []
    for _ in range(100):
        result = traverse.run(scene)
        assert result.probes["midspan"].shape[0] > 1
        result.close()
        resident.append(_resident_kb())
    growth = resident[-1] - resident[9]
    print(f"resident memory after 10 runs {resident[9]} kB, after 100 {resident[-1]} kB")
    assert growth < 3600, f"the resident memory grew by {growth} kB over 90 runs"


def test_events_and_solve_counts_are_the_executables(tmp_path):
    """A coupled bead leaves the cable at its end: the Result's events and counters are the
    ones the executable reports (its -v done line) and writes."""
    out = tmp_path / "exe.h5"
    r = run_exe("run", scene_path("rod", "coupled_bead_cable.yaml"), "-o", str(out), "-v")
    assert r.returncode == 0, r.stderr
    done = re.search(r"done: (\d+) steps, (\d+) coupling iterations, (\d+) Newton iterations; ended by the event "
                     r"(\w+) at t = (\S+) s", r.stdout)
    assert done, r.stdout
    result = traverse.run(scene_path("rod", "coupled_bead_cable.yaml"))
    steps, coupling, newton, reason, t = done.groups()
    assert (result.attrs["time_steps"], result.attrs["coupling_iterations"], result.attrs["newton_iterations"]) == (
        steps, coupling, newton)
    [event] = result.events
    assert event["reason"] == reason == "left_rod_at_L" and event["load"] == "bead"
    assert event["position"] == 1.0  # the rod's length: the right end
    assert abs(event["time"] - float(t)) <= 1e-8 * float(t)
    assert traverse.read(out).events == result.events
    # Without a coupled mass: no events, the rod's counters.
    plain = traverse.run(scene_path("default.yaml"), output=tmp_path / "plain.h5")
    assert plain.events == [] and int(plain.attrs["time_steps"]) == plain.steps - 1
    assert int(plain.attrs["newton_iterations"]) >= int(plain.attrs["time_steps"])
