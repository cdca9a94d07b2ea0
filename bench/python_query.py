#!/usr/bin/env python3
"""The Python batch against C++ query_many, per segment, in one run (issue 52's target: within
1.2x at a million segments, no copy of the segments array).

    PYTHONPATH=build/python /usr/bin/python3 bench/python_query.py BOX MODEL [--count 1000000] [--repeats 5]

Both read the same float32 (N, 6) array: `scene.query(segments)` (the binding: checks the
values, answers in chunks with the GIL released, fills numpy arrays) and
`hapticbox._core._time_query_many(scene, segments)` (C++ query_many alone over the same chunks,
no numpy output), on eval's random probes (hapticbox.sample_probes). The best of the repeats of
each, interleaved; also exact Embree's."""
import argparse
import time

import hapticbox


def main():
    p = argparse.ArgumentParser()
    p.add_argument("box")
    p.add_argument("model")
    p.add_argument("--count", type=int, default=1_000_000)
    p.add_argument("--repeats", type=int, default=5)
    a = p.parse_args()
    model = hapticbox.Model(a.model)
    segments = hapticbox.sample_probes(model, a.count, seed=2)  # eval's and bench's probes
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
        print(f"{name}: {a.count:,} segments: Python .query() {py_ns:.1f} ns/segment, C++ query_many "
              f"{cpp_ns:.1f} ns/segment: {py_ns / cpp_ns:.3f}x; segments read in place (no copy): {in_place}")


if __name__ == "__main__":
    main()
