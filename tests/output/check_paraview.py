"""Run by pvbatch (tests/output/run_paraview.py): opens each sidecar with ParaView's default
route (OpenDataFile -> Xdmf3ReaderS) and with the legacy XDMFReader, checks the time steps,
the structure's points, cells and arrays and the load's point at one step against the
values from HDF5, and renders the rod's sidecar to a PNG whose pixels must show the rod.
Usage: pvbatch check_paraview.py EXPECTED.json     (exit status 1 on any failure)
"""
import json
import os
import sys

from paraview import servermanager
from paraview.simple import (ColorBy, Delete, GetActiveViewOrCreate, OpenDataFile, Render, ResetCamera,
                             SaveScreenshot, Show, XDMFReader)
from vtkmodules.vtkIOImage import vtkPNGReader

passed, failed = 0, 0


def check(cond, what):
    global passed, failed
    if cond:
        passed += 1
    else:
        failed += 1
        print("FAILED: " + what)


def blocks(data):
    it = data.NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        yield it.GetCurrentDataObject()
        it.GoToNextItem()


def check_reader(reader, run, label):
    reader.UpdatePipelineInformation()
    times = list(reader.TimestepValues)
    check(times == run["times"], f"{label}: time steps ({len(times)} vs {len(run['times'])})")
    k = run["step"]
    reader.UpdatePipeline(run["times"][k])
    data = servermanager.Fetch(reader)
    grids = list(blocks(data))
    structure = [g for g in grids if g.GetNumberOfPoints() == run["nodes"]]
    loads = [g for g in grids if g.GetNumberOfPoints() == 1]
    check(len(grids) == 2 and len(structure) == 1 and len(loads) == 1,
          f"{label}: one structure and one loads grid ({[g.GetNumberOfPoints() for g in grids]} points)")
    if len(structure) != 1:
        return
    g = structure[0]
    n = run["nodes"]
    check(g.GetNumberOfPoints() == n, f"{label}: {g.GetNumberOfPoints()} points, expected {n}")
    check(g.GetNumberOfCells() == n - 1, f"{label}: {g.GetNumberOfCells()} cells, expected {n - 1}")
    pts = [list(g.GetPoint(i)) for i in range(g.GetNumberOfPoints())]
    check(pts == run["points"], f"{label}: points at step {k} equal the geometry in HDF5")
    pd = g.GetPointData()
    names = sorted(pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays()))
    check(names == sorted(run["arrays"]), f"{label}: arrays {names} vs {sorted(run['arrays'])}")
    for name, want in run["arrays"].items():
        a = pd.GetArray(name)
        if a is None:
            continue
        got = [a.GetTuple(i) for i in range(a.GetNumberOfTuples())]
        got = [list(t) if len(t) > 1 else t[0] for t in got]
        check(got == want, f"{label}: array {name} at step {k}")
    if len(loads) == 1:
        lp = loads[0]
        p = lp.GetPoint(0)
        check(max(abs(p[c] - run["load"][c]) for c in range(3)) < 1e-12, f"{label}: load at {p}, expected {run['load']}")
        # The same arrays as the structure (ParaView colours a multiblock only by an array every
        # block has), with the values at the load.
        lpd = lp.GetPointData()
        lnames = sorted(lpd.GetArrayName(i) for i in range(lpd.GetNumberOfArrays()))
        check(lnames == names, f"{label}: the load's arrays {lnames} are the structure's")
        for name, want in run["load_arrays"].items():
            a = lpd.GetArray(name)
            got = list(a.GetTuple(0)) if a is not None else None
            want = want if isinstance(want, list) else [want]
            check(got is not None and max(abs(x - y) for x, y in zip(got, want)) < 1e-12,
                  f"{label}: {name} at the load: {got}, expected {want}")
    print(f"{label}: {len(times)} time steps, {g.GetNumberOfPoints()} points, arrays {names}")


def render(reader, run, png):
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = [800, 500]
    view.OrientationAxesVisibility = 0
    view.Background = [1.0, 1.0, 1.0]
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    view.ViewTime = run["times"][-1]
    reader.UpdatePipeline(run["times"][-1])
    display = Show(reader, view)
    display.LineWidth = 4.0
    display.PointSize = 12.0
    display.AmbientColor = display.DiffuseColor = [0.1, 0.1, 0.6]  # dark on white, whatever the colouring
    ColorBy(display, ("POINTS", "s"))
    display.RescaleTransferFunctionToDataRange(True)
    # Look along the axis in which the structure is thinnest (a planar rod lies in a plane).
    b = reader.GetDataInformation().GetBounds()
    extent = [b[1] - b[0], b[3] - b[2], b[5] - b[4]]
    normal = extent.index(min(extent))
    up = 1 if normal != 1 else 2
    centre = [0.5 * (b[2 * c] + b[2 * c + 1]) for c in range(3)]
    view.CameraFocalPoint = centre
    view.CameraPosition = [centre[c] + (1.0 if c == normal else 0.0) for c in range(3)]
    view.CameraViewUp = [1.0 if c == up else 0.0 for c in range(3)]
    ResetCamera(view)
    Render(view)
    SaveScreenshot(png, view, ImageResolution=[800, 500])
    r = vtkPNGReader()
    r.SetFileName(png)
    r.Update()
    img = r.GetOutput()
    w, h, _ = img.GetDimensions()
    sc = img.GetPointData().GetScalars()
    ink = [(i % w, i // w) for i in range(w * h) if sum(sc.GetTuple(i)[:3]) < 3 * 250]
    colours = {sc.GetTuple(i)[:3] for i in range(w * h) if sum(sc.GetTuple(i)[:3]) < 3 * 250}
    frac = len(ink) / float(w * h)
    check(len(colours) >= 20, f"{png}: {len(colours)} colours: the rod is not coloured by s")
    check(os.path.getsize(png) > 0, "screenshot written")
    check(0.001 < frac < 0.5, f"{png}: {100 * frac:.2f} % of the pixels are not background (a blank or full frame?)")
    if ink:
        xs = [p[0] for p in ink]
        check(max(xs) - min(xs) > 0.5 * w, f"{png}: the drawn rod spans {max(xs) - min(xs)} of {w} pixels across")
    print(f"{png}: {len(ink)} of {w * h} pixels drawn ({100 * frac:.2f} %), {len(colours)} colours")


spec = json.load(open(sys.argv[1]))
for run in spec["runs"]:
    name = os.path.basename(run["xmf"])
    reader = OpenDataFile(run["xmf"])
    check(reader is not None and reader.GetXMLName() == "Xdmf3ReaderS",
          f"{name}: OpenDataFile chose {reader.GetXMLName() if reader else None}, expected Xdmf3ReaderS")
    if reader is not None:
        check_reader(reader, run, name + " (OpenDataFile)")
        if run is spec["runs"][0] and spec.get("render", True):
            render(reader, run, os.path.join(spec["out"], "rod.png"))
        Delete(reader)
    legacy = XDMFReader(FileNames=[run["xmf"]])
    check_reader(legacy, run, name + " (XDMFReader)")
    Delete(legacy)
print(f"{passed} passed, {failed} failed")
sys.stdout.flush()
# os._exit: ParaView 5.11's teardown under Xvfb raises an X error (GLXBadContext in
# glXMakeCurrent) whose default handler exits with 1 after the checks are done.
os._exit(0 if failed == 0 else 1)
