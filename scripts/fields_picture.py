# Renders the README's particle picture (docs/img/fields_cylinder.png) from a job's snapshot
# series (particles.pvd, docs/fields.md) with ParaView's pvpython: the last time step, fluid
# particles coloured by |v| / U, the cylinder's wall particles in grey, the wake in view.
# The picture's job: case cylinder_free_stream, scheme wcsph_tvf, Re = 100, D_over_dx = 10,
# t_end = 40, riemann_dissipation = "none", tvf = "limited", output_interval = 5 (a study with
# those [params]; about 4 min of CPU). Then, on a machine without a display:
#   xvfb-run -a pvpython scripts/fields_picture.py results/<study>/<key>/particles.pvd out.png
# (retry when it aborts with "bad X server connection": docs/fields.md), and 256 colours:
#   /usr/bin/python3 -c "from PIL import Image; Image.open('out.png').convert('RGB').quantize(256,
#     method=Image.Quantize.FASTOCTREE).save('docs/img/fields_cylinder.png', optimize=True)"
import sys
from paraview.simple import *
pvd, png = sys.argv[1:3]
r = OpenDataFile(pvd)
t = r.TimestepValues[-1]
v = GetActiveViewOrCreate("RenderView")
v.ViewSize = [1000, 520]
v.ViewTime = t
v.OrientationAxesVisibility = 0
v.Background = [1, 1, 1]
try:
    v.UseColorPaletteForBackground = 0
except AttributeError:
    pass
fluid = Threshold(Input=r, Scalars=["POINTS", "kind"], LowerThreshold=0, UpperThreshold=0)
wall = Threshold(Input=r, Scalars=["POINTS", "kind"], LowerThreshold=1, UpperThreshold=2)
fd = Show(fluid, v); fd.SetRepresentationType("Points"); fd.PointSize = 3
ColorBy(fd, ("POINTS", "velocity", "Magnitude"))
lut = GetColorTransferFunction("velocity"); lut.ApplyPreset("Cool to Warm", True); lut.RescaleTransferFunction(0.0, 1.5)
fd.SetScalarBarVisibility(v, True)
bar = GetScalarBar(lut, v); bar.Title = "|v| / U"; bar.ComponentTitle = ""; bar.TitleColor = [0, 0, 0]; bar.LabelColor = [0, 0, 0]
bar.WindowLocation = "Any Location"; bar.Position = [0.86, 0.1]; bar.ScalarBarLength = 0.8
wd = Show(wall, v); wd.SetRepresentationType("Points"); wd.PointSize = 3; ColorBy(wd, None); wd.AmbientColor = wd.DiffuseColor = [0.3, 0.3, 0.3]
text = Text(Text="cylinder_free_stream, Re = 100, D/dx = 10, t = %.0f D/U (ParaView 5.11)" % t)
td = Show(text, v); td.Color = [0, 0, 0]; td.FontSize = 14; td.WindowLocation = "Upper Left Corner"
Render(v)  # the first render resets the camera: set it after
v.CameraPosition = [11.0, 8.0, 40.0]; v.CameraFocalPoint = [11.0, 8.0, 0.0]; v.CameraViewUp = [0, 1, 0]
v.CameraParallelProjection = 1; v.CameraParallelScale = 4.2
Render(v)
SaveScreenshot(png, v, ImageResolution=[1000, 520])
