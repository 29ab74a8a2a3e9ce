"""traverse.sweep against `traverse sweep` of the same build: the table holds the numbers of
the executable's index.csv (values, status, exit code, summary: compared exactly), the case
files are the executable's, and refused keys, values and summaries raise SceneError with the
executable's message."""

import csv
import os

import numpy as np
import pytest

import traverse
from conftest import assert_same_datasets, run_exe, scene_path

DEFAULT = scene_path("default.yaml")
SETS = ["mesh.ds=0.05"]
# Three cases: two runs and a value that is bad input for its case only (recorded, not raised).
SPEEDS = [2, 3.5, "fast"]
SUMMARY = "midspan.y:min"


def exe_sweep(directory, options, summary, sets=SETS):
    """Runs `traverse sweep` (1 rank) into `directory` with `options` (--vary, --with and
    their values); returns its index rows (dicts of text)."""
    args = ["sweep", DEFAULT, "-o", str(directory), "-q", *options]
    for s in sets:
        args += ["--set", s]
    if summary:
        args += ["--summary", summary]
    r = run_exe(*args)
    assert r.returncode in (0, 2), r.stderr  # 2: the case of bad input
    with open(os.path.join(directory, "index.csv"), newline="") as f:
        return list(csv.DictReader(f))


def assert_table_is_index(table, index, keys, summaries):
    """Every row of `table` holds the numbers of the executable's `index` rows, exactly."""
    assert len(table) == len(index)
    for row, ref in zip(table, index):
        assert row["case"] == int(ref["case"])
        for key in keys:
            value = row[key]
            assert str(value) == ref[key] or (isinstance(value, (int, float)) and value == float(ref[key])), (key, value, ref[key])
        assert row["status"] == ref["status"]
        assert row["exit_code"] == int(ref["exit_code"])
        for s in summaries:
            expected = float(ref[s]) if ref[s] else float("nan")
            assert np.array_equal(row[s], expected, equal_nan=True), (s, row[s], ref[s])
        assert row["message"] == ref["message"]
        assert isinstance(row["wall_s"], float)


def test_table_is_the_executables_index(tmp_path):
    exe_dir, py_dir = tmp_path / "exe", tmp_path / "module"
    index = exe_sweep(exe_dir, ["--vary", "loads.F.speed=2,3.5,fast"], SUMMARY)
    scene = traverse.Scene.load(DEFAULT, overrides=SETS)
    table = traverse.sweep(scene, vary={"loads.F.speed": SPEEDS}, summary=SUMMARY, output=py_dir)
    print(table)
    assert_table_is_index(table, index, ["loads.F.speed"], [SUMMARY])
    assert [row["status"] for row in table] == ["complete", "complete", "bad input"]
    assert table.exit_code == 2 and table.directory == str(py_dir)
    assert [row["loads.F.speed"] for row in table] == [2, 3.5, "fast"]  # numbers as numbers
    assert isinstance(table[0]["loads.F.speed"], int) and isinstance(table[1]["loads.F.speed"], float)
    assert table[0][SUMMARY] < 0.0 and table.column(SUMMARY)[:2].tolist() == [table[0][SUMMARY], table[1][SUMMARY]]
    # The files the executable writes: the same index (but for the wall times) and case files.
    with open(py_dir / "index.csv", newline="") as f:
        mine = list(csv.DictReader(f))
    assert [{k: v for k, v in r.items() if k != "wall_s"} for r in mine] == \
           [{k: v for k, v in r.items() if k != "wall_s"} for r in index]
    assert table[2]["output"] is None and table[0]["output"] == str(py_dir / "case_0000.h5")
    for row in table[:2]:
        assert_same_datasets(exe_dir / os.path.basename(row["output"]), row["output"])


def test_temporary_directory_and_scene_text(tmp_path):
    """output=None: the table holds everything and the directory is gone; a scene of text is
    written into the sweep's directory for its cases, and gives the file scene's numbers."""
    exe_dir = tmp_path / "exe"
    index = exe_sweep(exe_dir, ["--vary", "loads.F.speed=1.5,3", "--vary", "loads.F.force=1:2:1"], SUMMARY)
    with open(DEFAULT) as f:
        scene = traverse.Scene.from_yaml(f.read(), overrides=SETS)
    table = traverse.sweep(scene, vary={"loads.F.speed": [1.5, 3], "loads.F.force": "1:2:1"}, summary=SUMMARY)
    assert table.directory is None and all(row["output"] is None for row in table)
    assert_table_is_index(table, index, ["loads.F.speed", "loads.F.force"], [SUMMARY])
    assert [(r["loads.F.speed"], r["loads.F.force"]) for r in table] == [(1.5, 1), (1.5, 2), (3, 1), (3, 2)]
    kept = tmp_path / "kept"
    again = traverse.sweep(scene, vary={"loads.F.speed": [1.5], "loads.F.force": [1]}, summary=SUMMARY, output=kept)
    assert (kept / "scene.yaml").read_text() == scene.yaml
    assert again[0][SUMMARY] == table[0][SUMMARY]


def test_several_summaries_and_keys_varied_together(tmp_path):
    """Each summary of a list is the column `traverse sweep --summary` writes for it; a tuple
    of keys varies them together (--vary and --with)."""
    options = ["--vary", "loads.F.speed=2,3", "--with", "loads.F.force=1,3"]
    first = exe_sweep(tmp_path / "a", options, SUMMARY)
    second = exe_sweep(tmp_path / "b", options, "midspan.x:absmax")
    table = traverse.sweep(traverse.Scene.load(DEFAULT, overrides=SETS),
                           vary={("loads.F.speed", "loads.F.force"): [(2, 1), (3, 3)]},
                           summary=[SUMMARY, "midspan.x:absmax"])
    keys = ["loads.F.speed", "loads.F.force"]
    assert_table_is_index(table, first, keys, [SUMMARY])
    assert_table_is_index(table, second, keys, ["midspan.x:absmax"])


BAD = {
    # name: (vary, summary, the executable's arguments)
    "unknown_key": ({"loads.F.sped": [1, 2]}, None, ["--vary", "loads.F.sped=1,2"]),
    "bad_range": ({"loads.F.speed": "1:2:0"}, None, ["--vary", "loads.F.speed=1:2:0"]),
    "empty_value": ({"loads.F.speed": "1,,2"}, None, ["--vary", "loads.F.speed=1,,2"]),
    "output_file": ({"output.file": ["a.h5"]}, None, ["--vary", "output.file=a.h5"]),
    "bad_reduction": ({"loads.F.speed": [1]}, "midspan.y:peak", ["--vary", "loads.F.speed=1", "--summary", "midspan.y:peak"]),
    "no_component": ({"loads.F.speed": [1]}, "midspan:min", ["--vary", "loads.F.speed=1", "--summary", "midspan:min"]),
    "unknown_probe": ({"loads.F.speed": [1]}, "quarter.y:min", ["--vary", "loads.F.speed=1", "--summary", "quarter.y:min"]),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_refused_with_the_cli_message(tmp_path, case):
    vary, summary, args = BAD[case]
    out = tmp_path / "out"
    with pytest.raises(traverse.SceneError) as e:
        traverse.sweep(traverse.Scene.load(DEFAULT), vary=vary, summary=summary, output=out)
    print(f"{case}: {e.value}")
    r = run_exe("sweep", DEFAULT, "-o", str(tmp_path / "exe"), *args)
    assert r.returncode == 2
    assert r.stderr.strip() == f"traverse: {e.value}\n(see traverse --help)"
    assert not (out / "index.csv").exists()


def test_refused_scene_text_leaves_no_file(tmp_path):
    with open(DEFAULT) as f:
        scene = traverse.Scene.from_yaml(f.read())
    out = tmp_path / "out"
    with pytest.raises(traverse.SceneError, match="loads.F.sped"):
        traverse.sweep(scene, vary={"loads.F.sped": [1]}, output=out)
    assert not (out / "scene.yaml").exists()


def test_existing_index_refused(tmp_path):
    scene = traverse.Scene.load(DEFAULT, overrides=SETS + ["time.end=0.01"])
    traverse.sweep(scene, vary={"loads.F.speed": [1]}, output=tmp_path)
    with pytest.raises(traverse.OutputError, match="index.csv: exists"):
        traverse.sweep(scene, vary={"loads.F.speed": [1]}, output=tmp_path)
    assert traverse.sweep(scene, vary={"loads.F.speed": [1]}, output=tmp_path, overwrite=True).exit_code == 0
