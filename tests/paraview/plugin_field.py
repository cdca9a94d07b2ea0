"""Run by ParaView's pvpython (run_plugin_test.sh): loads the HapticBox plugin, reads the model
(.vtp), runs HapticBox Error Field with the box file and checks every array against
`hapticbox field`'s .vtp bit for bit; then the .hbox reader, the probe, the decomposition.
Usage: pvpython plugin_field.py PLUGIN MODEL.vtp BOX.hbox CLI_FIELD.vtp"""
import sys

import numpy as np
from paraview import servermanager
from paraview.simple import LoadPlugin, OpenDataFile, XMLPolyDataReader
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

plugin, model_vtp, box, cli_vtp = sys.argv[1:5]
LoadPlugin(plugin, remote=False, ns=globals())  # defines HapticBoxErrorField, HapticBoxProbe, ... here

model = XMLPolyDataReader(FileName=[model_vtp])
field = HapticBoxErrorField(Input=model, BoxFile=box)  # noqa: F821 (the plugin's)
field.UpdatePipeline()
mine = servermanager.Fetch(field)

reader = vtkXMLPolyDataReader()
reader.SetFileName(cli_vtp)
reader.Update()
cli = reader.GetOutput()


def arrays(polydata):
    pd = polydata.GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}


a, b = arrays(mine), arrays(cli)
missing = set(b) - set(a)
assert not missing, f"arrays of hapticbox field missing in ParaView's output: {missing}"
assert "PerceptibleColour" in a, "no PerceptibleColour"
assert mine.GetNumberOfPoints() == cli.GetNumberOfPoints()
for name in sorted(b):
    x, y = np.ascontiguousarray(a[name]), np.ascontiguousarray(b[name])
    assert x.dtype == y.dtype and x.shape == y.shape, f"{name}: {x.dtype}{x.shape} against {y.dtype}{y.shape}"
    assert np.array_equal(x.view(np.uint8), y.view(np.uint8)), f"{name} differs from hapticbox field"
    print(f"plugin_field: {name} {x.shape}: bit for bit as hapticbox field")

boxes = OpenDataFile(box)
boxes.UpdatePipeline()
outlines = servermanager.Fetch(boxes)
assert outlines.GetNumberOfCells() > 0 and outlines.GetNumberOfCells() % 12 == 0, "the .hbox reader shows no boxes"
print(f"plugin_field: {box}: {outlines.GetNumberOfCells() // 12} box(es)")

bounds = mine.GetBounds()
centre = [(bounds[0] + bounds[1]) / 2, (bounds[2] + bounds[3]) / 2, (bounds[4] + bounds[5]) / 2]
probe = HapticBoxProbe(  # noqa: F821 (the plugin's)
    Input=model, BoxFile=box, Point1=[centre[0], centre[1], bounds[5] * 1.5], Point2=centre)
probe.UpdatePipeline()
answer = servermanager.Fetch(probe)
verdict = answer.GetFieldData().GetAbstractArray("Perceptible").GetValue(0)
exact_n = answer.GetFieldData().GetArray("ExactForceN").GetValue(0)
box_n = answer.GetFieldData().GetArray("BoxForceN").GetValue(0)
print(f"plugin_field: probe {exact_n:.4g} N exact, {box_n:.4g} N box, perceptible: {verdict}")
assert verdict in ("none", "magnitude", "direction", "contact", "magnitude+direction")

pieces = HapticBoxDecomposition(Input=model)  # noqa: F821 (the plugin's)
pieces.UpdatePipeline()
ids = vtk_to_numpy(servermanager.Fetch(pieces).GetCellData().GetArray("PieceId"))
print(f"plugin_field: decomposition: {len(np.unique(ids))} piece(s)")
assert len(ids) > 0
baked_file = box.replace(".hbox", "_paraview.hbox")
bake = HapticBoxBake(Input=pieces, OutputFile=baked_file)  # noqa: F821 (the plugin's)
bake.UpdatePipeline()
baked = servermanager.Fetch(bake)
assert baked.GetNumberOfCells() == 12 * len(np.unique(ids)), "one box a piece of the decomposition"
reread = OpenDataFile(baked_file)
reread.UpdatePipeline()
assert servermanager.Fetch(reread).GetNumberOfCells() == baked.GetNumberOfCells()
print(f"plugin_field: bake: {baked.GetNumberOfCells() // 12} box(es), saved as {baked_file}")
print("plugin_field: OK")
