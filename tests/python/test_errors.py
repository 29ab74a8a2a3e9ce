"""The module's errors carry the executable's messages: a value --set refuses, a scene file
that cannot be read, and a run whose numerics fail (RunError, the partial file readable)."""


import h5py
import pytest

import traverse
from conftest import exe_run, run_exe, scene_path

DEFAULT = scene_path("default.yaml")

BAD_SETS = {
    "negative_density": ("rod.density", -1500.0, "rod.density=-1500.0"),
    "unknown_key": ("rod.densty", 1500, "rod.densty=1500"),
    "word_for_number": ("loads.F.speed", "fast", "loads.F.speed=fast"),
    "unknown_end_type": ("ends.left.type", "glued", "ends.left.type=glued"),
    "not_yaml": ("mesh.ds", "[0.1", "mesh.ds=[0.1"),
}


def cli_message(*args):
    """What `traverse check ARGS` prints when it refuses the scene (exit 2)."""
    r = run_exe("check", *args)
    assert r.returncode == 2, f"the executable accepted {args}: {r.stdout[:200]}"
    return r.stderr.strip()


@pytest.mark.parametrize("case", sorted(BAD_SETS))
def test_set_refused_with_the_cli_message(case):
    key, value, cli = BAD_SETS[case]
    scene = traverse.Scene.load(DEFAULT)
    with pytest.raises(traverse.SceneError) as e:
        scene.set(key, value)
    print(f"{case}: {e.value}")
    assert isinstance(e.value, ValueError)
    assert cli_message(DEFAULT, "--set", cli) == f"traverse: bad scene: {e.value}"
    # The refused value is not kept: the scene still reads and runs as before.
    assert scene.overrides == ()
    assert scene["rod.density"] == 1500


def test_item_assignment_is_set():
    scene = traverse.Scene.load(DEFAULT)
    with pytest.raises(traverse.SceneError) as e:
        scene["rod.density"] = -1.0
    assert cli_message(DEFAULT, "--set", "rod.density=-1.0") == f"traverse: bad scene: {e.value}"


def test_bad_file_refused_with_the_cli_message(tmp_path):
    missing = str(tmp_path / "missing.yaml")
    with pytest.raises(traverse.SceneError) as e:
        traverse.Scene.load(missing)
    assert cli_message(missing) == f"traverse: bad scene: {e.value}"
    # A located message: the file, and the line of the bad value.
    bad = tmp_path / "bad.yaml"
    bad.write_text(open(DEFAULT).read().replace("density: 1500", "density: -3"))
    with pytest.raises(traverse.SceneError) as e:
        traverse.Scene.load(str(bad))
    msg = str(e.value)
    line = 1 + open(bad).read().split("\n").index("  density: -3")
    assert str(bad) in msg and f":{line}" in msg and "density" in msg, msg
    assert cli_message(str(bad)) == f"traverse: bad scene: {msg}"


def test_numerical_failure_raises_run_error_with_a_readable_partial_file(tmp_path):
    # RK4 far above its stability limit for ten modes of the cantilever: the numerics fail
    # in a time step (the executable's exit code 3), after some steps were written.
    path = scene_path("beam", "cantilever.yaml")
    sets = ["beam.modes=10", "time.dt=1e-3", "loads.mass.speed=5"]
    cli_out = str(tmp_path / "cli.h5")
    r = exe_run(path, cli_out, sets, code=3)

    out = str(tmp_path / "module.h5")
    with pytest.raises(traverse.RunError) as e:
        traverse.run(traverse.Scene.load(path, overrides=sets), output=out)
    print(f"RunError: {e.value}")
    assert isinstance(e.value, RuntimeError)
    assert r.stderr.strip() == f"traverse: numerics failed: {e.value}"
    assert e.value.output == out
    with pytest.raises(traverse.IncompleteOutputError):
        traverse.read(out)
    partial = traverse.read(out, allow_incomplete=True)
    assert partial.status.startswith("failed")
    assert partial.steps_written >= 1 and partial.time.shape == (partial.steps_written,)
    with h5py.File(cli_out, "r") as f:
        assert partial.status == f.attrs["status"].decode() if isinstance(f.attrs["status"], bytes) else f.attrs["status"]
        assert partial.steps_written == int(f.attrs["steps_written"])
    # The process is still good for another run.
    ok = traverse.run(traverse.Scene.load(path))
    assert ok.status == "complete"
