#!/usr/bin/env python3
"""Bake a model, probe it, and plot what a hand would feel against what it costs: the share of
probes perceptibly different from exact against the query time per probe, for the default bake,
a few raw samplings of the paper's box, and exact Embree. Writes the figure (PNG).

    export PYTHONPATH=$PWD/build/python
    /usr/bin/python3 examples/bake_probe_plot.py datasets/data/meshes/elephant.off -o felt_vs_time.png
"""
import argparse
import time

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt

import hapticbox


def timed(answerer, segments):
    answerer.query(segments[:1000])  # warm up
    t0 = time.perf_counter()
    answers = answerer.query(segments)
    return answers, (time.perf_counter() - t0) / len(segments) * 1e9


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("model")
    p.add_argument("-o", "--output", default="felt_vs_time.png")
    p.add_argument("--probes", type=int, default=200_000)
    a = p.parse_args()

    model = hapticbox.Model(a.model)
    segments = hapticbox.sample_probes(model, a.probes)  # eval's random probes, (N, 6) float32
    exact_answers, exact_ns = timed(hapticbox.Exact(model), segments)
    points = [("exact Embree", exact_ns, 0.0)]
    bakes = [("default bake", {})] + [(f"raw m{m} n{n}", {"m": m, "n": n}) for m, n in ((8, 4), (16, 8), (32, 16))]
    for label, sampling in bakes:
        scene = hapticbox.bake(model, **sampling)
        answers, ns = timed(scene, segments)
        felt = hapticbox.perceive(exact_answers, answers)["perceptible"].mean() * 100
        points.append((label, ns, felt))
        print(f"{label:14s} {ns:8.1f} ns/probe   {felt:6.2f}% of probes felt")

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for label, ns, felt in points:
        ax.scatter(ns, felt, s=40)
        ax.annotate(label, (ns, felt), textcoords="offset points", xytext=(6, 4), fontsize=9)
    ax.set_xlabel("query time per probe (ns, one core, batched)")
    ax.set_ylabel("probes perceptibly different from exact (%)")
    ax.set_title(f"{model.path.split('/')[-1]}: {model.triangle_count:,} triangles, {a.probes:,} probes")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(a.output, dpi=120)
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
