"""Every error path of the module: Python exceptions carrying the product's messages (the file
or value and the cause), ValueErrors that say which array element or argument is bad."""
import os

import numpy as np
import pytest

import hapticbox
from conftest import cli_bake, dataset


@pytest.fixture(scope="module")
def scene(small_model_path):
    return hapticbox.Scene.load(cli_bake(small_model_path, "elephant"))


@pytest.fixture(scope="module")
def model(small_model_path):
    return hapticbox.Model(small_model_path)


def test_a_missing_model_is_an_oserror_naming_it(tmp_path):
    path = str(tmp_path / "nowhere.off")
    with pytest.raises(hapticbox.IoError) as e:
        hapticbox.Model(path)
    assert isinstance(e.value, OSError) and isinstance(e.value, hapticbox.Error)
    assert path in str(e.value) and "no such file" in str(e.value)


def test_a_damaged_model_names_the_file_and_the_cause(tmp_path):
    path = tmp_path / "garbage.off"
    path.write_text("OFF\n3 1 0\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n")
    with pytest.raises(hapticbox.InvalidInput) as e:
        hapticbox.Model(str(path))
    assert isinstance(e.value, ValueError)
    assert str(path) in str(e.value)


def test_an_unknown_extension_is_refused(tmp_path):
    path = tmp_path / "model.xyz"
    path.write_text("1 2 3\n")
    with pytest.raises(hapticbox.Error) as e:
        hapticbox.Model(str(path))
    assert str(path) in str(e.value)


@pytest.mark.parametrize("options, words", [
    ({"unit": "furlong"}, "unknown unit 'furlong'"),
    ({"volume": "iso=abc"}, "--volume"),
    ({"volume": "colour=red"}, "unknown key 'colour'"),
    ({"cad": "chordal-mm=-1"}, "--cad chordal-mm"),
    ({"cad": "accept-lost-faces=maybe"}, "is not on or off"),
])
def test_bad_model_options_say_which(small_model_path, options, words):
    with pytest.raises(hapticbox.InvalidInput) as e:
        hapticbox.Model(small_model_path, **options)
    assert words in str(e.value)


def test_model_options_must_be_text(small_model_path):
    with pytest.raises(TypeError):
        hapticbox.Model(small_model_path, volume=300)


def test_a_file_that_is_no_box_file_is_refused_naming_it(small_model_path, tmp_path):
    with pytest.raises(hapticbox.InvalidInput) as e:
        hapticbox.Scene.load(small_model_path)
    assert small_model_path in str(e.value)
    with pytest.raises(hapticbox.IoError) as e:
        hapticbox.Scene.load(str(tmp_path / "none.hbox"))
    assert "none.hbox" in str(e.value)


def test_a_truncated_box_file_is_refused(scene, tmp_path):
    whole = tmp_path / "whole.hbox"
    scene.save(str(whole))
    cut = tmp_path / "cut.hbox"
    cut.write_bytes(whole.read_bytes()[:200])
    with pytest.raises(hapticbox.Error) as e:
        hapticbox.Scene.load(str(cut))
    assert "cut.hbox" in str(e.value)


def test_saving_where_no_file_can_be_written_names_it(scene, tmp_path):
    with pytest.raises(hapticbox.IoError) as e:
        scene.save(str(tmp_path / "no" / "such" / "dir" / "x.hbox"))
    assert "x.hbox" in str(e.value)


@pytest.mark.parametrize("segments, words", [
    (np.zeros((4, 5), np.float32), "shape (N, 6)"),
    (np.zeros(6, np.float32), "got shape (6,)"),
    (np.zeros((2, 6, 1), np.float32), "got shape (2, 6, 1)"),
    (np.zeros((3, 6), np.int64), "dtype int64"),
    (np.zeros((3, 6), np.complex64), "dtype complex64"),
    (np.array([[0, 0, 1, 0, 0, float("nan")]], np.float32), "segments[0, 5] is NaN"),
    (np.array([[0, 0, 1, 0, 0, 0], [0, float("inf"), 1, 0, 0, 0]], np.float64), "segments[1, 1] is infinite"),
    (np.array([[0, 0, 1e16, 0, 0, 0]], np.float32), "segments[0, 2] is beyond 4e15"),
    ([[0, 0, 1, 0, 0, 0]], "expected a numpy array"),
])
def test_bad_segment_arrays_are_valueerrors_saying_which(scene, model, segments, words):
    for answerer in (scene, hapticbox.Exact(model)):
        with pytest.raises(ValueError) as e:
            answerer.query(segments)
        assert words in str(e.value)


def test_no_segments_is_no_answers(scene):
    answers = scene.query(np.zeros((0, 6), np.float32))
    assert all(len(a) == 0 for a in answers.values())


def test_a_strided_array_is_read_correctly(scene, model):
    rows = np.array([[0, 0, 200, 0, 0, 40]] * 4, np.float32)
    wide = np.zeros((4, 12), np.float32)
    wide[:, ::2] = rows
    assert np.array_equal(scene.query(wide[:, ::2])["force"], scene.query(rows)["force"])


@pytest.mark.parametrize("workspace, words", [
    ("stiffness=-5", "--workspace stiffness"),
    ("mm=80,real-size", "exclude each other"),
    ("depth=3", "unknown key 'depth'"),
])
def test_a_bad_workspace_says_which(scene, workspace, words):
    with pytest.raises(hapticbox.InvalidInput) as e:
        scene.query(np.zeros((1, 6), np.float32), workspace=workspace)
    assert words in str(e.value)


def test_bad_verdict_inputs_say_which(scene):
    answers = scene.query(np.zeros((3, 6), np.float32))
    with pytest.raises(ValueError, match="different probe counts"):
        hapticbox.perceive(answers, scene.query(np.zeros((2, 6), np.float32)))
    with pytest.raises(ValueError, match="no 'force' array"):
        hapticbox.perceive({k: v for k, v in answers.items() if k != "force"}, answers)
    with pytest.raises(ValueError, match="expected a dict"):
        hapticbox.perceive([1, 2], answers)
    with pytest.raises(hapticbox.InvalidInput):
        hapticbox.perceive(answers, answers, perceptual="w=abc")


def test_bad_bake_arguments_say_which(model):
    with pytest.raises(ValueError, match="m: 1 is outside"):
        hapticbox.bake(model, m=1)
    with pytest.raises(ValueError, match="budget belongs to the default bake"):
        hapticbox.bake(model, m=8, budget="felt=0.1")
    with pytest.raises(hapticbox.InvalidInput):
        hapticbox.bake(model, budget="felt=lots")


def test_bad_field_and_eval_arguments_say_which(scene, model):
    with pytest.raises(ValueError, match="probes: 0 is outside"):
        hapticbox.error_field(scene, model, probes=0)
    with pytest.raises(ValueError, match="samples: 0 is outside"):
        hapticbox.evaluate(scene, model, samples=0)


def test_bad_tools_and_poses_say_which(scene):
    with pytest.raises(hapticbox.InvalidInput, match="radius"):
        hapticbox.Tool("sphere,radius-mm=-2")
    with pytest.raises(hapticbox.IoError, match="nowhere.stl"):
        hapticbox.Tool("mesh=/nowhere.stl,points=10")
    tool = hapticbox.Tool("sphere,radius-mm=1,points=20")
    with pytest.raises(ValueError, match=r"\(N, 3\) or \(N, 7\)"):
        tool.answer(scene, np.zeros((2, 4), np.float32))
    with pytest.raises(ValueError, match=r"poses\[1\]: the orientation qw,qx,qy,qz has no length"):
        tool.answer(scene, np.array([[0, 0, 0, 1, 0, 0, 0], [0, 0, 0, 0, 0, 0, 0]], np.float32))
    with pytest.raises(ValueError, match=r"poses\[0, 2\] is NaN"):
        tool.answer(scene, np.array([[0, 0, float("nan")]], np.float32))
