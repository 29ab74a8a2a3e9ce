"""traverse.run against the executable of the same build: the same output file dataset by
dataset, bit for bit, for a rod, a beam and a statics scene; repeated runs in one process;
the Result's arrays as the file holds them."""

import os

import h5py
import numpy as np
import pytest

import traverse
from conftest import assert_same_datasets, run_exe, scene_path

# (scene, --set strings that keep the run short). The default scene is run as it is.
CASES = {
    "default": ("default.yaml", []),
    "beam_cantilever": (os.path.join("beam", "cantilever.yaml"), ["time.dt=1e-4"]),
    "statics_euler_buckling": (os.path.join("statics", "euler_buckling.yaml"), []),
}


def run_both(tmp_path, case):
    """Runs the case with the executable and with the module; returns both paths and the
    Result."""
    rel, sets = CASES[case]
    path = scene_path(rel)
    exe_out, py_out = str(tmp_path / "exe.h5"), str(tmp_path / "module.h5")
    args = ["run", path, "-o", exe_out, "-q"]
    for s in sets:
        args += ["--set", s]
    r = run_exe(*args)
    assert r.returncode == 0, r.stderr
    result = traverse.run(traverse.Scene.load(path, overrides=sets), output=py_out)
    return exe_out, py_out, result


@pytest.mark.parametrize("case", sorted(CASES))
def test_same_file_as_the_executable(tmp_path, case):
    exe_out, py_out, result = run_both(tmp_path, case)
    n = assert_same_datasets(exe_out, py_out)
    print(f"{case}: {n} datasets equal bit for bit, {result.steps} output steps")
    assert result.status == "complete"
    with h5py.File(exe_out, "r") as a, h5py.File(py_out, "r") as b:
        # The same run: model, status, steps and the validated scene the run used.
        for key in ("model", "status", "steps_written", "scene"):
            assert a.attrs[key] == b.attrs[key], key
    assert os.path.exists(os.path.splitext(py_out)[0] + ".xmf"), "the ParaView sidecar is written too"


def test_result_arrays_are_the_files(tmp_path):
    _, py_out, result = run_both(tmp_path, "default")
    with h5py.File(py_out, "r") as f:
        n = int(f.attrs["steps_written"])
        assert result.steps == n > 1
        np.testing.assert_array_equal(result.time, f["time"][:n])
        np.testing.assert_array_equal(result.sigma, f["sigma"][:n])
        np.testing.assert_array_equal(result.probes["midspan"], f["probes/midspan"][:n])
        assert list(result.fields) == ["r"] and "r" in result.fields
        np.testing.assert_array_equal(result.fields["r"], f["fields/r"][:n])
    assert result.fields["r"].shape == (n, result.s.size, 3)
    assert result.attrs["status"] == "complete"
    assert "steps written: " + str(n) in result.summary()


def test_repeated_runs_leave_no_state(tmp_path):
    """A rod run, a beam run, a statics run and the rod run again in one process: the two
    rod runs' files are equal bit for bit (nothing of a run is left for the next)."""
    rod = traverse.Scene.load(scene_path("default.yaml"), overrides=["mesh.ds=0.05"])
    first = traverse.run(rod)
    traverse.run(traverse.Scene.load(scene_path("beam", "cantilever.yaml"), overrides=["time.dt=1e-4"]))
    traverse.run(scene_path("statics", "euler_buckling.yaml"))
    second = traverse.run(rod)
    assert first.path != second.path
    n = assert_same_datasets(first.path, second.path)
    print(f"two rod runs in one process: {n} datasets equal bit for bit")


def test_temporary_output_is_owned_by_the_result():
    scene = traverse.Scene.load(scene_path("beam", "cantilever.yaml"), overrides=["time.dt=1e-4"])
    result = traverse.run(scene)
    path = result.path
    assert os.path.exists(path)
    del result
    assert not os.path.exists(path), "the temporary output goes with its Result"


def test_existing_output_refused_like_the_executable(tmp_path):
    path = scene_path("beam", "cantilever.yaml")
    out = str(tmp_path / "taken.h5")
    traverse.run(traverse.Scene.load(path, overrides=["time.dt=1e-4"]), output=out)
    before = os.path.getmtime(out)
    with pytest.raises(traverse.OutputError) as e:
        traverse.run(traverse.Scene.load(path, overrides=["time.dt=1e-4"]), output=out)
    r = run_exe("run", path, "-o", out, "-q", "--set", "time.dt=1e-4")
    assert r.returncode == 2
    assert r.stderr.strip() == f"traverse: bad output path: {e.value}"
    assert os.path.getmtime(out) == before
    # overwrite=True replaces it, as --overwrite does.
    assert traverse.run(traverse.Scene.load(path, overrides=["time.dt=1e-4"]), output=out, overwrite=True).status == "complete"
