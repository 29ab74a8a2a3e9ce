#!/usr/bin/env python3
"""Read traverse output files (HDF5, layout in docs/output.md). Needs numpy and h5py only.

    import traverse_io
    out = traverse_io.load("run.h5")              # refuses runs that did not complete
    out.time, out.sigma, out.s                     # numpy arrays, trimmed to steps_written
    out.probes["midspan_w"]                        # (steps,) or (steps, components)
    out.field("r")                                 # (steps, nodes, components)
    out.field("r", step=-1)                        # (nodes, components), last written step
    out.units("midspan_w"), out.description("r"), out.components("reaction")
    out.attrs["status"], out.attrs["scene"]

    out = traverse_io.load("crashed.h5", allow_incomplete=True)   # running / failed runs

    cases = traverse_io.sweep_index("sweep_dir")  # rows of a `traverse sweep` index (dicts)
    paths = traverse_io.sweep_outputs("sweep_dir")  # its case files in case order, all complete

Command line: ``python3 traverse_io.py FILE [--check]`` prints a summary (``--check``: exit
status 2 unless the run's status is "complete").

The code is the reader of the Python package traverse (src/python/traverse/reader.py, also
``traverse.read``). This module is that reader: the package's when the package is importable
(so that both name the same classes, e.g. IncompleteOutputError), else the file itself, loaded
by its path in this source tree (it needs neither the package nor its compiled part).
"""

import importlib.util
import os
import sys


def _reader():
    try:
        from traverse import reader  # the built or installed package (docs/python.md)

        return reader
    except ImportError:
        pass
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "src", "python", "traverse", "reader.py")
    spec = importlib.util.spec_from_file_location("_traverse_io_reader", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_impl = _reader()
globals().update({k: v for k, v in vars(_impl).items() if not (k.startswith("__") and k.endswith("__"))})
__all__ = list(_impl.__all__)

if __name__ == "__main__":
    sys.exit(_impl.main())
