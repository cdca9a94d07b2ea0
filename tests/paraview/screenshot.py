"""The picture of docs/paraview.md, taken with pvpython under xvfb-run:
    xvfb-run -a pvpython screenshot.py PLUGIN MODEL.vtp BOX.hbox OUT.png
The error field coloured by the product's perceptible scale (PerceptibleColour, Map Scalars off),
the boxes of the .hbox file as outlines."""
import sys

from paraview.simple import (ColorBy, GetActiveViewOrCreate, LoadPlugin, OpenDataFile, ResetCamera, SaveScreenshot,
                             Show, XMLPolyDataReader)

plugin, model_vtp, box, out = sys.argv[1:5]
LoadPlugin(plugin, remote=False, ns=globals())  # defines HapticBoxErrorField here
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1000, 800]
view.Background = [1, 1, 1]
view.OrientationAxesVisibility = 0
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass
model = XMLPolyDataReader(FileName=[model_vtp])
field = HapticBoxErrorField(Input=model, BoxFile=box, ProbesPerPoint=4)
shown = Show(field, view)
ColorBy(shown, ("POINTS", "PerceptibleColour"))
shown.MapScalars = 0
boxes = OpenDataFile(box)
outlines = Show(boxes, view)
ColorBy(outlines, None)
outlines.AmbientColor = outlines.DiffuseColor = [0.15, 0.3, 0.8]
outlines.LineWidth = 1.5
view.CameraPosition = [0, 0, 1]
view.CameraViewUp = [0, 1, 0]
ResetCamera(view)
view.CameraPosition = [p for p in view.CameraPosition]
SaveScreenshot(out, view, ImageResolution=[1000, 800])
print(f"screenshot: {out}")
