"""The bake, the box file, eval's figures and the error field from Python equal the command
line's: the same scene bytes, the same figures, the same arrays bit for bit."""
import json
import os

import numpy as np
import pytest

import hapticbox
from conftest import cli_bake, dataset, probe_segments, run_cli


def test_the_default_bake_saves_loads_and_answers_alike(small_model_path, tmp_path):
    model = hapticbox.Model(small_model_path)
    scene = hapticbox.bake(model, cache=str(tmp_path / "cache"))
    path = str(tmp_path / "elephant.hbox")
    scene.save(path)
    loaded = hapticbox.Scene.load(path, verify=True)
    assert loaded.path == path
    segments = probe_segments(model, 2000)
    a, b = scene.query(segments), loaded.query(segments)
    for key in a:
        assert np.array_equal(a[key], b[key])
    info = loaded.info()
    assert info["boxes"] >= 1 and info["source_path"] == small_model_path and info["source_hash"] == model.hash
    assert hapticbox.info(path)["boxes"] == info["boxes"]
    # The CLI's default bake of the same model is the same file.
    cli_box = tmp_path / "cli.hbox"
    run_cli("bake", small_model_path, "-o", cli_box, "--cache", tmp_path / "cache")
    assert cli_box.read_bytes() == open(path, "rb").read()


def test_one_sampling_bakes_one_raw_box(small_model_path):
    model = hapticbox.Model(small_model_path)
    scene = hapticbox.bake(model, m=8, n=4, cache=False)
    assert scene.info()["boxes"] == 1
    answers = scene.query(probe_segments(model, 500))
    assert answers["contact"].any()


def test_model_facts(small_model_path):
    model = hapticbox.Model(small_model_path)
    info = model.info()
    assert info["format"] == "OFF" and info["triangles"] == model.triangle_count == len(model.triangles)
    assert model.vertices.shape == (model.vertex_count, 3)
    assert abs(info["diagonal"] - model.diagonal) < 1e-3
    assert hapticbox.info(small_model_path)["triangles"] == model.triangle_count


def test_evaluate_gives_evals_figures(small_model_path):
    box = cli_bake(small_model_path, "elephant")
    r = run_cli("eval", box, small_model_path, "--samples", 3000, "--seed", 3, "--json")
    cli = json.loads(r.stdout)
    mine = hapticbox.evaluate(hapticbox.Scene.load(box), hapticbox.Model(small_model_path), samples=3000, seed=3)
    for key in ("perceptible", "contact_agreement", "force_error_median", "force_error_p95", "angle_error_p99_deg",
                "force_difference_n", "light_touch", "workspace", "exact_contacts"):
        assert mine[key] == cli[key], key


def test_a_volume_reads_with_the_cli_options():
    ct = dataset("generated/femur_ct.nii.gz")
    model = hapticbox.Model(ct, volume="iso=300")
    assert model.triangle_count > 1000
    assert model.info()["kind"] == "volume"


def read_vtp(path):
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def point_arrays(polydata):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    pd = polydata.GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}


@pytest.mark.parametrize("even", [0, 2000])
def test_the_error_field_equals_hapticbox_fields_arrays(small_model_path, tmp_path, even):
    box = cli_bake(small_model_path, "elephant")
    out = tmp_path / "field.vtp"
    args = ["field", box, small_model_path, "-o", out, "--probes", 2, "--seed", 5]
    if even:
        args += ["--even", even]
    run_cli(*args)
    field = hapticbox.error_field(hapticbox.Scene.load(box), hapticbox.Model(small_model_path), probes=2, seed=5,
                                  even=even)
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    assert isinstance(field, vtkPolyData)
    cli, mine = point_arrays(read_vtp(out)), point_arrays(field)
    assert set(cli) == set(mine) and "PerceptibleRatio" in mine
    for name in cli:
        a, b = np.ascontiguousarray(mine[name]), np.ascontiguousarray(cli[name])
        assert a.dtype == b.dtype and a.shape == b.shape, name
        assert np.array_equal(a.view(np.uint8), b.view(np.uint8)), f"{name} differs from hapticbox field"
    assert field.GetNumberOfPoints() == read_vtp(out).GetNumberOfPoints()


@pytest.mark.parametrize("relative, options", [
    ("generated/reference_solid.step", {}),
    ("generated/elephant.gltf", {}),
    ("generated/elephant.glb", {}),
    ("generated/elephant.3mf", {}),
    ("generated/elephant.dae", {}),
    ("generated/elephant.fbx", {}),
    ("generated/ct_phantom.mha", {"volume": "iso=300"}),
    ("generated/ct_phantom.nrrd", {"volume": "iso=300"}),
    ("generated/femur_ct_dicom", {"volume": "iso=300"}),
    ("meshes/elephant.off", {"unit": "cm"}),
])
def test_every_format_reads_as_the_command_line_reads_it(relative, options):
    path = dataset(relative)
    model = hapticbox.Model(path, **options)
    args = ["info", path, "--json"] + [f"--{k}={v}" for k, v in options.items()]
    cli = json.loads(run_cli(*args).stdout)
    assert model.triangle_count == cli["triangles"] > 0
    assert model.diagonal == pytest.approx(cli["diagonal"], rel=1e-6)
    assert model.hash == hapticbox.Model(path, **options).hash
