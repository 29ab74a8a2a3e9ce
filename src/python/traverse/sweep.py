"""traverse.sweep: a scene run once per case of a product of values, in this process (or over
the ranks of an MPI launch), as `traverse sweep` runs it."""

import csv
import io
import math
import os
import re
import shutil

from . import _traverse
from .result import _catches_signals, _interrupted
from .scene import Scene, _value_text

# A number as the index writes a varied value that is one (YAML's decimal and exponent forms).
_INT = re.compile(r"[-+]?\d+")
_FLOAT = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


def _value(text):
    """A varied value of the index: an int or a float when the text is a number, else the text."""
    if _INT.fullmatch(text):
        return int(text)
    if _FLOAT.fullmatch(text):
        return float(text)
    return text


def _values_text(values):
    """The text after `KEY=` of --vary: a str as the command line takes it (values and ranges
    a:b:step, comma-separated), else each value of the list written as --set writes it."""
    if isinstance(values, str):
        return values
    if hasattr(values, "tolist") and hasattr(values, "ndim"):
        values = values.tolist()
    try:
        items = list(values)
    except TypeError:
        items = [values]
    return ",".join(_value_text(v) for v in items)


def _vary_options(vary):
    """The ("--vary" | "--with", "KEY=VALUES") options of the dict `vary`, in its order. A key
    that is a tuple of keys varies them together (the first as --vary, the others as --with),
    its value a list of tuples, one value per key."""
    if not isinstance(vary, dict) or not vary:
        raise TypeError("traverse.sweep: vary must be a non-empty dict {key: values}, "
                        "e.g. {'loads.F.speed': [1, 2, 3]}")
    options = []
    for key, values in vary.items():
        if isinstance(key, tuple):
            rows = None if isinstance(values, str) else list(values)
            if not rows or any(not isinstance(row, (tuple, list)) or len(row) != len(key) for row in rows):
                raise TypeError(f"traverse.sweep: the keys {key} vary together: expected a list of tuples of "
                                f"{len(key)} values, one per key, found {values!r}")
            for i, k in enumerate(key):
                options.append(("--vary" if i == 0 else "--with", f"{k}={_values_text([row[i] for row in rows])}"))
        else:
            options.append(("--vary", f"{key}={_values_text(values)}"))
    return options


class SweepTable(list):
    """The cases of a sweep, in case order: one dict per case with the columns of the sweep's
    index.csv (docs/sweeps.md), as Python values:

    - "case" (int), each varied key (its value: an int or a float when it is a number, else
      the text given to --set),
    - "output" (the case's file; None when it has none or the directory was removed),
    - "status" (str), "exit_code" (int), "wall_s" (float),
    - each summary text, e.g. "midspan.y:min" (float; NaN where the case did not complete),
    - "message" (str, empty for a complete case).

    `directory` is the sweep's directory (None when it was temporary and is gone), `exit_code`
    the sweep's (0 when every case completed), `keys` the varied keys and `summaries` the
    summary texts. `column(name)` is a column as a list, or a numpy array of floats for a
    numeric one.
    """

    def __init__(self, rows, directory, exit_code, keys, summaries):
        super().__init__(rows)
        self.directory = directory
        self.exit_code = exit_code
        self.keys = tuple(keys)
        self.summaries = tuple(summaries)

    def column(self, name):
        values = [row[name] for row in self]
        if values and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            import numpy as np

            return np.array(values, dtype=float)
        return values

    def __repr__(self):
        complete = sum(row["status"] == "complete" for row in self)
        return (f"traverse.SweepTable({len(self)} cases, {complete} complete, keys={list(self.keys)}, "
                f"summaries={list(self.summaries)}, directory={self.directory!r})")


def _table(index, directory, code, keys, summaries, more, kept):
    rows = []
    for raw in csv.DictReader(io.StringIO(index)):
        k = int(raw["case"])
        row = {"case": k}
        for key in keys:
            row[key] = _value(raw[key])
        row["output"] = os.path.join(directory, raw["output"]) if kept and raw["output"] else None
        row["status"] = raw["status"]
        row["exit_code"] = int(raw["exit_code"])
        row["wall_s"] = float(raw["wall_s"])
        for i, text in enumerate(summaries):
            if i == 0:
                row[text] = float(raw[text]) if raw[text] else math.nan
            else:
                row[text] = more[i - 1][k]
        row["message"] = raw["message"]
        rows.append(row)
    rows.sort(key=lambda r: r["case"])
    return SweepTable(rows, directory if kept else None, code, keys, summaries)


def sweep(scene, vary, summary=None, output=None, overwrite=False, quiet=True):
    """Runs `scene` (a Scene or a scene file's path) once per case of the product of `vary`,
    as `traverse sweep SCENE -o OUTPUT --vary KEY=VALUES ... [--summary S] [--overwrite] [-q]`
    does, in this process (under mpirun with every rank calling it: the cases spread over the
    ranks of MPI_COMM_WORLD). Returns a SweepTable: one dict per case, the numbers of the
    index.csv the sweep writes.

    `vary`: {key: values}, the first key outermost (the last varies fastest); values a list
    (each written as Scene.set writes it) or a str as --vary takes it ("0.5:5:0.5", "1,2,4");
    a tuple of keys varies them together ({("loads.F.speed", "time.end"): [(1, 4), (2, 2)]}).
    `summary`: a --summary text "PROBE[.x|.y|.z]:REDUCTION" or a list of them (the first is
    the index's column, each one a column of the table). `output`: the sweep's directory
    (index.csv, case_NNNN.h5); None: a temporary directory removed before returning. A scene
    of text (Scene.from_yaml, from_dict) is written to OUTPUT/scene.yaml for the cases.

    Raises SceneError for a bad scene, key, value or summary (the command line's message),
    OutputError for a directory that cannot be written or files it would replace without
    overwrite=True. A case that fails does not raise: its row says how it ended.
    """
    if not isinstance(scene, Scene):
        scene = Scene.load(scene)
    summaries = [] if summary is None else [summary] if isinstance(summary, str) else list(summary)
    args = _traverse.SweepArgs()
    args.vary = _vary_options(vary)
    args.summaries = summaries
    args.directory = "" if output is None else os.fspath(output)
    args.overwrite = bool(overwrite)
    args.quiet = bool(quiet)
    args.invocation = (f"traverse.sweep({scene.name!r}" + "".join(f", --set {o}" for o in scene.overrides) +
                       "".join(f", {opt} {text}" for opt, text in args.vary) +
                       (f", --summary {summaries[0]}" if summaries else "") + ")")
    args.signals = _catches_signals()
    code, index, directory, more, rank, sig = _traverse.sweep(scene._src(), args)
    keys = [text.split("=", 1)[0] for _, text in args.vary]
    table = _table(index, directory, code, keys, summaries, more, kept=output is not None)
    if output is None and rank == 0:
        shutil.rmtree(directory, ignore_errors=True)
    if sig:
        done = sum(row["status"] == "complete" for row in table)
        e = _interrupted(f"traverse.sweep: interrupted after {done} of {len(table)} cases complete", sig, None,
                         "traverse.sweep")
        e.table = table
        e.add_note("traverse.sweep: the cases run so far are in the exception's `table`"
                   + (f" and in {os.path.join(directory, 'index.csv')}; the interrupted case continues with "
                      "traverse.run(restart=its output)" if output is not None else ""))
        raise e
    return table
