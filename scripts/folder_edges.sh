#!/usr/bin/env bash
# The folder-level include graph of the core (src/): which folder's files include which other
# folder's headers, and the cycles in it (the core's folders must depend one way only).
#
#   scripts/folder_edges.sh              edges of src/ and its cycles; exit 1 when there is one
#   scripts/folder_edges.sh --from DIR   which src/ folders the files under DIR include (e.g.
#                                        device: it should need math/ and contact/ only)
#   scripts/folder_edges.sh --dot        the graph in Graphviz dot (dot -Tsvg > folders.svg)
#   scripts/folder_edges.sh --check      one line when the rules hold (no folder cycle in src/,
#                                        device/ includes no evaluation/ header), else what
#                                        breaks them; exit 1 then (./test.sh runs it)
#
# An edge a -> b means a file under src/a/ has `#include "b/..."` with src/b/ a folder. The
# headers at the top of src/ (errors.h, progress.h, ...) belong to no folder and make no edge.
# Each edge is listed with its count and one file and include that make it, so a cycle can be
# broken where it is made.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=graph from=""
case "${1:-}" in
  "") ;;
  --dot) mode=dot ;;
  --check) mode=check ;;
  --from)
    [ -n "${2:-}" ] || { echo "folder_edges.sh: --from needs a directory (e.g. device)" >&2; exit 2; }
    [ -d "$2" ] || { echo "folder_edges.sh: --from $2: no such directory" >&2; exit 2; }
    mode=from from=$2 ;;
  -h|--help) sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "folder_edges.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
esac

exec python3 - "$mode" "$from" <<'PY'
import os, re, sys
from collections import defaultdict

mode, source = sys.argv[1], sys.argv[2]
folders = sorted(d for d in os.listdir("src") if os.path.isdir(os.path.join("src", d)))
include = re.compile(r'^\s*#\s*include\s*"([^"/]+)/[^"]+"', re.M)

def scan(root, folder_of):
    """edges[(a, b)] = [(file, included header)] for every include of a src/ folder's header."""
    edges = defaultdict(list)
    for dirpath, _, names in os.walk(root):
        for name in sorted(names):
            if not name.endswith((".h", ".hpp", ".cpp", ".cxx", ".cc")):
                continue
            path = os.path.join(dirpath, name)
            a = folder_of(path)
            if a is None:
                continue
            with open(path, encoding="utf-8", errors="replace") as f:
                text = f.read()
            for m in include.finditer(text):
                b = m.group(1)
                if b in folders and b != a:
                    line = m.group(0).strip()
                    edges[(a, b)].append((path, line[line.index('"'):]))
    return edges

if mode == "from":
    edges = scan(source, lambda p: source)
    if not edges:
        print(f"{source}: includes no src/ folder's header")
    for (_, b), uses in sorted(edges.items()):
        print(f"{source} -> {b}  ({len(uses)} includes; e.g. {uses[0][0]}: {uses[0][1]})")
    sys.exit(0)

def src_folder(path):
    parts = os.path.relpath(path, "src").split(os.sep)
    return parts[0] if len(parts) > 1 else None

edges = scan("src", src_folder)
graph = defaultdict(set)
for a, b in edges:
    graph[a].add(b)

if mode == "check":
    # The layers' rules, beyond src/: device/ uses the core's math and contact, never its
    # measurements (evaluation/).
    banned = [(u, "device -> evaluation") for (_, b), us in scan("device", lambda p: "device").items()
              if b == "evaluation" for u in us]
    for (path, inc), rule in banned:
        print(f"folder_edges.sh: {path} includes {inc} ({rule}: device/ must not include evaluation/ headers)")

if mode == "dot":
    print("digraph src_folders {\n  rankdir=LR;")
    for f in folders:
        print(f'  "{f}";')
    for (a, b), uses in sorted(edges.items()):
        print(f'  "{a}" -> "{b}" [label="{len(uses)}"];')
    print("}")
    sys.exit(0)

# Strongly connected components (Tarjan): a component of two or more folders is a cycle.
index, low, stack, on_stack, sccs, counter = {}, {}, [], set(), [], [0]
def connect(v):
    index[v] = low[v] = counter[0]; counter[0] += 1
    stack.append(v); on_stack.add(v)
    for w in sorted(graph[v]):
        if w not in index:
            connect(w); low[v] = min(low[v], low[w])
        elif w in on_stack:
            low[v] = min(low[v], index[w])
    if low[v] == index[v]:
        comp = []
        while True:
            w = stack.pop(); on_stack.discard(w); comp.append(w)
            if w == v:
                break
        sccs.append(sorted(comp))
for f in folders:
    if f not in index:
        connect(f)
cycles = [c for c in sccs if len(c) > 1]

if mode == "check" and not cycles:
    if banned:
        sys.exit(1)
    print(f"folder_edges.sh: no folder cycle in src/ ({len(folders)} folders, {len(edges)} edges); device/ includes no evaluation/ header")
    sys.exit(0)
print(f"folder edges in src/ ({len(folders)} folders, {len(edges)} edges):")
for (a, b), uses in sorted(edges.items()):
    back = " [cycle]" if any(a in c and b in c for c in cycles) else ""
    print(f"  {a} -> {b}  ({len(uses)}; e.g. {uses[0][0]}: {uses[0][1]}){back}")
if not cycles:
    print("no folder cycle")
    sys.exit(0)
print(f"{len(cycles)} folder cycle(s):")
for c in cycles:
    print("  " + " <-> ".join(c))
    # The two-way pairs inside the component, with every include that makes the weaker way
    # (the direction with fewer includes: usually the one to break).
    for i, a in enumerate(c):
        for b in c[i + 1:]:
            if (a, b) in edges and (b, a) in edges:
                weak = (a, b) if len(edges[(a, b)]) <= len(edges[(b, a)]) else (b, a)
                print(f"    {a} <-> {b}: {weak[0]} -> {weak[1]} by")
                for path, inc in edges[weak]:
                    print(f"      {path}: {inc}")
sys.exit(1)
PY
