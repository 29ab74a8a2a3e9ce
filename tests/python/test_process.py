"""MPI in a Python process: started by the module and finalised at the interpreter's exit
(after Kokkos), or, when mpi4py started it, used and left to mpi4py. Each case runs in a
fresh interpreter (MPI starts once per process)."""

import os
import subprocess
import sys

import pytest

from conftest import assert_same_datasets, scene_path

SCENE = scene_path("default.yaml")

# Registered before traverse is imported, so that it runs after traverse's own exit handler:
# reports whether MPI is finalised then (mpi4py imported without starting or ending MPI).
CHECK_AT_EXIT = """
import atexit, sys
def _report():
    import mpi4py
    mpi4py.rc.initialize = mpi4py.rc.finalize = False
    from mpi4py import MPI
    print("finalized at exit:", MPI.Is_finalized(), flush=True)
atexit.register(_report)
"""

RUN = """
import traverse
from traverse import _traverse
scene = traverse.Scene.load({scene!r}, overrides=["mesh.ds=0.05"])
traverse.run(scene, output={out!r})
print("started here:", _traverse.mpi_started_here(), flush=True)
"""


def child(code):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=240)
    assert r.returncode == 0, r.stderr
    return r


def test_module_starts_and_finalises_mpi(tmp_path):
    pytest.importorskip("mpi4py")
    out = str(tmp_path / "alone.h5")
    r = child(CHECK_AT_EXIT + RUN.format(scene=SCENE, out=out))
    assert "started here: True" in r.stdout, r.stdout
    assert "finalized at exit: True" in r.stdout, r.stdout
    assert r.stderr == "", r.stderr  # no complaint of Kokkos or MPI left running


def test_mpi_started_by_mpi4py_is_left_to_it(tmp_path):
    pytest.importorskip("mpi4py")
    alone, shared = str(tmp_path / "alone.h5"), str(tmp_path / "mpi4py.h5")
    child(RUN.format(scene=SCENE, out=alone))
    # mpi4py initialises MPI on import and finalises it at exit, after traverse's handler.
    code = "from mpi4py import MPI\n" + RUN.format(scene=SCENE, out=shared) + \
           "print('still initialized:', MPI.Is_initialized() and not MPI.Is_finalized(), flush=True)\n"
    r = child(code)
    assert "started here: False" in r.stdout, r.stdout
    assert "still initialized: True" in r.stdout, r.stdout
    assert r.stderr == "", r.stderr
    assert_same_datasets(alone, shared)
