"""What answers a scene's queries, in words a newcomer understands: the results tables of
scripts/results.sh and scripts/tool_results.sh, defined in README.md beside the table."""

ROUTES = {
    "raw": "raw box (the paper's samples)",
    "boxes": "refined boxes (exact, each box's triangles)",
    "cells": "surface cells (exact, grid walk)",
    "embree": "exact ray cast over the surface (Embree)",
}


def route_words(route):
    return ROUTES.get(route, route)


def tool_route_words(route):
    """The tool benchmark names the query route only: on a default bake "boxes" are raw boxes."""
    return route_words("raw" if route == "boxes" else route)


def raw_trial_words(t):
    """Why the paper's raw box, tried first, was not kept: 'raw box m16 n8 felt on 51% of probes'."""
    def share(key):
        v = t.get(key)
        return None if v is None or v < 0 else f"{100 * v:.2g}%"
    outcome = t.get("outcome", "")
    why = {"felt-probes": f"felt on {share('probes_felt')} of probes",
           "felt-slides": f"felt on {share('slide_ticks_felt')} of slide ticks",
           "felt-light": f"felt on {share('light_touches_felt')} of light touches",
           "over-cap": "larger than the size cap",
           "slower": "slower than exact",
           "slower-strokes": "slower than exact along strokes",
           "serves": "not needed", "kept": "kept"}.get(outcome, outcome)
    return f"raw box m{t['m']} n{t['n']} {why}"


def answer_words(report):
    """The results table's cell: what answers, along strokes when that differs, and the raw
    box's fate when it was tried and not kept. `report` is `bake --json`'s budget object."""
    a = report.get("answer", "cells")
    text = route_words(a)
    if report.get("stroke_answer") == "embree":
        text += "; strokes: exact ray cast (Embree)"
    raw = report.get("raw_tried") or []
    if a != "raw" and raw:
        text += "; " + raw_trial_words(raw[-1])
    return text
