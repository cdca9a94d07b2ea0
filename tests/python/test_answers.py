"""The module answers as the command line does: `hapticbox query --out` on the results models
(armadillo, bumpy sphere, chess piece), bit for bit, the scene's and the exact answers and the
verdict; a million segments in one call, read in place."""
import csv
import os

import numpy as np
import pytest

import hapticbox
from conftest import RESULTS_MODELS, cli_bake, dataset, probe_segments, run_cli

BY_NAMES = {1: "magnitude", 2: "direction", 4: "contact"}


def by_name(bits):
    names = [name for bit, name in BY_NAMES.items() if bits & bit]
    return "+".join(names) if names else "none"


def read_cli_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    def column(*keys):
        return np.array([[np.float32(r[k]) for k in keys] for r in rows], dtype=np.float32)
    def side(prefix):
        return {
            "contact": np.array([r[prefix + "contact"] == "1" for r in rows]),
            "depth": column(prefix + "depth")[:, 0],
            "normal": column(prefix + "nx", prefix + "ny", prefix + "nz"),
            "force": column(prefix + "fx", prefix + "fy", prefix + "fz"),
        }
    return side(""), side("exact_"), [r["perceptible"] for r in rows]


def assert_same_bits(mine, cli, what):
    for key in ("depth", "normal", "force"):
        a, b = np.ascontiguousarray(mine[key]), np.ascontiguousarray(cli[key])
        differ = np.flatnonzero((a.view(np.uint32) != b.view(np.uint32)).reshape(len(a), -1).any(axis=1))
        assert differ.size == 0, f"{what} {key}: {differ.size} rows differ from hapticbox query, first {differ[:5]}"
    assert np.array_equal(mine["contact"], cli["contact"]), f"{what} contact differs"


@pytest.mark.parametrize("name", sorted(RESULTS_MODELS))
def test_answers_equal_the_command_lines_bit_for_bit(name, tmp_path):
    mesh = dataset(RESULTS_MODELS[name])
    box = cli_bake(mesh, name)
    model = hapticbox.Model(mesh)
    segments = probe_segments(model, 3000)
    seg_csv, out_csv = tmp_path / "segments.csv", tmp_path / "answers.csv"
    # Nine significant digits: the CLI reads back exactly these float32 values.
    np.savetxt(seg_csv, segments, fmt="%.9g", delimiter=",", header="sx,sy,sz,ex,ey,ez", comments="")
    run_cli("query", box, "--segments", seg_csv, "--exact", mesh, "--out", out_csv)
    cli_box, cli_exact, cli_felt = read_cli_csv(out_csv)

    scene = hapticbox.Scene.load(box)
    mine_box = scene.query(segments)
    mine_exact = hapticbox.Exact(model).query(segments)
    assert_same_bits(mine_box, cli_box, f"{name} scene")
    assert_same_bits(mine_exact, cli_exact, f"{name} exact")
    verdict = hapticbox.perceive(mine_exact, mine_box)
    assert [by_name(b) for b in verdict["by"]] == cli_felt
    contacts = int(mine_exact["contact"].sum())
    assert 0 < contacts < len(segments), "the probes should both touch and miss"
    # The point lies on the segment at the depth from the tip (model units).
    hit = mine_exact["contact"]
    tips = segments[hit, 3:]
    handles = segments[hit, :3]
    along = (tips - handles) / np.linalg.norm(tips - handles, axis=1, keepdims=True)
    expected = tips - along * mine_exact["depth"][hit, None]
    assert np.allclose(mine_exact["point"][hit], expected, atol=1e-3 * model.diagonal)


def test_a_million_segments_in_one_call_read_in_place():
    mesh = dataset(RESULTS_MODELS["armadillo"])
    scene = hapticbox.Scene.load(cli_bake(mesh, "armadillo"))
    model = hapticbox.Model(mesh)
    segments = probe_segments(model, 1_000_000, seed=11)
    answers = scene.query(segments)
    assert answers["contact"].shape == (1_000_000,) and answers["contact"].dtype == np.bool_
    assert answers["depth"].shape == (1_000_000,) and answers["depth"].dtype == np.float32
    for key in ("point", "normal", "force"):
        assert answers[key].shape == (1_000_000, 3) and answers[key].dtype == np.float32
    # A slice answers as the same rows of the whole batch.
    part = scene.query(segments[123_456:123_756])
    for key in answers:
        assert np.array_equal(part[key], answers[key][123_456:123_756])
    # Read in place: the core reads the array's own buffer (no copy of the segments).
    seconds, address = hapticbox._core._time_query_many(scene, segments)
    assert address == segments.ctypes.data and seconds > 0
    # float64 is converted (a copy), with the same answers.
    assert np.array_equal(scene.query(segments[:1000].astype(np.float64))["force"], answers["force"][:1000])


def test_the_workspace_scales_the_force():
    mesh = dataset(RESULTS_MODELS["armadillo"])
    scene = hapticbox.Scene.load(cli_bake(mesh, "armadillo"))
    segments = probe_segments(hapticbox.Model(mesh), 2000)
    default = scene.query(segments)
    stiffer = scene.query(segments, workspace="stiffness=3000")
    hit = default["contact"]
    assert hit.any()
    assert np.allclose(stiffer["force"][hit], 2 * default["force"][hit], rtol=1e-5)
    assert np.array_equal(stiffer["depth"], default["depth"])


def test_a_tool_answers_as_query_tool_does_bit_for_bit(tmp_path):
    mesh = dataset(RESULTS_MODELS["armadillo"])
    box = cli_bake(mesh, "armadillo")
    model = hapticbox.Model(mesh)
    rng = np.random.default_rng(5)
    v = model.vertices
    centres = v[rng.integers(0, len(v), 200)] + rng.normal(0, 0.004 * model.diagonal, (200, 3))
    q = rng.normal(size=(200, 4))
    poses = np.ascontiguousarray(np.hstack([centres, q]).astype(np.float32))
    spec = "sphere,radius-mm=2,points=300"
    pose_csv, out_csv = tmp_path / "poses.csv", tmp_path / "tool.csv"
    np.savetxt(pose_csv, poses, fmt="%.9g", delimiter=",", header="x,y,z,qw,qx,qy,qz", comments="")
    run_cli("query", box, "--tool", spec, "--poses", pose_csv, "--out", out_csv)
    with open(out_csv, newline="") as f:
        rows = list(csv.DictReader(f))
    cli_force = np.array([[np.float32(r[k]) for k in ("fx", "fy", "fz")] for r in rows], np.float32)
    cli_torque = np.array([[np.float32(r[k]) for k in ("tx", "ty", "tz")] for r in rows], np.float32)
    cli_contacts = np.array([int(r["contacts"]) for r in rows])
    tool = hapticbox.Tool(spec)
    assert tool.points == 300
    mine = tool.answer(hapticbox.Scene.load(box), poses)
    assert np.array_equal(mine["force"].view(np.uint32), cli_force.view(np.uint32))
    assert np.array_equal(mine["torque"].view(np.uint32), cli_torque.view(np.uint32))
    assert np.array_equal(mine["contacts"], cli_contacts)
    assert (cli_contacts > 0).any() and (cli_contacts == 0).any()
    exact = tool.answer(hapticbox.Exact(model), poses[:, :3])  # (N, 3): no rotation
    assert exact["force"].shape == (200, 3)
