#!/usr/bin/env python3
"""Checks that every CMake target still compiles as one unity translation unit.

scripts/build.sh builds with CMAKE_UNITY_BUILD (the sources of a target compiled a few at a
time in one translation unit), so two files of one target must not define the same name in an
anonymous namespace or as a static function. Which files share a unity batch changes as files
are added, so this check puts ALL the sources of each target into one translation unit and runs
the compiler with -fsyntax-only (seconds, no code generated), using the commands of a configured
build's compile_commands.json. Usage: scripts/check_unity.py [BUILD_DIR] (default build).
Exit status 1 and the compiler's errors when a target's sources clash."""
import collections, json, os, shlex, subprocess, sys, tempfile
from concurrent.futures import ThreadPoolExecutor

build = sys.argv[1] if len(sys.argv) > 1 else "build"
db = json.load(open(os.path.join(build, "compile_commands.json")))
groups = collections.defaultdict(list)
for e in db:
    args = shlex.split(e["command"]) if "command" in e else e["arguments"]
    out = args[args.index("-o") + 1] if "-o" in args else ""
    if "/Unity/" in out or "CMakeFiles/" not in out:
        continue
    target = out.split("CMakeFiles/")[1].split(".dir")[0]
    src = e["file"]
    # the flags without -o/-c/-MD/-MT/-MF and the source itself: files of a target whose flags
    # differ from the rest are compiled alone by CMake's unity build too
    flags, skip = [], False
    for a in args[:]:
        if skip:
            skip = False
            continue
        if a in ("-o", "-MT", "-MF"):
            skip = True
            continue
        if a in ("-c", "-MD") or a == src or a == e.get("file"):
            continue
        flags.append(a)
    groups[(target, e["directory"], tuple(flags))].append(src)

def check(item):
    (target, directory, flags), srcs = item
    srcs = [s for s in srcs if "_autogen/" not in s]  # moc output: compiled on its own
    if len(srcs) < 2:
        return None
    with tempfile.NamedTemporaryFile("w", suffix=".cpp", delete=False) as f:
        f.write("".join(f'#include "{s}"\n' for s in srcs))
        name = f.name
    try:
        r = subprocess.run(list(flags) + ["-fsyntax-only", "-w", "-fmax-errors=0", name], cwd=directory,
                           capture_output=True, text=True)
    finally:
        os.unlink(name)
    if r.returncode != 0:
        errors = [l for l in r.stderr.splitlines() if "error" in l]
        return f"{target}: its {len(srcs)} sources clash in one translation unit:\n  " + "\n  ".join(errors[:60])
    return None

with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
    failures = [m for m in pool.map(check, groups.items()) if m]
for m in failures:
    print(m, file=sys.stderr)
print(f"check_unity.py: {len(groups)} target groups, {len(failures)} clash", file=sys.stderr)
sys.exit(1 if failures else 0)
