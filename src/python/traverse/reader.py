"""Read traverse output files (HDF5, layout in docs/output.md). Needs numpy and h5py only.

The reader of the package traverse (``traverse.read``); postprocessing/traverse_io.py is the
same module for scripts that run without the package (it loads this file by its path), so
this file imports nothing of the package and nothing compiled.

    out = load("run.h5")                           # refuses runs that did not complete
    out.time, out.sigma, out.s                     # numpy arrays, trimmed to steps_written
    out.probes["midspan_w"]                        # (steps,) or (steps, components)
    out.field("r")                                 # (steps, nodes, components)
    out.field("r", step=-1)                        # (nodes, components), last written step
    out.units("midspan_w"), out.description("r"), out.components("reaction")
    out.attrs["status"], out.attrs["scene"]

    out = load("crashed.h5", allow_incomplete=True)   # running / failed runs

    cases = sweep_index("sweep_dir")               # rows of a `traverse sweep` index (dicts)
    paths = sweep_outputs("sweep_dir")             # its case files in case order, all complete

Command line: ``python3 traverse_io.py FILE [--check]`` prints a summary (``--check``: exit
status 2 unless the run's status is "complete").
"""

import csv
import os
import sys

import h5py
import numpy as np

__all__ = ["load", "TraverseOutput", "IncompleteOutputError", "summary", "sweep_index", "sweep_outputs",
           "ContinuationOutput", "load_continuation", "read"]

SUPPORTED_FORMAT = 1


class IncompleteOutputError(RuntimeError):
    """The file's status is not "complete" (the run is still going, was killed, or failed)."""


def _text(value):
    if isinstance(value, bytes):
        return value.decode("utf-8", errors="replace")
    if isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in "SO":
        return _text(value[()])
    return value


def _open(path):
    # A running or killed writer may leave the file in a state file locking objects to.
    try:
        return h5py.File(path, "r", locking=False)
    except (TypeError, ValueError):
        return h5py.File(path, "r")
    except OSError as e:
        # The file is open in this process already, with file locking (HDF5 refuses to open
        # it again with other locking flags): open it as it is open.
        if "locking flag" not in str(e):
            raise
        return h5py.File(path, "r")


class TraverseOutput:
    """Contents of one traverse output file, trimmed to the completed steps.

    Attributes: path, attrs (dict of root attributes, e.g. status, model, scene, command_line,
    traverse_version, steps_written), status, steps_written, time [s] (steps,), sigma [m]
    ((steps,) for one moving load, else (steps, loads)), s [m] (nodes,), probes (dict name ->
    array), probe_names, field_names, events (list of dicts time [s], position [m], load, reason:
    the /events table of runs with a coupled mass, else empty), restart (dict name -> array,
    empty if none valid), restart_time [s] or None.
    """

    def __init__(self, path):
        self.path = str(path)
        self._meta = {}
        with _open(self.path) as f:
            self.attrs = {k: _text(v) for k, v in f.attrs.items()}
            if "steps_written" not in self.attrs or "status" not in self.attrs:
                raise ValueError(f"{self.path} is not a traverse output file "
                                 "(no steps_written/status root attributes)")
            fmt = int(self.attrs.get("traverse_output_format", SUPPORTED_FORMAT))
            if fmt > SUPPORTED_FORMAT:
                raise ValueError(f"{self.path} has output format {fmt}; this traverse_io.py "
                                 f"reads format {SUPPORTED_FORMAT}")
            self.steps_written = int(self.attrs["steps_written"])
            self.status = str(self.attrs["status"])
            n = self.steps_written
            self.time = self._series(f, "time", n)
            self.sigma = self._series(f, "sigma", n)
            self.s = np.asarray(f["mesh/s"][...])
            self._remember(f, "s", "mesh/s")
            self.probes = {}
            for name in sorted(f.get("probes", {})):
                self.probes[name] = self._series(f, f"probes/{name}", n)
            self.probe_names = list(self.probes)
            self.field_names = sorted(f.get("fields", {}))
            self.field_shapes = {}
            for name in self.field_names:
                d = f[f"fields/{name}"]
                self._remember(f, f"fields/{name}", f"fields/{name}")
                self.field_shapes[name] = (n,) + tuple(d.shape[1:])
            self.events = []
            g = f.get("events")
            if g is not None and "time" in g:
                loads = _text(g.attrs.get("loads", "")).split(",")
                reasons = _text(g.attrs.get("reasons", "")).split(",")
                for k, (t, p) in enumerate(zip(g["time"][...], g["position"][...])):
                    self.events.append({"time": float(t), "position": float(p),
                                        "load": loads[k] if k < len(loads) else "",
                                        "reason": reasons[k] if k < len(reasons) else ""})
            self.restart, self.restart_time = {}, None
            g = f.get("restart")
            if g is not None and int(g.attrs.get("valid", 0)) == 1:
                self.restart_time = float(g.attrs["time"])
                self.restart = {k: np.asarray(g[k][...]) for k in g}

    def _remember(self, f, key, dataset):
        a = f[dataset].attrs
        comps = _text(a.get("components", ""))
        self._meta[key] = {
            "units": _text(a.get("units", "")),
            "description": _text(a.get("description", "")),
            "components": comps.split(",") if comps else [],
        }

    def _series(self, f, dataset, n):
        d = f[dataset]
        if d.shape[0] < n:
            raise ValueError(f"{self.path}:/{dataset} has {d.shape[0]} rows but "
                             f"steps_written = {n}")
        self._remember(f, dataset, dataset)
        return np.asarray(d[:n])

    def _key(self, name):
        for key in (name, f"probes/{name}", f"fields/{name}"):
            if key in self._meta:
                return key
        raise KeyError(f"{self.path}: no time series, probe or field named {name!r}")

    def units(self, name):
        """Units of "time", "sigma", "s", a probe or a field ("probes/x" or "fields/x"
        when a probe and a field share a name; probes win otherwise)."""
        return self._meta[self._key(name)]["units"]

    def description(self, name):
        return self._meta[self._key(name)]["description"]

    def components(self, name):
        """Component names (list of str, empty if none were given)."""
        return list(self._meta[self._key(name)]["components"])

    def field(self, name, step=None):
        """Field values: (steps, nodes, components), or (nodes, components) for one step
        (negative steps count from the last written one)."""
        if name not in self.field_shapes:
            raise KeyError(f"{self.path}: no field {name!r} (fields: {self.field_names})")
        n = self.steps_written
        with _open(self.path) as f:
            d = f[f"fields/{name}"]
            if step is None:
                return np.asarray(d[:n])
            k = step + n if step < 0 else step
            if not 0 <= k < n:
                raise IndexError(f"step {step} not written (steps_written = {n})")
            return np.asarray(d[k])

    def __repr__(self):
        return (f"TraverseOutput({self.path!r}, status={self.status!r}, "
                f"steps_written={self.steps_written})")


def load(path, allow_incomplete=False):
    """Reads a traverse output file. Raises IncompleteOutputError if its status is not
    "complete" unless allow_incomplete=True (then everything up to steps_written is
    returned, which is all the data a running, killed or failed run completed)."""
    out = TraverseOutput(path)
    if out.status != "complete" and not allow_incomplete:
        raise IncompleteOutputError(
            f"{out.path}: run status is {out.status!r} ({out.steps_written} steps written), "
            "not 'complete'; pass allow_incomplete=True to read the written steps anyway")
    return out


class ContinuationOutput:
    """Contents of one continuation (statics) output file, trimmed to the points written
    (layout: docs/output.md, "Continuation files").

    Attributes: path, attrs (root attributes; kind = "continuation"), status, points_written,
    s [m] (nodes,), parameter (the continued parameter's name), continuation (dict name ->
    (points,) array: the parameter, each probe, unstable_modes, critical_eigenvalue, branch),
    bifurcations (dict name -> (n,) array: type as str, branch, located, the parameter and the
    probes), bifurcation_states (list of dicts r, R, kappa, n), states (dict name -> dict r,
    R, kappa, n; "final" is the run's last state).
    """

    def __init__(self, path):
        self.path = str(path)
        self._units = {}
        with _open(self.path) as f:
            self.attrs = {k: _text(v) for k, v in f.attrs.items()}
            if self.attrs.get("kind") != "continuation" or "points_written" not in self.attrs:
                raise ValueError(f"{self.path} is not a traverse continuation output "
                                 "(no kind = continuation / points_written root attributes)")
            self.status = str(self.attrs.get("status", ""))
            n = self.points_written = int(self.attrs["points_written"])
            self.s = np.asarray(f["mesh/s"][...]).reshape(-1)
            self.continuation, self.parameter = {}, None
            for name, d in f.get("continuation", {}).items():
                self.continuation[name] = np.asarray(d[:n])
                self._units[name] = _text(d.attrs.get("units", ""))
                if _text(d.attrs.get("description", "")) == "the continued parameter":
                    self.parameter = name
            self.bifurcations, self.bifurcation_states = {}, []
            g = f.get("bifurcations", {})
            for name in g:
                if isinstance(g[name], h5py.Dataset):
                    v = np.asarray(g[name][()])
                    self.bifurcations[name] = [_text(x) for x in v] if v.dtype.kind in "SO" else v
            k = 0
            while f"state_{k}" in g:
                self.bifurcation_states.append({a: np.asarray(b[...]) for a, b in g[f"state_{k}"].items()})
                k += 1
            self.states = {name: {a: np.asarray(b[...]) for a, b in grp.items()}
                           for name, grp in f.get("states", {}).items()}

    def units(self, name):
        """Units of a dataset of /continuation ("" when none are given)."""
        return self._units[name]

    def __repr__(self):
        return (f"ContinuationOutput({self.path!r}, status={self.status!r}, "
                f"points_written={self.points_written})")


def load_continuation(path, allow_incomplete=False):
    """Reads a continuation output file; IncompleteOutputError if the run did not complete,
    unless allow_incomplete=True."""
    out = ContinuationOutput(path)
    if out.status != "complete" and not allow_incomplete:
        raise IncompleteOutputError(
            f"{out.path}: run status is {out.status!r} ({out.points_written} points written), "
            "not 'complete'; pass allow_incomplete=True to read the written points anyway")
    return out


def read(path, allow_incomplete=False):
    """Any traverse output file: a ContinuationOutput for a continuation (statics) run, else
    a TraverseOutput (load)."""
    with _open(str(path)) as f:
        kind = _text(f.attrs.get("kind", ""))
    if kind == "continuation":
        return load_continuation(path, allow_incomplete)
    return load(path, allow_incomplete)


def command(exe, verb, ranks=1):
    """The start of a `traverse VERB ...` command line: under `mpirun -n RANKS` when ranks > 1
    (a sweep's cases then spread over the ranks: docs/sweeps.md)."""
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-n", str(ranks)] if ranks > 1 else []
    return cmd + [exe, verb]


def sweep_index(directory):
    """The rows of DIRECTORY/index.csv written by `traverse sweep` (docs/sweeps.md), in case
    order: dicts from the column names (case, each varied key, output, status, exit_code,
    wall_s, the --summary column, message) to their text."""
    with open(os.path.join(directory, "index.csv"), newline="") as f:
        return sorted(csv.DictReader(f), key=lambda row: int(row["case"]))


def sweep_outputs(directory):
    """The output file of every case of a sweep, in case order; raises IncompleteOutputError
    naming the cases that did not complete."""
    rows = sweep_index(directory)
    bad = [f"case {r['case']}: {r['status']} {r['message']}".strip() for r in rows if r["status"] != "complete"]
    if bad:
        raise IncompleteOutputError(f"{directory}: not every case completed: " + "; ".join(bad))
    return [os.path.join(directory, r["output"]) for r in rows]


def _exit_with(message, status=2):
    print(message, file=sys.stderr)
    sys.exit(status)


def load_for_plot(path, model, script):
    """load(path) for a figure script: exits with a clear message (status 2) when the file
    cannot be read, is not a time-series output of `model` ("rod" or "beam") or did not
    complete."""
    try:
        out = load(path)
    except IncompleteOutputError as e:
        _exit_with(f"{script}: {e}")
    except (OSError, ValueError, KeyError) as e:
        _exit_with(f"{script}: cannot read {path} as a traverse time-series output: {e}")
    have = out.attrs.get("model", "")
    if have != model:
        other = {"rod": "plot_rod.py", "beam": "plot_beam.py"}.get(have, "")
        _exit_with(f"{script}: {path} is a {have or 'unknown'} run, not a {model} run"
                         + (f"; draw it with {other}" if other else ""))
    return out


def require_probe(out, name, script):
    """Exits with a clear message (status 2) when `out` has no probe `name`."""
    if name not in out.probes:
        _exit_with(f"{script}: {out.path} has no probe '{name}' (its probes: "
                         f"{', '.join(out.probe_names) or 'none'}); choose one with --probe")


def scene_title(out):
    """The `title:` of the validated scene stored in the file ("" when there is none). It is
    the scene author's text: after --set it may no longer describe the run (run_title does)."""
    for line in str(out.attrs.get("scene", "")).splitlines():
        if line.startswith("title:"):
            return line.split(":", 1)[1].strip().strip("'\"")
    return ""


def _scalar(text):
    text = text.strip()
    if len(text) >= 2 and text[0] == text[-1] and text[0] in "'\"":
        return text[1:-1]
    if text.startswith("[") and text.endswith("]"):
        return [_scalar(t) for t in text[1:-1].split(",") if t.strip()]
    if text == "{}":
        return {}
    try:
        return float(text)
    except ValueError:
        return text


def scene_values(out):
    """The validated scene stored in the file (root attribute `scene`: every key the run used,
    after --set, defaults filled in) as nested dicts; numbers as floats, flow lists as lists.
    It is block YAML written by traverse, read here without a YAML module."""
    root = {}
    stack = [(-1, root)]
    for line in str(_text(out.attrs.get("scene", ""))).splitlines():
        if not line.strip() or line.lstrip().startswith("#") or ":" not in line:
            continue
        indent = len(line) - len(line.lstrip())
        key, _, rest = line.strip().partition(":")
        while stack[-1][0] >= indent:
            stack.pop()
        parent = stack[-1][1]
        if rest.strip():
            parent[key.strip().strip("'\"")] = _scalar(rest)
        else:
            parent[key.strip().strip("'\"")] = child = {}
            stack.append((indent, child))
    return root


def _g(v):
    return f"{v:g}" if isinstance(v, float) else str(v)


def load_text(name, load):
    """A moving load as the run used it, e.g. "'F': moving_force 2 N at 3.63 m/s"."""
    what = [str(load.get("type", "load")).replace("_", " ")]
    if "force" in load:
        what.append(f"{_g(load['force'])} N")
    elif "axle_load" in load:
        what.append(f"{_g(load['axle_load'])} N per axle")
    if "mass_fraction" in load:
        what.append(f"p = {_g(load['mass_fraction'])} (mass fraction)")
    elif "mass" in load:
        what.append(f"{_g(load['mass'])} kg")
    text = f"'{name}': " + " ".join(what)
    if isinstance(load.get("speed"), float):
        start = " starting" if load.get("type") == "coupled_mass" else ""  # it moves by itself
        text += f"{start} at {load['speed']:.3g} m/s"
    if isinstance(load.get("acceleration"), float) and load["acceleration"] != 0.0:
        text += f", {load['acceleration']:.3g} m/s^2"
    return text


def run_title(out):
    """A title from the values the run used (its stored scene), not the scene's `title:`:
    the model, its length and supports or ends, and each load, e.g. "beam 2 m, clamped-free,
    3 modes; 'mass': moving_mass p = 0.2 (mass fraction) at 50 m/s"."""
    sc = scene_values(out)
    model = str(sc.get("model", _text(out.attrs.get("model", ""))))
    body = sc.get(model, {}) if isinstance(sc.get(model), dict) else {}
    parts = [f"{model} {_g(body['length'])} m" if "length" in body else model]
    if model == "beam":
        parts[0] += f", {body.get('supports', '')}, {_g(body.get('modes', ''))} modes".replace(".0 modes", " modes")
    elif isinstance(sc.get("ends"), dict):
        ends = sc["ends"]
        parts[0] += ", ends " + "-".join(str(ends.get(e, {}).get("type", "?")) for e in ("left", "right"))
    loads = sc.get("loads", {}) if isinstance(sc.get("loads"), dict) else {}
    parts += [load_text(n, l) for n, l in loads.items() if isinstance(l, dict)]
    cont = sc.get("continuation")
    if isinstance(cont, dict) and "parameter" in cont:
        parts.append(f"{cont['parameter']} from {_g(cont.get('start', '?'))} to {_g(cont.get('stop', '?'))}")
    return "; ".join(parts)


def wrapped(text, width=90):
    """`text` broken into lines of at most `width` characters (for titles)."""
    import textwrap

    return "\n".join(textwrap.wrap(text, width)) or text


def exaggeration(displacement, length):
    """The factor that draws a deformed shape visibly: 1 when the largest displacement from
    the undeformed structure is at least a tenth of its length; else the largest 1-2-5 number
    that brings it to at most a fifth of the length. Shapes drawn with equal axes otherwise
    show a sag of a millimetre on a metre as a straight line."""
    d = float(np.nanmax(np.abs(displacement))) if np.size(displacement) else 0.0
    if not np.isfinite(d) or d == 0.0 or d >= length / 10.0:
        return 1.0
    want = 0.2 * length / d
    decade = 10.0 ** np.floor(np.log10(want))
    return max(f * decade for f in (1.0, 2.0, 5.0) if f * decade <= want)


def first_load_sigma(out):
    """Position of the first moving load at each output step."""
    import numpy as np

    s = np.asarray(out.sigma)
    return s if s.ndim == 1 else s[:, 0]


def _range(a):
    return f"{a.min():.6g} .. {a.max():.6g}" if a.size else "(empty)"


def summary(out):
    """A human-readable multi-line summary of a TraverseOutput."""
    a = out.attrs
    lines = [
        f"file:          {out.path}",
        f"status:        {out.status}",
        f"model:         {a.get('model', '')}",
        f"traverse:      {a.get('traverse_version', '')}",
        f"scene file:    {a.get('scene_file', '')} ({len(a.get('scene', ''))} characters of scene text)",
        f"command line:  {a.get('command_line', '')}",
        f"steps written: {out.steps_written}",
        f"time [{out.units('time')}]:      {_range(out.time)}",
        f"sigma [{out.units('sigma')}]:     {_range(out.sigma)}  shape {out.sigma.shape}",
        f"nodes:         {out.s.size}, s [{out.units('s')}] {_range(out.s)}",
        f"probes ({len(out.probes)}):",
    ]
    for name, v in out.probes.items():
        comps = ",".join(out.components(f"probes/{name}"))
        lines.append(f"  {name:<20} [{out.units(f'probes/{name}')}] shape {v.shape}"
                     f"{' (' + comps + ')' if comps else ''}  {out.description(f'probes/{name}')}")
    lines.append(f"fields ({len(out.field_names)}):")
    for name in out.field_names:
        comps = ",".join(out.components(f"fields/{name}"))
        lines.append(f"  {name:<20} [{out.units(f'fields/{name}')}] shape "
                     f"{out.field_shapes[name]} ({comps})  {out.description(f'fields/{name}')}")
    if "time_steps" in out.attrs:
        lines.append(f"solves:        {out.attrs['time_steps']} time steps"
                     + "".join(f", {out.attrs[k]} {k.replace('_', ' ')}" for k in ("newton_iterations", "coupling_iterations")
                               if k in out.attrs))
    for e in out.events:
        lines.append(f"event:         {e['reason']} of '{e['load']}' at t = {e['time']:.9g} s, sigma = {e['position']:.6g} m")
    if out.restart_time is not None:
        lines.append(f"restart:       t = {out.restart_time:.6g} s, arrays "
                     + ", ".join(f"{k}{v.shape}" for k, v in out.restart.items()))
    return "\n".join(lines)


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    check = "--check" in argv
    files = [x for x in argv if x != "--check"]
    if len(files) != 1 or any(x.startswith("-") for x in files):
        print("usage: traverse_io.py FILE [--check]", file=sys.stderr)
        return 1
    try:
        out = load(files[0], allow_incomplete=True)
    except (OSError, ValueError, KeyError) as e:
        print(f"traverse_io: cannot read {files[0]}: {e}", file=sys.stderr)
        return 1
    print(summary(out))
    if out.status != "complete":
        print(f"warning: the run did not complete (status {out.status!r})", file=sys.stderr)
        if check:
            return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
