"""traverse in Python: read, check and run scenes in this process, read their outputs.

    import traverse
    scene = traverse.Scene.load("inputs/default.yaml")
    scene["time.end"] = 0.1                     # as `--set time.end=0.1`
    result = traverse.run(scene)                # rod, beam or statics scenes
    result.time, result.sigma, result.probes["midspan"], result.fields["r"]
    table = traverse.sweep(scene, vary={"loads.F.speed": [1, 2, 3]}, summary="midspan.y:min")
    out = traverse.read("run.h5")               # any output file

Documentation: docs/python.md.
"""

import atexit as _atexit

from . import _traverse
from ._errors import OutputError, RunError, SceneError
from .reader import ContinuationOutput, IncompleteOutputError, TraverseOutput, summary
from .result import BeamStep, MassStep, Result, Step, read, run
from .scene import Scene
from .sweep import SweepTable, sweep

__version__ = _traverse.version
__all__ = ["Scene", "run", "sweep", "SweepTable", "Step", "MassStep", "BeamStep", "read", "Result", "TraverseOutput", "ContinuationOutput",
           "summary", "SceneError", "RunError", "OutputError", "IncompleteOutputError"]

# Kokkos (kept from the first rod run to the last, as in the program) and MPI, when this
# module started it, end at the interpreter's exit. atexit runs its functions in reverse
# order of registration: a package that started MPI before this import (mpi4py) finalises
# it after this.
_atexit.register(_traverse.finish)
