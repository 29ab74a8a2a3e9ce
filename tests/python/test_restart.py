"""Continuing and stopping runs from Python: traverse.run(restart=...) continues a stopped run
into its file as `traverse run --restart` does; step callbacks of rod runs with a coupled or a
sprung mass see the mass; Ctrl-C (SIGINT) stops a run or a sweep as it stops the executable
(restartable file, KeyboardInterrupt) and leaves the interpreter's handler in place."""

import os
import signal
import threading
import time

import h5py
import numpy as np
import pytest

import traverse
from conftest import assert_same_datasets, exe_run, run_exe, scene_path

EVERY = 2

# Short runs, every time step an output step. The coupled and sprung runs start their mass on
# the rod (a bead launched at 2 m/s, a cabin on its wheel) and end before it leaves.
CASES = {
    "rod": (("default.yaml",), ["mesh.ds=0.05", "output.every=1", "output.fields=[r, kappa]", "time.end=0.15"]),
    "beam": (("beam", "cantilever.yaml"), ["time.dt=1e-4", "output.every=1", "time.end=0.01"]),
    "coupled": (("rod", "coupled_bead_cable.yaml"), ["mesh.ds=0.05", "output.every=1", "time.end=0.3"]),
    "sprung": (("rod", "sprung_cabin_cable.yaml"), ["mesh.ds=0.05", "output.every=1", "time.end=0.3"]),
}


def scene(kind):
    parts, sets = CASES[kind]
    return traverse.Scene.load(scene_path(*parts), overrides=sets)


@pytest.fixture(scope="module")
def references(tmp_path_factory):
    """The executable's uninterrupted run of each case."""
    out = {}
    base = tmp_path_factory.mktemp("references")
    for kind, (parts, sets) in CASES.items():
        path = base / f"{kind}.h5"
        exe_run(scene_path(*parts), path, sets)
        out[kind] = str(path)
    return out


@pytest.mark.parametrize("kind", ["coupled", "sprung"])
def test_callback_of_a_coupled_run_sees_the_mass(tmp_path, references, kind):
    seen = []
    result = traverse.run(scene(kind), output=tmp_path / "run.h5", every=EVERY, callback=seen.append)
    assert result.status == "complete"
    name = next(iter(scene(kind).check()["loads"]))
    with h5py.File(references[kind], "r") as f:
        n = int(f.attrs["steps_written"])
        times, r = f["time"][:n], f["fields/r"][:n]
        sigma, speed = f[f"probes/{name}_position"][:n], f[f"probes/{name}_speed"][:n]
        body = f[f"probes/{name}_body_displacement"][:n] if kind == "sprung" else None
    assert [s.step for s in seen] == list(range(EVERY, n, EVERY))
    for s in seen:
        assert s.t == times[s.step]
        np.testing.assert_array_equal(s.r, r[s.step])
        assert s.mass is not None
        # The mass the file holds at that step, exactly.
        assert (s.mass.sigma, s.mass.speed) == (sigma[s.step].item(), speed[s.step].item())
        if kind == "sprung":
            assert s.mass.body == body[s.step].item() and s.mass.body_speed is not None
        else:
            assert s.mass.body is None and s.mass.body_speed is None
    assert seen[-1].mass.sigma > seen[0].mass.sigma  # it moves along the rod
    assert_same_datasets(references[kind], result.path)


@pytest.mark.parametrize("kind", sorted(CASES))
def test_restart_from_python_continues_bit_for_bit(tmp_path, references, kind):
    stop_at = 2 * EVERY
    stopped = traverse.run(scene(kind), every=EVERY, callback=lambda s: s.step < stop_at)
    assert stopped.interrupted and stopped.steps == stop_at + 1
    path = stopped.path
    # The Result of a temporary output hands its file over to the restart's.
    done = traverse.run(restart=stopped)
    assert stopped._tmp is None and os.path.exists(path)
    assert done.path == path and done.status == "complete" and not done.interrupted
    n = assert_same_datasets(references[kind], done.path)
    print(f"{kind}: stopped at step {stop_at}, restarted in Python: {n} datasets equal bit for bit")
    done.close()
    assert not os.path.exists(path)


def test_a_refused_restart_leaves_the_temporary_file_with_its_result(references):
    stopped = traverse.run(scene("rod"), every=EVERY, callback=lambda s: s.step < EVERY)
    with pytest.raises(ValueError, match="a restart continues its own file"):
        traverse.run(restart=stopped, output="elsewhere.h5")
    with pytest.raises(traverse.SceneError, match="continuation .statics. runs cannot be restarted"):
        traverse.run(scene_path("statics", "euler_buckling.yaml"), restart=stopped)
    assert stopped._tmp is not None and os.path.exists(stopped.path)
    done = traverse.run(restart=stopped)
    assert stopped._tmp is None and done.status == "complete"
    assert_same_datasets(references["rod"], done.path)


def test_restart_takes_a_scene_file_and_refuses_what_the_program_refuses(tmp_path, references):
    out = tmp_path / "stopped.h5"
    traverse.run(scene("rod"), output=out, every=EVERY, callback=lambda s: s.step < EVERY)
    done = traverse.run(scene("rod"), restart=out)  # the scene given again, as `--restart OUT SCENE`
    assert done.status == "complete"
    assert_same_datasets(references["rod"], out)
    with pytest.raises(ValueError, match="a restart continues its own file"):
        traverse.run(restart=out, output=tmp_path / "other.h5")
    with pytest.raises(traverse.SceneError, match="cannot read it as a traverse output file"):
        traverse.run(restart=tmp_path / "missing.h5")
    # The executable's message for the same file.
    r = run_exe("run", "--restart", str(tmp_path / "missing.h5"))
    assert r.returncode == 2 and "cannot read it as a traverse output file" in r.stderr
    with pytest.raises(TypeError, match="a scene is needed"):
        traverse.run()


def test_ctrl_c_stops_a_run_restartably_and_gives_the_handler_back(tmp_path, references):
    before = signal.getsignal(signal.SIGINT)
    out = tmp_path / "interrupted.h5"

    def press_ctrl_c(step):
        if step.step == 2 * EVERY:
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt) as e:
        traverse.run(scene("rod"), output=out, every=EVERY, callback=press_ctrl_c)
    assert e.value.output == str(out)
    assert any("stopped by SIGINT" in note for note in e.value.__notes__), e.value.__notes__
    status = traverse.read(out, allow_incomplete=True).status
    assert status.startswith("interrupted at t = ") and "SIGINT" in status, status
    assert signal.getsignal(signal.SIGINT) is before
    traverse.run(restart=out)
    assert_same_datasets(references["rod"], out)
    # The interpreter's own handler answers the next Ctrl-C.
    with pytest.raises(KeyboardInterrupt):
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(1.0)


def test_ctrl_c_stops_a_sweep_and_the_interrupted_case_restarts(tmp_path):
    directory = tmp_path / "sweep"
    # Cases of about a second each, so that case 1 is still running when the signal comes.
    base = traverse.Scene.load(scene_path("default.yaml"), overrides=["mesh.ds=0.004"])
    speeds = [1.0, 1.5, 2.0, 2.5, 3.0, 3.5]

    def press_ctrl_c_when_case_1_starts():
        first = directory / "case_0001.h5"
        for _ in range(12000):
            if first.exists():
                break
            time.sleep(0.01)
        os.kill(os.getpid(), signal.SIGINT)

    watcher = threading.Thread(target=press_ctrl_c_when_case_1_starts)
    watcher.start()
    try:
        with pytest.raises(KeyboardInterrupt) as e:
            traverse.sweep(base, vary={"loads.F.speed": speeds}, summary="midspan.y:min", output=directory)
    finally:
        watcher.join()
    table = e.value.table
    statuses = [row["status"] for row in table]
    assert statuses[0] == "complete", statuses
    k = statuses.index("interrupted")
    assert all(s == "complete" for s in statuses[:k]) and all(s == "not run" for s in statuses[k + 1:]), statuses
    assert os.path.exists(directory / "index.csv")
    # The interrupted case continues to the file its uninterrupted run writes.
    traverse.run(restart=table[k]["output"])
    reference = base.copy()
    reference["loads.F.speed"] = speeds[k]
    ref = traverse.run(reference, output=tmp_path / "reference.h5")
    n = assert_same_datasets(ref.path, table[k]["output"])
    print(f"sweep stopped in case {k} ({statuses}); restarted: {n} datasets equal bit for bit")
