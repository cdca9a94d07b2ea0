"""HapticBox from Python: bake a model into haptic boxes, answer probe segments in batches,
and judge the answers against exact Embree in what a hand can feel.

    import numpy as np, hapticbox
    model = hapticbox.Model("datasets/data/meshes/armadillo.off")
    scene = hapticbox.bake(model)                      # the default bake (hapticbox bake)
    segs = np.array([[0, 0, 200, 0, 0, 40]], np.float32)  # handle then tip, model units
    box = scene.query(segs)                            # dict of arrays; force in N
    exact = hapticbox.Exact(model).query(segs)
    felt = hapticbox.perceive(exact, box)["perceptible"]

Units: lengths in model units (millimetres once loaded), forces in newtons at the workspace
(the model's diagonal fitted to 80 mm at the device, 1500 N/m; `workspace=` changes it).
docs/python.md has the whole API.
"""
from ._core import (  # noqa: F401  (the compiled part: pybind11 over the core)
    Error,
    Exact,
    InvalidInput,
    IoError,
    Model,
    Scene,
    Tool,
    __version__,
    bake,
    evaluate,
    perceive,
    sample_probes,
)
from . import _core

__all__ = ["Error", "IoError", "InvalidInput", "Model", "Scene", "Exact", "Tool", "bake", "sample_probes", "perceive", "evaluate",
           "error_field", "polydata", "info", "__version__"]


def error_field(scene, model, *, probes=1, seed=1, even=0, workspace=None, perceptual="nominal"):
    """The error field of `scene` against exact Embree on `model`, as `hapticbox field BOX MODEL`
    computes it (the same VTK filter, the same arrays), returned as a vtkPolyData of VTK's own
    Python (python3-vtk9; `pyvista.wrap(field)` makes it a PyVista mesh).

    probes: probes aimed at each point (default 1); seed: their seed (default 1); even: sample
    this many points evenly by area instead of the vertices (0: the vertices).
    workspace / perceptual: as Scene.query and perceive.
    Point arrays: ExactForce, ApproxForce (N, 3 components), AbsoluteForceError (N),
    RelativeForceError (fraction, NaN where no probe is in contact on both sides),
    DirectionError (degrees, NaN likewise), ContactDisagreement, ExactContactFraction,
    PerceptibleRatio (the difference over what a hand can feel: above 1 it is felt; the active
    scalars), PerceptibleFraction, Normals. Field data: units and provenance.
    """
    return _to_vtk(_core._error_field(scene, model, probes=probes, seed=seed, even=even, workspace=workspace,
                                      perceptual=perceptual))


def _to_vtk(handle):
    from vtkmodules.vtkCommonDataModel import vtkPolyData

    wrapped = vtkPolyData(handle.pointer_text)  # the C++ object, seen from VTK's Python
    data = vtkPolyData()
    data.ShallowCopy(wrapped)  # owned by Python: the handle may go now
    return data


def polydata(model):
    """The model's triangles as a vtkPolyData of VTK's own Python (points in mm, triangle cells
    in the model's order, point data "Normals": the shaded vertex normals the queries use).
    Written as .vtp it reads back as the same mesh in HapticBox, ParaView and PyVista."""
    return _to_vtk(_core._model_polydata(model))


def info(path, **model_options):
    """What `hapticbox info FILE` tells of a model or a .hbox file, as a dict: a box file's
    boxes, route, source and workspace (Scene.info), or a model's format, counts, bounds, unit,
    defects and warnings (Model.info; keyword options as Model's)."""
    try:
        with open(path, "rb") as f:
            magic = f.read(8)
    except OSError:
        magic = b""  # the loader names the file and the cause
    if magic == b"HBOXFILE":
        return Scene.load(path).info()
    return Model(path, **model_options).info()
