#!/usr/bin/env bash
# Code comments say what the code does and why; the history of a decision (when it was made,
# which issue asked for it) belongs in commit messages. This check fails, listing file:line,
# when a comment in the code folders carries an ISO date (2024-05-17) or an issue number
# ("issue 12", "issues 11 and 17", "(issue ...", "stop 34", "see #48").
#
#   scripts/check_comments.sh [PATH...]   (default: the code folders below)
#
# Only comments are read: C and C++ `//` and `/* */` comments (string and character literals
# skipped), and `#` comments in shell, Python and CMake files. A date inside a string (a test's
# expected output, a format example) is not a comment and is not flagged.
set -euo pipefail
cd "$(dirname "$0")/.."

FOLDERS=(src cli device qt_ui vtk_pipelines report scripts tests bench mpi peers datasets
         CMakeLists.txt test.sh run.sh)
# Files another branch is rewriting: checked again once that branch is merged. Empty this list
# then (the check covers every file of FOLDERS).
EXCLUDED_UNTIL_MERGE=()
# Data, not code (fuzzing corpora hold dated files of other tools); and this script, whose
# comments show the patterns it looks for.
EXCLUDED_DIRS=(tests/fuzz/corpus scripts/check_comments.sh)

paths=("$@")
[ ${#paths[@]} -gt 0 ] || paths=("${FOLDERS[@]}")
existing=()
for p in "${paths[@]}"; do [ -e "$p" ] && existing+=("$p"); done
[ ${#existing[@]} -gt 0 ] || exit 0

find "${existing[@]}" -type f \( -name '*.h' -o -name '*.hpp' -o -name '*.cpp' -o -name '*.cc' \
    -o -name '*.cxx' -o -name '*.c' -o -name '*.in' -o -name '*.sh' -o -name '*.py' -o -name '*.cmake' \
    -o -name 'CMakeLists.txt' \) -print0 |
python3 -c '
import re, sys

excluded = set(sys.argv[1].split())
excluded_dirs = tuple(sys.argv[2].split())
history = re.compile(
    r"\b20\d\d-[01]\d-[0-3]\d\b"                         # an ISO date
    r"|\bissues?\s+#?\d+"                                # issue 12, issues 11 and 17, issue #12
    r"|\(issue\b"                                        # (issue "tools with volume")
    r"|\bstop\s+\d+\b"                                   # before stop 34
    r"|\b(?:see|fixes|fixed|closes|closed|per)\s+#\d+",  # see #48
    re.I)

def c_comments(text):
    """(line, text) of every comment in C/C++ source, literals skipped."""
    i, n, line = 0, len(text), 1
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1; i += 1
        elif text.startswith("//", i):
            j = text.find("\n", i); j = n if j < 0 else j
            yield line, text[i:j]; i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2); j = n if j < 0 else j + 2
            for k, part in enumerate(text[i:j].split("\n")):
                yield line + k, part
            line += text.count("\n", i, j); i = j
        elif c == "R" and text.startswith("R\"", i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            k = text.find("(", i + 2); delim = ")" + text[i + 2:k] + "\""
            j = text.find(delim, k); j = n if j < 0 else j + len(delim)
            line += text.count("\n", i, j); i = j
        elif c in "\"\x27":
            if c == "\x27" and i > 0 and text[i - 1].isalnum():  # a digit separator: 1\x27000
                i += 1; continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            i = j + 1
        else:
            i += 1

def hash_comments(text):
    """(line, text) of every # comment in shell, Python or CMake, quoted text skipped."""
    for number, row in enumerate(text.split("\n"), 1):
        quote, k = None, 0
        while k < len(row):
            ch = row[k]
            if quote:
                if ch == "\\": k += 1
                elif ch == quote: quote = None
            elif ch in "\"\x27": quote = ch
            elif ch == "#" and (k == 0 or row[k - 1] in " \t;(") and not row.startswith("#!"):
                yield number, row[k:]; break
            k += 1

found = 0
for path in sys.stdin.buffer.read().decode().split("\0"):
    if not path or path in excluded or any(path == d or path.startswith(d.rstrip("/") + "/") for d in excluded_dirs):
        continue
    try:
        text = open(path, encoding="utf-8", errors="replace").read()
    except OSError:
        continue
    is_c = path.endswith((".h", ".hpp", ".cpp", ".cc", ".cxx", ".c")) or (path.endswith(".in") and "/*" in text)
    for number, comment in (c_comments(text) if is_c else hash_comments(text)):
        m = history.search(comment)
        if m:
            found += 1
            print(f"{path}:{number}: {comment.strip()[:120]}")
if found:
    print(f"check_comments.sh: {found} code comment(s) carry a date or an issue number; say what and why "
          "instead (the history belongs in the commit message)", file=sys.stderr)
    sys.exit(1)
' "${EXCLUDED_UNTIL_MERGE[*]}" "${EXCLUDED_DIRS[*]}"
