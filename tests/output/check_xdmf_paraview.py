"""Opens the sample run's XDMF sidecar with ParaView's XDMF reader (run by pvbatch) and
checks the time steps, the polyline, the points (from the field "r") and the node arrays.
Usage: pvbatch check_xdmf_paraview.py SAMPLE.xmf     (exit status 1 on any failure)
"""
import sys

from paraview import servermanager
from paraview.simple import XDMFReader

NODES, STEPS = 7, 5
passed, failed = 0, 0


def check(cond, what):
    global passed, failed
    if cond:
        passed += 1
    else:
        failed += 1
        print("FAILED: " + what)


def field(f, step, node, comp):  # tests/output/sample_run.hpp
    return 1000.0 * f + 10.0 * step + 0.5 * node + 0.0625 * comp


reader = XDMFReader(FileNames=[sys.argv[1]])
reader.UpdatePipelineInformation()
times = list(reader.TimestepValues)
check(times == [0.25 * k for k in range(STEPS)], "time steps %s" % times)
for step in range(STEPS):
    reader.UpdatePipeline(0.25 * step)
    d = servermanager.Fetch(reader)
    if d.IsA("vtkMultiBlockDataSet"):
        d = d.GetBlock(0)
    check(d.GetNumberOfPoints() == NODES, "points at step %d" % step)
    check(d.GetNumberOfCells() == NODES - 1, "polyline segments at step %d" % step)
    pts = [d.GetPoints().GetPoint(i) for i in range(d.GetNumberOfPoints())]
    check(pts == [tuple(field(1, step, i, c) for c in range(3)) for i in range(NODES)],
          "points = field r at step %d" % step)
    pd = d.GetPointData()
    names = sorted(pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays()))
    want = sorted(["w", "r"] + ["strain_" + c for c in ("g1", "g2", "g3", "k1", "k2", "k3")])
    check(names == want, "arrays %s" % names)
    w = pd.GetArray("w")
    check(w is not None and [w.GetValue(i) for i in range(NODES)] ==
          [field(0, step, i, 0) for i in range(NODES)], "w at step %d" % step)
    k2 = pd.GetArray("strain_k2")
    check(k2 is not None and [k2.GetValue(i) for i in range(NODES)] ==
          [field(2, step, i, 4) for i in range(NODES)], "strain_k2 at step %d" % step)
print("%d passed, %d failed" % (passed, failed))
sys.exit(0 if failed == 0 else 1)
