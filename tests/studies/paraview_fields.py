# Opens a job's particle snapshot series (particles.pvd, io/particle_snapshot.hpp) in ParaView's
# pvpython as a user would (OpenDataFile: the reader ParaView picks for the file), checks what
# ParaView sees and renders the last time step to a PNG (issue 16, part 1). Run under an X server
# (xvfb-run -a: pvpython aborts without one). Used by tests/studies/paraview_fields.sh.
#
# Usage: pvpython paraview_fields.py PVD PNG STEPS T_END POINTS FLUID [COLOR]
#   STEPS   number of time steps the series must have
#   T_END   the last time step's value (to 1e-9)
#   POINTS  particles in every snapshot (every kind)
#   FLUID   of them, fluid (kind 0); the rest must be of other kinds (wall, body, buffer)
#   COLOR   point array to colour by (default: velocity magnitude)
# Exit 0 when every check holds; prints one line per check.
import os
import sys

from paraview.simple import (ColorBy, GetActiveViewOrCreate, OpenDataFile, ResetCamera,
                             SaveScreenshot, Show)
from paraview import servermanager

pvd, png, steps, t_end, points, fluid = sys.argv[1:7]
color = sys.argv[7] if len(sys.argv) > 7 else "velocity"
steps, t_end, points, fluid = int(steps), float(t_end), int(points), int(fluid)
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


reader = OpenDataFile(pvd)
check(reader is not None, "ParaView has a reader for " + pvd)
if reader is None:
    sys.exit(1)
check(reader.GetXMLName() == "PVDReader", "the reader is ParaView's PVD reader (" +
      reader.GetXMLName() + ")")
times = list(reader.TimestepValues)
check(len(times) == steps, "%d time steps (expected %d): %s" % (len(times), steps, times))
check(all(b > a for a, b in zip(times, times[1:])), "time steps increase")
check(len(times) > 0 and times[0] == 0.0, "the first time step is the initial state, t = 0")
check(len(times) > 0 and abs(times[-1] - t_end) < 1e-9,
      "the last time step is the final state, t = %.12g (expected %g)" % (times[-1], t_end))

expected_arrays = ["velocity", "pressure", "density", "mass", "volume", "smoothing_length",
                   "kind", "id"]
for t in times:
    reader.UpdatePipeline(t)
    data = servermanager.Fetch(reader)
    pd = data.GetPointData()
    names = [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]
    n = data.GetNumberOfPoints()
    label = "t = %.6g: " % t
    check(n == points, label + "%d points (expected %d)" % (n, points))
    check(data.GetNumberOfCells() == points, label + "one vertex cell per point")
    missing = [a for a in expected_arrays if a not in names]
    check(not missing, label + "arrays %s present (missing: %s)" % (expected_arrays, missing))
    if missing:
        continue
    check(pd.GetArray("velocity").GetNumberOfComponents() == 3, label + "velocity is a 3-vector")
    kind = pd.GetArray("kind")
    n_fluid = sum(1 for i in range(n) if kind.GetValue(i) == 0)
    check(n_fluid == fluid, label + "%d fluid particles (expected %d)" % (n_fluid, fluid))
    ids = pd.GetArray("id")
    check(sorted(int(ids.GetValue(i)) for i in range(n)) == list(range(n)),
          label + "ids are 0..N-1, each once")
    vrange = pd.GetArray("velocity").GetRange(-1)  # magnitude
    if t > 0.0:  # (a smooth start begins at rest)
        check(vrange[1] > 0.0, label + "the flow moves (|v| max %g)" % vrange[1])

# Render the final state, coloured by the chosen array, and check the picture is not blank.
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [800, 600]
view.ViewTime = times[-1] if times else 0.0
view.OrientationAxesVisibility = 0
display = Show(reader, view)
display.SetRepresentationType("Points")
display.PointSize = 3
ColorBy(display, ("POINTS", color, "Magnitude") if color == "velocity" else ("POINTS", color))
display.RescaleTransferFunctionToDataRange(True, False)
display.SetScalarBarVisibility(view, True)
ResetCamera(view)
SaveScreenshot(png, view, ImageResolution=[800, 600])

from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402

img = vtkPNGReader()
img.SetFileName(png)
img.Update()
dims = img.GetOutput().GetDimensions()
check(dims[0] == 800 and dims[1] == 600, "the PNG is 800 x 600 (%s)" % (dims,))
scalars = img.GetOutput().GetPointData().GetScalars()
colours = set()
for i in range(0, scalars.GetNumberOfTuples(), 97):
    colours.add(tuple(int(scalars.GetComponent(i, c)) for c in range(3)))
check(len(colours) > 20, "the PNG shows a coloured field (%d distinct colours sampled)" %
      len(colours))

print("%s: %s" % (pvd, "OK" if not failures else "%d checks failed" % len(failures)), flush=True)
# Leave without ParaView's teardown: every check is done, and on this project's machines closing
# the X connection at exit now and then fails (GLXBadContext), which would turn a pass into an
# abort.
os._exit(1 if failures else 0)
