#!/usr/bin/env python3
"""The Python batch against C++ query_many, per segment, in one run (issue 52's target: within
1.2x at a million segments, no copy of the segments array).

    PYTHONPATH=build/python /usr/bin/python3 bench/python_query.py BOX MODEL [--count 1000000] [--repeats 5]

Both read the same float32 (N, 6) array: `scene.query(segments)` (the binding: checks the
values, answers in chunks with the GIL released, fills numpy arrays) and
`hapticbox._core._time_query_many(scene, segments)` (C++ query_many alone over the same chunks,
no numpy output). The best of the repeats of each, interleaved; also exact Embree's."""
import argparse
import time

import numpy as np

import hapticbox


def segments_near(model, count, seed=7):
    rng = np.random.default_rng(seed)
    v = model.vertices
    tips = v[rng.integers(0, len(v), count)] + rng.normal(0, 0.002 * model.diagonal, (count, 3))
    d = rng.normal(size=(count, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return np.ascontiguousarray(np.hstack([tips + d * 0.1 * model.diagonal, tips]).astype(np.float32))


def best(fn, repeats):
    return min(fn() for _ in range(repeats))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("box")
    p.add_argument("model")
    p.add_argument("--count", type=int, default=1_000_000)
    p.add_argument("--repeats", type=int, default=5)
    a = p.parse_args()
    model = hapticbox.Model(a.model)
    segments = segments_near(model, a.count)
    for name, answerer in (("scene", hapticbox.Scene.load(a.box)), ("exact", hapticbox.Exact(model))):
        answerer.query(segments[:10000])  # warm the pages and caches
        py_times, cpp_times = [], []
        for _ in range(a.repeats):
            t0 = time.perf_counter()
            answerer.query(segments)
            py_times.append(time.perf_counter() - t0)
            seconds, address = hapticbox._core._time_query_many(answerer, segments)
            cpp_times.append(seconds)
        in_place = address == segments.ctypes.data
        py_ns, cpp_ns = min(py_times) / a.count * 1e9, min(cpp_times) / a.count * 1e9
        print(f"{name}: {a.count:,} segments: Python scene.query {py_ns:.1f} ns/segment, C++ query_many "
              f"{cpp_ns:.1f} ns/segment: {py_ns / cpp_ns:.3f}x; segments read in place (no copy): {in_place}")


if __name__ == "__main__":
    main()
