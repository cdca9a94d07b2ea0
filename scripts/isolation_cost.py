#!/usr/bin/env python3
"""What the reader isolation costs on valid files, through the command users run.

For each file, `hapticbox info FILE` runs REPS times with HB_READER_ISOLATION=0 (the reader in
the process) and REPS times with the default (the reader in a forked child), alternating so
that both see the same machine load. Each run is timed on the wall clock and by `perf stat -e
task-clock` (processor time of the command and every process it starts, the reader's child
included, whether or not it was reaped). Prints the medians and their ratios.
Usage: scripts/isolation_cost.py [--reps 9] [FILE ...]   (from the source tree, build in build/)
"""
import argparse, os, statistics, subprocess, sys, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HB = os.path.join(ROOT, "build", "cli", "hapticbox")
DATA = os.path.join(ROOT, "datasets", "data")
DEFAULT = [os.path.join(DATA, "meshes", "armadillo.off"),
           os.path.join(DATA, "generated", "ct_phantom.nii.gz"),
           os.path.join(DATA, "generated", "femur_ct.nii.gz"),
           os.path.join(DATA, "volumes", "dicom", "CT5N"),
           os.path.join(DATA, "generated", "reference_solid.step"),
           os.path.join(DATA, "generated", "elephant.gltf"),
           os.path.join(DATA, "generated", "elephant.glb")]


def run(path, isolate):
    env = dict(os.environ, HB_READER_ISOLATION="1" if isolate else "0")
    start = time.perf_counter()
    p = subprocess.run(["perf", "stat", "-x", ",", "-e", "task-clock", "--", HB, "info", path],
                       env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - start
    cpu = None
    for line in p.stderr.splitlines():
        if "task-clock" in line:
            cpu = float(line.split(",")[0])
    if p.returncode != 0 or cpu is None:
        sys.exit("isolation_cost: %s failed:\n%s" % (path, p.stderr[-2000:]))
    return wall * 1e3, cpu


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=9)
    ap.add_argument("files", nargs="*")
    a = ap.parse_args()
    files = a.files or [f for f in DEFAULT if os.path.exists(f)]
    with open("/proc/loadavg") as f:
        load = f.read().split()[0]
    print("isolation_cost: %d runs each, alternating; load average %s at the start" % (a.reps, load))
    print("%-28s %9s %9s %6s %9s %9s %6s" % ("file", "wall ms", "isolated", "ratio", "cpu ms", "isolated", "ratio"))
    for path in files:
        run(path, False)  # warm the page cache
        direct, isolated = [], []
        for _ in range(a.reps):
            direct.append(run(path, False))
            isolated.append(run(path, True))
        dw = statistics.median(r[0] for r in direct)
        iw = statistics.median(r[0] for r in isolated)
        dc = statistics.median(r[1] for r in direct)
        ic = statistics.median(r[1] for r in isolated)
        print("%-28s %9.0f %9.0f %6.2f %9.0f %9.0f %6.2f" % (os.path.basename(path.rstrip("/")), dw, iw, iw / dw, dc, ic, ic / dc))


if __name__ == "__main__":
    main()
