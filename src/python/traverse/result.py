"""traverse.run and traverse.read: a scene run in this process, and what it wrote."""

import numbers
import os
import shutil
import signal
import tempfile
import threading

from . import _traverse
from . import reader as _reader
from ._errors import RunError
from .scene import Scene


def read(path, allow_incomplete=False):
    """The output file `path` (any traverse run's): a TraverseOutput (time, sigma, s, probes,
    field(name), attrs, status) for a time-series run, a ContinuationOutput (continuation,
    bifurcations, states, parameter) for a continuation run (docs/output.md). Raises
    IncompleteOutputError when the run did not complete, unless allow_incomplete=True (then
    what was written)."""
    return _reader.read(os.fspath(path), allow_incomplete=allow_incomplete)


class _Fields:
    """result.fields[name]: a field's values at every output step, (steps, nodes, components),
    read from the file when asked for."""

    def __init__(self, out):
        self._out = out

    def __getitem__(self, name):
        return self._out.field(name)

    def __contains__(self, name):
        return name in self._out.field_names

    def __iter__(self):
        return iter(self._out.field_names)

    def __len__(self):
        return len(self._out.field_names)

    def keys(self):
        return list(self._out.field_names)


class MassStep:
    """The coupled or sprung mass of a rod run's Step: `sigma` [m] its position along the rod
    (arc length of the rest shape), `speed` [m/s] sigma'; of a sprung mass also `body` [m] and
    `body_speed` [m/s], the body's displacement and velocity along up (None otherwise)."""

    __slots__ = ("sigma", "speed", "body", "body_speed")

    def __init__(self, sigma, speed, body=None, body_speed=None):
        self.sigma, self.speed, self.body, self.body_speed = sigma, speed, body, body_speed

    def __repr__(self):
        return (f"traverse.MassStep(sigma={self.sigma!r}, speed={self.speed!r}"
                + ("" if self.body is None else f", body={self.body!r}, body_speed={self.body_speed!r}") + ")")


class Step:
    """What a step callback of traverse.run(scene, every=k, callback=f) is given after every
    k-th time step: `t` [s] (the step's time, t_k), `step` (its index k), and the whole rod
    as read-only numpy arrays (copies, the callback may keep them): `r` (nodes, 3) the
    centreline [m] and `directors` (nodes, 3, 3) the rows d1, d2, d3, in fixed components;
    `u`, `omega`, `kappa`, `n` (nodes, 3) in body components, the fields of the same names.
    `mass`: a MassStep in a run with a coupled or sprung mass, else None."""

    __slots__ = ("t", "step", "r", "directors", "u", "omega", "kappa", "n", "mass")

    def __init__(self, t, step, r, directors, u, omega, kappa, n, mass=None):
        self.t, self.step, self.r, self.directors = t, step, r, directors
        self.u, self.omega, self.kappa, self.n = u, omega, kappa, n
        self.mass = mass

    def __repr__(self):
        return (f"traverse.Step(step={self.step}, t={self.t!r}, nodes={self.r.shape[0]}"
                + ("" if self.mass is None else f", mass={self.mass!r}") + ")")


class BeamStep:
    """What a step callback of traverse.run(beam_scene, every=k, callback=f) is given after
    every k-th time step: `t` [s] (the step's time, t_k), `step` (its index k), and the beam
    as read-only numpy arrays (copies, the callback may keep them): `q`, `q_t` (modes,) the
    modal coordinates [m] and their rates [m/s], `x` (nodes,) the output's nodes along the
    beam [m] and `w` (nodes,) the deflection there [m] (positive up: the field `deflection`)."""

    __slots__ = ("t", "step", "q", "q_t", "x", "w")

    def __init__(self, t, step, q, q_t, x, w):
        self.t, self.step, self.q, self.q_t, self.x, self.w = t, step, q, q_t, x, w

    def __repr__(self):
        return f"traverse.BeamStep(step={self.step}, t={self.t!r}, modes={self.q.shape[0]}, nodes={self.x.shape[0]})"


class Result:
    """What one traverse.run wrote: `path` (the HDF5 file), `attrs` (its root attributes),
    `status`, `steps` (output steps, or continuation points, written), `output` (the file
    read: a TraverseOutput or a ContinuationOutput), and

    - of a time-series run (beam, rod): `time` [s], `sigma` [m], `s` [m], `probes[name]`,
      `fields[name]` (numpy arrays, fields read when asked for), `events` (a coupled mass's:
      dicts of time, position, load, reason); a rod run's `attrs` hold its `time_steps` and
      `newton_iterations` (and `coupling_iterations` with a coupled mass);
    - of a continuation run (statics): `continuation[name]` (the parameter, each probe,
      unstable_modes, critical_eigenvalue, branch), `parameter`, `bifurcations`, `states`.

    When run() was given no output path the file lives in a temporary directory that this
    object owns: it is removed with the object or by close(); keep(path) moves it out first.

    `interrupted` is True for a run its step callback stopped: `status` then says where
    ("interrupted at t = ... s (time step k of n, stopped by the step callback); ..."), the
    arrays hold the output steps written until then, and traverse.run(restart=result)
    continues it (or `traverse run --restart PATH`, keep(path) a temporary one first).
    """

    def __init__(self, path, temporary_dir=None, interrupted=False):
        self._tmp = temporary_dir
        self.interrupted = interrupted
        self._read(path)

    def _read(self, path):
        self.path = path
        self.output = read(path, allow_incomplete=self.interrupted)
        self.kind = "continuation" if isinstance(self.output, _reader.ContinuationOutput) else "time_series"
        self.fields = _Fields(self.output) if self.kind == "time_series" else {}

    def _series(self, name):
        if self.kind != "time_series":
            raise AttributeError(f"{self.path} is a continuation run: it has no {name} (see result.continuation)")
        return getattr(self.output, name)

    def _points(self, name):
        if self.kind != "continuation":
            raise AttributeError(f"{self.path} is a time-series run: it has no {name} (see result.time, probes)")
        return getattr(self.output, name)

    time = property(lambda self: self._series("time"))
    sigma = property(lambda self: self._series("sigma"))
    probes = property(lambda self: self._series("probes"))
    events = property(lambda self: self._series("events"))
    continuation = property(lambda self: self._points("continuation"))
    parameter = property(lambda self: self._points("parameter"))
    bifurcations = property(lambda self: self._points("bifurcations"))
    states = property(lambda self: self._points("states"))
    s = property(lambda self: self.output.s)
    attrs = property(lambda self: self.output.attrs)
    status = property(lambda self: self.output.status)
    steps = property(lambda self: self.output.steps_written if self.kind == "time_series" else self.output.points_written)

    def summary(self):
        """The summary `python3 postprocessing/traverse_io.py FILE` prints (time-series runs);
        for a continuation run its points, parameter range and bifurcations."""
        if self.kind == "time_series":
            return _reader.summary(self.output)
        o = self.output
        p = o.continuation.get(o.parameter)
        lines = [f"file:          {self.path}", f"status:        {o.status}", f"points:        {o.points_written}",
                 f"parameter:     {o.parameter}" + (f" {p.min():.6g} .. {p.max():.6g}" if p is not None and p.size else ""),
                 f"bifurcations:  {', '.join(o.bifurcations.get('type', [])) or 'none'}",
                 f"states:        {', '.join(o.states) or 'none'}"]
        return "\n".join(lines)

    def keep(self, path):
        """Moves a temporary output (and its .xmf sidecar) to `path`; the result then refers
        to it and no longer removes it. Returns the new path."""
        path = os.fspath(path)
        if os.path.exists(path):
            raise FileExistsError(f"traverse.Result.keep: {path} exists")
        shutil.move(self.path, path)
        side = os.path.splitext(self.path)[0] + ".xmf"
        if os.path.exists(side):
            shutil.move(side, os.path.splitext(path)[0] + ".xmf")
        self.close()
        self._read(path)
        return path

    def close(self):
        """Removes the temporary directory of an output written without a path (if any)."""
        if self._tmp is not None:
            shutil.rmtree(self._tmp, ignore_errors=True)
            self._tmp = None

    def __del__(self):
        self.close()

    def __repr__(self):
        return f"traverse.Result({self.path!r}, status={self.status!r}, steps={self.steps})"


def _catches_signals():
    # The program's SIGINT/SIGTERM handlers replace the interpreter's for the length of a run
    # only in the main thread (where Python handles signals).
    return threading.current_thread() is threading.main_thread()


def _interrupted(status, sig, output, what):
    """The exception for a run or sweep a signal stopped: KeyboardInterrupt for SIGINT (Ctrl-C),
    RunError for another (SIGTERM); `output` the restartable file (None for a sweep)."""
    try:
        name = signal.Signals(sig).name
    except ValueError:
        name = f"signal {sig}"
    e = KeyboardInterrupt(status) if sig == signal.SIGINT else RunError(status)
    e.output = output
    e.add_note(f"{what}: stopped by {name}" + (f"; continue with traverse.run(restart={output!r})" if output else ""))
    return e


def run(scene=None, output=None, quiet=True, overwrite=False, verbose=False, every=1, callback=None, restart=None):
    """Runs `scene` (a Scene, or the path of a scene file) in this process, as
    `traverse run SCENE -o OUTPUT [--overwrite] [-q]` does, and returns its Result.

    `output`: the HDF5 file to write (and its .xmf sidecar), the same file the program
    writes; None: a file in a temporary directory owned by the Result. MPI starts on the
    first run if nobody started it (one process, or every rank of an MPI launch calling run).

    `restart`: an output file (or the Result) of a run that was stopped (by the step callback,
    Ctrl-C, a kill) or failed: continues it from its last restart point into the same file, as
    `traverse run --restart OUTPUT [SCENE]` does; `scene` None takes the scene stored in the
    file. The Result of a temporary output passes its file on to the new Result.

    `callback`: a function called after every `every`-th time step with a Step for a rod run
    (t, step, r, directors, u, omega, kappa, n, and `mass` for a coupled or sprung mass; on
    rank 0 of an MPI launch, with the whole rod) or a BeamStep for a beam run (t, step, q,
    q_t, x, w). If it returns a false value other than None (False, numpy's False, 0) the run
    stops there as Ctrl-C stops `traverse run`: a restart point, the file marked
    interrupted, and the Result is returned with `interrupted` True.
    If it raises, the run stops the same way and the exception propagates, with a note that
    names the restartable file (a temporary one is then kept). Statics scenes refuse a
    callback (ValueError).

    Ctrl-C (SIGINT; in the main thread) stops the run after the time step in progress, as it
    stops `traverse run`: the restart point is stored, the file marked interrupted (a temporary
    one kept) and KeyboardInterrupt raised, its `output` the file to continue with
    traverse.run(restart=...). SIGTERM does the same and raises RunError. A second Ctrl-C
    ends the process at once, as it does the program.

    Raises SceneError for a scene that only shows as bad when its model is built,
    OutputError for an output path that cannot be written, RunError when the numerics fail
    (its `output` is the partial file).
    """
    tmp = None
    handed = None  # a Result whose file the restart continues: its temporary file passes on once the run ran
    if restart is not None:
        if isinstance(restart, Result):
            handed, restart = restart, restart.path
        restart = os.fspath(restart)
        if output is not None and os.fspath(output) != restart:
            raise ValueError(f"traverse.run: output={os.fspath(output)!r} with restart={restart!r}: a restart "
                             "continues its own file")
        if overwrite:
            raise ValueError(f"traverse.run: overwrite=True with restart={restart!r}: a restart continues the file")
        output = restart
        if scene is not None and not isinstance(scene, Scene):
            scene = Scene.load(scene)
        invocation = f"traverse.run(restart={restart!r}" + ("" if scene is None else f", {scene.name!r}") + "".join(
            f", --set {o}" for o in (scene.overrides if scene is not None else ())) + ")"
    else:
        if scene is None:
            raise TypeError("traverse.run: a scene is needed (a Scene or a scene file's path), or restart=")
        if not isinstance(scene, Scene):
            scene = Scene.load(scene)
        if output is None:
            tmp = tempfile.mkdtemp(prefix="traverse-")
            output = os.path.join(tmp, "run.h5")
        output = os.fspath(output)
        invocation = f"traverse.run({scene.name!r}" + "".join(f", --set {o}" for o in scene.overrides) + ")"
    if callback is not None:
        if not callable(callback):
            raise TypeError(f"traverse.run: callback must be callable, found {type(callback).__name__}")
        if isinstance(every, bool) or not isinstance(every, numbers.Integral) or every < 1:
            raise ValueError(f"traverse.run: every must be a whole number of time steps >= 1, found {every!r}")
    raised = []

    def call(step):
        # None (no return) goes on, any other false value (False, numpy's False, 0) stops the
        # run; what the callback raises stops it too and is raised once it stopped.
        try:
            answer = callback(step)
            return answer is None or bool(answer)
        except BaseException as e:
            raised.append(e)
            return False

    try:
        stopped, sig = _traverse.run(None if scene is None else scene._src(), output, overwrite, quiet, verbose,
                                     invocation, restart is not None, _catches_signals(), int(every),
                                     None if callback is None else call)
    except BaseException as e:
        # A failed run's partial file is the caller's to read: a temporary one is kept
        # (its directory is named in RunError.output); anything else removes the directory.
        if tmp is not None and not (hasattr(e, "output") and e.output):
            shutil.rmtree(tmp, ignore_errors=True)
        raise
    if handed is not None:
        tmp, handed._tmp = handed._tmp, None
    if raised:
        e = raised[0]
        if stopped:
            e.add_note(f"traverse.run: the step callback raised and stopped the run; {output} is restartable ({stopped})")
        else:  # at the last step: nothing was left to stop
            e.add_note(f"traverse.run: the step callback raised after the last step; {output} is complete")
        raise e
    if sig and sig != _traverse.stop_requested:
        raise _interrupted(stopped, sig, output, "traverse.run")
    return Result(output, tmp, interrupted=bool(stopped))
