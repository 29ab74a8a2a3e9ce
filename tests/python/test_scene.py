"""traverse.Scene: the complete scene of `traverse check`, overrides as --set, scenes from
YAML text and from dicts."""

import yaml
import pytest

import traverse
from conftest import run_exe, scene_path

DEFAULT = scene_path("default.yaml")


def cli_complete_scene(*args):
    """The complete scene `traverse check ARGS` prints (its first line is the plan)."""
    r = run_exe("check", *args)
    assert r.returncode == 0, r.stderr
    first, _, rest = r.stdout.partition("\n")
    assert first.startswith("# ") and "valid" in first, first
    return yaml.safe_load(rest)


def test_check_is_the_cli_check():
    scene = traverse.Scene.load(DEFAULT)
    complete = scene.check()
    assert complete == cli_complete_scene(DEFAULT)
    # Defaults filled in: keys the file does not give are there.
    assert "scheme" in complete and "solver" in complete, sorted(complete)
    # describe(): the same scene with every key documented in comments.
    text = scene.describe()
    assert yaml.safe_load(text) == complete
    assert sum("#" in line for line in text.splitlines()) > len(complete), "the keys are documented"


@pytest.mark.parametrize("scene_file", ["default.yaml", "beam/cantilever.yaml", "statics/euler_buckling.yaml"])
def test_check_of_other_models(scene_file):
    assert traverse.Scene.load(scene_path(scene_file)).check() == cli_complete_scene(scene_path(scene_file))


def test_set_is_the_cli_set():
    scene = traverse.Scene.load(DEFAULT)
    scene["loads.F.speed"] = 3.0
    scene.set("mesh.ds", 0.02).set("ends.right", {"type": "pinned"})
    assert scene.overrides == ("loads.F.speed=3.0", "mesh.ds=0.02", "ends.right={type: pinned}")
    assert scene["loads.F.speed"] == 3.0
    assert scene["mesh.ds"] == 0.02
    assert scene.check() == cli_complete_scene(DEFAULT, "--set", "loads.F.speed=3.0", "--set", "mesh.ds=0.02",
                                               "--set", "ends.right={type: pinned}")
    with pytest.raises(KeyError):
        scene["loads.F.nothing"]


def test_values_of_every_kind_round_trip():
    scene = traverse.Scene.load(DEFAULT)
    speed = 3.63418 / 3.0  # a float whose shortest text has many digits
    scene["loads.F.speed"] = speed
    scene["mesh.ds"] = 1e-2
    scene["ends.right.axis"] = [0, 0, 1]
    # The --set text reads back as the same double; `traverse check` prints 15 digits.
    assert float(scene.overrides[0].partition("=")[2]) == speed
    assert scene["loads.F.speed"] == pytest.approx(speed, rel=1e-14)
    assert scene["ends.right.axis"] == [0.0, 0.0, 1.0]
    with pytest.raises(TypeError):
        scene.set("mesh.ds", object())


def test_from_yaml_and_from_dict_are_the_file():
    text = open(DEFAULT).read()
    from_file = traverse.Scene.load(DEFAULT).check()
    assert traverse.Scene.from_yaml(text).check() == from_file
    assert traverse.Scene.from_dict(yaml.safe_load(text)).check() == from_file


def test_from_dict_errors_are_located():
    d = yaml.safe_load(open(DEFAULT).read())
    d["rod"]["density"] = -1.0
    with pytest.raises(traverse.SceneError) as e:
        traverse.Scene.from_dict(d, name="cable")
    assert "cable" in str(e.value) and "density" in str(e.value), str(e.value)
