#!/usr/bin/env python3
"""Fresh mutations of the project's own model files through `hapticbox`, counted by outcome.

Each run takes a seed file (the generated CT phantom, the real DICOM series, the reference STEP
solid, the elephant's glTF/GLB/3MF/Collada/FBX exports, piece files written by `decompose`, a
servo log recorded from the virtual device),
damages it once (bit flips, interesting integers, truncation, cut or repeated chunks, and for
text formats a number, line or token of the header replaced), and runs `hapticbox info FILE`
(piece files: `bake SPHERE --pieces FILE`; servo logs: `trajectory LOG plane -o OUT.vtp`) under
a wall-clock timeout. Outcomes:
  crash     the command died by a signal (exit status > 128 or negative)
  hang      the outer timeout (--timeout, default 40 s) expired
  blowup    peak resident memory of the command and its reader above --blowup-mb (2048)
  empty     a rejection whose message does not name the file with a non-empty cause
  unreadable a rejection whose message holds raw bytes (control or invalid UTF-8) or runs past
            2,000 bytes
  rejected  exit code 1 or 2 with a message naming the file and a cause
  accepted  exit code 0 (a harmless mutation, or a silent acceptance: read the samples)
For counts in the thousands use build/tests/vtk_pipelines/hb_mutate_campaign (the same damage
through load_model in one process, forked per case, about 30-150 ms of processor a run instead
of a whole command); this script checks the command end to end (exit codes, stderr).
Usage: scripts/mutate_models.py [--runs N] [--families volumes,cad,scenes,pieces,logs] [--jobs 2]
       [--seed S] [--keep DIR]   (run from the source tree with the build in build/)
"""
import argparse, gzip, json, os, random, resource, shutil, signal, subprocess, sys, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HB = os.path.join(ROOT, "build", "cli", "hapticbox")
DATA = os.path.join(ROOT, "datasets", "data")

INTERESTING = [0, 1, 0xFF, 0x7F, 0x80, 0xFFFF, 0x7FFF, 0x8000, 0x7FFFFFFF, 0x80000000, 0xFFFFFFFF, 0xFFFFFFF8, 65535, 1 << 20, 3]
TEXT_NUMBERS = ["0", "-1", "2147483648", "1e308", "nan", "-0", "99999999", "3", "65535", "4294967295", "1.5", ""]


def mutate_binary(data, rng):
    b = bytearray(data)
    if not b:
        return bytes(b)
    kind = rng.randrange(6)
    if kind == 0:  # bit flips
        for _ in range(rng.randint(1, 8)):
            i = rng.randrange(len(b))
            b[i] ^= 1 << rng.randrange(8)
    elif kind == 1:  # an interesting byte
        b[rng.randrange(len(b))] = rng.choice([0, 0xFF, 0x7F, 0x80])
    elif kind == 2:  # an interesting 2- or 4-byte integer, little endian, often in the header
        width = rng.choice([2, 4])
        at = rng.randrange(min(len(b), 1024) if rng.random() < 0.7 else len(b))
        v = rng.choice(INTERESTING) & ((1 << (8 * width)) - 1)
        b[at:at + width] = v.to_bytes(width, "little")
    elif kind == 3:  # truncation
        del b[rng.randrange(len(b)):]
    elif kind == 4:  # a chunk cut out
        at = rng.randrange(len(b))
        del b[at:at + rng.randint(1, 256)]
    else:  # a chunk repeated
        at = rng.randrange(len(b))
        chunk = b[at:at + rng.randint(1, 256)]
        b[at:at] = chunk * rng.randint(1, 16)
    return bytes(b)


def mutate_text(data, rng, header_end=None):
    end = header_end if header_end is not None else len(data)
    head, tail = data[:end], data[end:]
    lines = head.split(b"\n")
    if len(lines) < 2:
        return mutate_binary(data, rng)
    i = rng.randrange(len(lines))
    kind = rng.randrange(5)
    line = lines[i]
    if kind == 0:  # a number replaced
        import re
        nums = list(re.finditer(rb"-?\d+(\.\d+)?(e[-+]?\d+)?", line))
        if nums:
            m = rng.choice(nums)
            line = line[:m.start()] + rng.choice(TEXT_NUMBERS).encode() + line[m.end():]
        lines[i] = line
    elif kind == 1:  # a line deleted
        del lines[i]
    elif kind == 2:  # a line repeated
        lines.insert(i, line)
    elif kind == 3:  # a token replaced by garbage or a reference
        toks = line.split(b" ")
        j = rng.randrange(len(toks))
        toks[j] = rng.choice([b"*", b"#0", b"#999999", b"garbage", b"\x01\x02", b"LIST", b"%d 1 10 0", b"-1", b""])
        lines[i] = b" ".join(toks)
    else:  # a reference id changed (STEP '#N', XML/JSON indices)
        import re
        refs = list(re.finditer(rb"#\d+|\"\d+\"|\b\d+\b", line))
        if refs:
            m = rng.choice(refs)
            lines[i] = line[:m.start()] + rng.choice([b"#0", b"#1", b"#999999", b"0", b"1", b"99999", b"-1"]) + line[m.end():]
    return b"\n".join(lines) + tail


def header_end_of(name, data):
    if name.endswith(".mha"):
        at = data.find(b"ElementDataFile = LOCAL\n")
        return at + 24 if at >= 0 else None
    if name.endswith(".nrrd"):
        at = data.find(b"\n\n")
        return at + 2 if at >= 0 else None
    return None


def prepare_seeds(work):
    """Seed files per family: (family, kind, path, text?)"""
    g = os.path.join(DATA, "generated")
    seeds = []
    nii = os.path.join(work, "ct_phantom.nii")
    with gzip.open(os.path.join(g, "ct_phantom.nii.gz")) as f, open(nii, "wb") as o:
        o.write(f.read())
    seeds += [("volumes", "file", nii, False), ("volumes", "file", os.path.join(g, "ct_phantom.mha"), True),
              ("volumes", "file", os.path.join(g, "ct_phantom.nrrd"), True),
              ("volumes", "file", os.path.join(g, "ct_phantom.nii.gz"), False),
              ("volumes", "dicom", os.path.join(DATA, "volumes", "dicom", "CT5N"), False)]
    seeds += [("cad", "file", os.path.join(g, "reference_solid.step"), True)]
    for ext, text in ((".glb", False), (".gltf", True), (".3mf", False), (".dae", True), (".fbx", False)):
        seeds.append(("scenes", "file", os.path.join(g, "elephant" + ext), text))
    # Piece files: written by `decompose` for a sphere (.vtp, .ply, .txt), used by `bake --pieces`.
    sphere = os.path.join(work, "sphere.off")
    subprocess.run([HB, "subdivide", os.path.join(DATA, "meshes", "octahedron.off"), "--levels", "3", "-o", sphere],
                   check=True, capture_output=True)
    for ext in (".vtp", ".ply", ".txt"):
        out = os.path.join(work, "pieces" + ext)
        subprocess.run([HB, "decompose", sphere, "--max-pieces", "4", "--lines", "1000", "--leaves", "8", "-o", out],
                       check=True, capture_output=True)
        seeds.append(("pieces", "file", out, ext != ".vtp"))
    # A servo log of the virtual device on the plane, exported by `trajectory`.
    log = os.path.join(work, "run.hbslog")
    subprocess.run([HB, "servo", "plane", "--device", "virtual", "--seconds", "0.2", "--record", log], check=True, capture_output=True)
    seeds.append(("logs", "file", log, False))
    return seeds, sphere


def run_one(args):
    family, kind, seed, text, index, rng_seed, work, sphere, timeout, blowup_mb, keep = args
    rng = random.Random(rng_seed)
    case = os.path.join(work, "case%06d" % index)
    os.makedirs(case)
    name = os.path.basename(seed)
    if kind == "dicom":  # one slice of a copied series damaged; the series opened as a directory
        target_dir = os.path.join(case, name)
        shutil.copytree(seed, target_dir)
        victim = os.path.join(target_dir, rng.choice(sorted(os.listdir(target_dir))))
        data = open(victim, "rb").read()
        open(victim, "wb").write(mutate_binary(data, rng) if rng.random() < 0.5 else mutate_binary(data[:4096], rng) + data[4096:])
        target = target_dir
    else:
        data = open(seed, "rb").read()
        if name.endswith(".gltf"):
            shutil.copy(os.path.join(os.path.dirname(seed), "elephant.bin"), case)
        target = os.path.join(case, name)
        if text and rng.random() < 0.6:
            mutated = mutate_text(data, rng, header_end_of(name, data))
        else:
            mutated = mutate_binary(data, rng)
        open(target, "wb").write(mutated)
    if family == "pieces":
        cmd = [HB, "bake", sphere, "--pieces", target, "-o", os.path.join(case, "x.hbox"), "-m", "2", "-n", "2", "--cache", "none"]
    elif family == "logs":
        cmd = [HB, "trajectory", target, "plane", "-o", os.path.join(case, "t.vtp")]
    else:
        cmd = [HB, "info", target]
    env = dict(os.environ, HB_READER_TIMEOUT_S=str(max(1, timeout // 2)), XDG_CACHE_HOME=os.path.join(case, "cache"))
    start = time.time()
    memfile = os.path.join(case, "peak_kb")
    cmd = ["/usr/bin/time", "-f", "%M", "-o", memfile] + cmd  # peak RSS of the command and its reader
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env, start_new_session=True)
    outcome = None
    try:
        _, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        _, err = p.communicate()
        outcome = "hang"
    rc = p.returncode
    err = err.decode("utf-8", "replace")
    try:
        peak_mb = int(open(memfile).read().strip().splitlines()[-1]) / 1024.0
    except (OSError, ValueError, IndexError):
        peak_mb = 0.0
    if outcome is None:
        if peak_mb > blowup_mb:
            outcome = "blowup"
        elif rc < 0 or rc > 128:
            outcome = "crash"
        elif rc == 0:
            outcome = "accepted"
        else:
            line = next((l for l in err.splitlines() if l.startswith("hapticbox: error: ")), "")
            cause = line[len("hapticbox: error: "):]
            named = (target + ": ") in cause or any(cause.startswith(os.path.join(case, x)) for x in os.listdir(case)) or case in cause
            after = cause.split(": ", 1)[1].strip() if ": " in cause else ""
            outcome = "rejected" if named and after else "empty"
            # The error itself (VTK's own log lines, coloured, are not the command's message).
            message = err[err.find("hapticbox: error: "):] if "hapticbox: error: " in err else ""
            raw = any((ord(c) < 0x20 and c not in "\n\t") or c == "\ufffd" for c in message)
            if outcome == "rejected" and (raw or len(message.rstrip("\n")) > 2000):
                outcome = "unreadable"
    result = {"family": family, "seed": name, "index": index, "outcome": outcome, "rc": rc,
              "seconds": round(time.time() - start, 2), "peak_mb": round(peak_mb), "message": err.strip().splitlines()[-1][:300] if err.strip() else ""}
    if keep and outcome not in ("rejected",):
        dest = os.path.join(keep, "%s-%s-%06d" % (outcome, family, index))
        shutil.copytree(case, dest, dirs_exist_ok=True)
    shutil.rmtree(case, ignore_errors=True)
    return result


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=100, help="mutations per family")
    ap.add_argument("--families", default="volumes,cad,scenes,pieces,logs")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--seed", type=int, default=int(time.time()))
    ap.add_argument("--timeout", type=int, default=40)
    ap.add_argument("--blowup-mb", type=int, default=2048)
    ap.add_argument("--keep", default="")
    ap.add_argument("--json", default="")
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="hb_mutate_")
    seeds, sphere = prepare_seeds(work)
    families = a.families.split(",")
    rng = random.Random(a.seed)
    jobs = []
    index = 0
    for fam in families:
        fam_seeds = [s for s in seeds if s[0] == fam]
        for _ in range(a.runs):
            s = rng.choice(fam_seeds)
            jobs.append((fam, s[1], s[2], s[3], index, rng.getrandbits(64), work, sphere, a.timeout, a.blowup_mb, a.keep))
            index += 1
    if a.keep:
        os.makedirs(a.keep, exist_ok=True)
    from concurrent.futures import ThreadPoolExecutor
    results = []
    with ThreadPoolExecutor(a.jobs) as pool:
        for r in pool.map(run_one, jobs):
            results.append(r)
    shutil.rmtree(work, ignore_errors=True)
    outcomes = ["crash", "hang", "blowup", "empty", "unreadable", "rejected", "accepted"]
    print("mutate_models: seed %d, %d runs a family" % (a.seed, a.runs))
    print("%-8s %s" % ("family", " ".join("%9s" % o for o in outcomes)))
    for fam in families:
        rs = [r for r in results if r["family"] == fam]
        print("%-8s %s" % (fam, " ".join("%9d" % sum(1 for r in rs if r["outcome"] == o) for o in outcomes)))
    bad = [r for r in results if r["outcome"] in ("crash", "hang", "blowup", "empty", "unreadable")]
    for r in bad[:40]:
        print("  %s %s #%d rc %s: %s" % (r["outcome"], r["seed"], r["index"], r["rc"], r["message"]))
    if a.json:
        json.dump(results, open(a.json, "w"), indent=1)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
