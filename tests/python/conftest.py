"""Fixtures of the Python module's suite: the command line (HB_CLI), the datasets
(HB_DATASETS_DIR), a bake cache that outlives the run (HB_TEST_CACHE) and probe segments."""
import os
import subprocess

import numpy as np
import pytest

import hapticbox

DATA = os.environ.get("HB_DATASETS_DIR", os.path.join(os.path.dirname(__file__), "../../datasets/data"))
CLI = os.environ.get("HB_CLI", os.path.join(os.path.dirname(__file__), "../../build/cli/hapticbox"))
CACHE = os.environ.get("HB_TEST_CACHE", os.path.join(os.path.dirname(__file__), "../../build/tests/python/cache"))

# The results models (scripts/results.sh): name -> file under datasets/data.
RESULTS_MODELS = {
    "armadillo": "meshes/armadillo.off",
    "bumpy_sphere": "generated/bumpy_sphere.off",
    "chess_piece": "generated/chess_piece.off",
}


def dataset(relative):
    path = os.path.join(DATA, relative)
    if not os.path.exists(path):
        pytest.skip(f"{path} is missing: run bash datasets/fetch.sh build/datasets/hb_generate_datasets")
    return path


def run_cli(*args):
    """Runs the hapticbox command; fails the test with its stderr when it fails."""
    r = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, f"hapticbox {' '.join(map(str, args))} failed ({r.returncode}): {r.stderr}"
    return r


def cli_bake(model_path, name):
    """The CLI's default bake of a model (`hapticbox bake MODEL -o BOX`), through a cache kept
    in the build folder so that later runs copy it instead of baking."""
    os.makedirs(CACHE, exist_ok=True)
    box = os.path.join(CACHE, name + ".hbox")
    run_cli("bake", model_path, "-o", box, "--cache", os.path.join(CACHE, "boxes"))
    return box


def probe_segments(model, count, seed=7):
    """`count` segments of which most end just inside the surface near a vertex, from a handle
    a tenth of the diagonal away in a random direction (contacts, misses, handles inside),
    and some anywhere in the bounding box; float32, C-contiguous, (count, 6)."""
    rng = np.random.default_rng(seed)
    vertices = model.vertices
    diag = model.diagonal
    near = count * 3 // 4
    tips = vertices[rng.integers(0, len(vertices), near)] + rng.normal(0, 0.002 * diag, (near, 3))
    directions = rng.normal(size=(near, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    handles = tips + directions * 0.1 * diag
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    free = rng.uniform(np.tile(lo, 2), np.tile(hi, 2), (count - near, 6))
    near_rows = np.hstack([handles, tips])
    return np.ascontiguousarray(np.vstack([near_rows, free]).astype(np.float32))


@pytest.fixture(scope="session")
def small_model_path():
    """A small mesh for the bakes the suite makes itself (CGAL's elephant, 5.5K triangles)."""
    return dataset("meshes/elephant.off")
