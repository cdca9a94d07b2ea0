"""The picture of docs/paraview.md, taken with pvpython under xvfb-run:
    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" pvpython screenshot.py PLUGIN MODEL.vtp BOX.hbox OUT.png
The error field coloured by the product's perceptible scale (PerceptibleColour, Map Scalars off),
the boxes of the .hbox file as outlines."""
import sys

from paraview.simple import (ColorBy, GetActiveViewOrCreate, LoadPlugin, OpenDataFile, Render, SaveScreenshot, Show,
                             XMLPolyDataReader)

plugin, model_vtp, box, out = sys.argv[1:5]
LoadPlugin(plugin, remote=False, ns=globals())  # defines HapticBoxErrorField here
view = GetActiveViewOrCreate("RenderView")
model = XMLPolyDataReader(FileName=[model_vtp])
field = HapticBoxErrorField(Input=model, BoxFile=box, ProbesPerPoint=4)  # noqa: F821
shown = Show(field, view)
ColorBy(shown, ("POINTS", "PerceptibleColour"))
shown.MapScalars = 0
outlines = Show(OpenDataFile(box), view)
ColorBy(outlines, None)
outlines.AmbientColor = outlines.DiffuseColor = [0.15, 0.3, 0.8]
outlines.LineWidth = 1.5
outlines.Opacity = 0.5
view.OrientationAxesVisibility = 0
Render(view)
view.ResetCamera()
view.CameraPosition = [-c for c in view.CameraPosition]  # the front of the model
view.ResetCamera()
view.GetActiveCamera().Zoom(1.5)
SaveScreenshot(out, view, ImageResolution=[1000, 800], OverrideColorPalette="WhiteBackground")
print(f"screenshot: {out}")
