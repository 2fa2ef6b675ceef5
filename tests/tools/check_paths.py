#!/usr/bin/env python3
"""Every repository path named in the docs and in comments exists.

Looks in the tracked Markdown files (their text, whose paths are named from the repository's
root, and their links, which resolve from the file's folder) and in the comments of the tracked C, Python, shell, CMake and YAML files for words that
start with a top-level folder of the repository (src/, include/, app/, tests/, docs/, cases/,
bench/, scripts/, examples/, fuzz/, python/, cmake/, .ci/) or with ../, and checks that each
names a file or folder that exists. Paths that are meant but not here (the shared papers next to
the repository, a peer code's files, generated folders) are in ALLOWED; patterns and placeholders
(tests/*.c, cases/CASE.yaml) are skipped. Prints each missing path with the places that name
it and exits 1 if there is any.

Usage: check_paths.py [REPO]   (ctest: unit_paths_named_in_docs_and_comments_exist)
"""
import os
import re
import subprocess
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", ".."))
TOP = ("src", "include", "app", "tests", "docs", "cases", "bench", "scripts", "examples", "fuzz",
       "python", "cmake", ".ci")

# Paths that need not exist here, named on purpose: prefixes (after normalising).
ALLOWED = (
    "../shared/",          # the papers and notes next to the repository (/work/shared)
    "bench/in.chute",      # LAMMPS's granular benchmark and its logs, in the LAMMPS repository
    "bench/log.",
    "bench/peers/beds/",   # written by bench/peers/make_bed.sh
    "bench/peers/runs/",   # written by bench/peers/run_peers.sh
)
# A word with a segment in capitals (CASE, NAME, TARGET, DATE) or a size N (bedN.data) is a
# pattern; one through an out/ folder is a run's output.
PLACEHOLDER = re.compile(r"(^|/)([A-Z]{3,}|[a-z]+N)(\.[\w.]+)?(/|$)|(^|/)out/")

WORD = re.compile(r"(?<![\w./-])((?:\.\./)+[\w.+-][\w./+*?%%{}<>$-]*|(?:%s)/[\w./+*?%%{}<>$-]*)" % "|".join(re.escape(t) for t in TOP))
LINK = re.compile(r"\]\(([^)\s#]+)(?:#[^)]*)?\)")


def tracked():
    out = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True)
    return [f for f in out.stdout.splitlines() if os.path.isfile(os.path.join(ROOT, f))]


def comments(path, text):
    """The comment text of a source file (C: /* */ and //; others: # to the end of the line)."""
    if path.endswith((".c", ".h")):
        # strings first, so that a "//" or "/*" inside a string is not a comment
        pat = re.compile(r'"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'|/\*.*?\*/|//[^\n]*', re.S)
        return "\n".join(m.group(0) for m in pat.finditer(text) if m.group(0)[0] == "/")
    return "\n".join(line[line.index("#"):] for line in text.splitlines() if "#" in line)


def candidates(path, text):
    """(word, folder it resolves from) for every path-like word."""
    base = os.path.dirname(path)
    if path.endswith(".md"):
        for m in LINK.finditer(text):
            target = m.group(1)
            if "://" in target or target.startswith("mailto:"):
                continue
            yield target, base
        body = text
    else:
        body = comments(path, text)
    for m in WORD.finditer(body):
        yield m.group(1), ""  # a path in the text is named from the repository's root


def normal(word):
    word = word.rstrip(".,;:)'\"`")
    if any(c in word for c in "*?%{}<>$") or word.endswith(("/...", "...")) or PLACEHOLDER.search(word):
        return None  # a pattern, a format, a placeholder, an elision or an output, not a path
    return word


def main():
    missing = {}
    for f in tracked():
        if not f.endswith((".md", ".c", ".h", ".py", ".sh", ".txt", ".yaml", ".cmake")) and \
                not os.path.basename(f) in ("run", "CMakeLists.txt"):
            continue
        try:
            text = open(os.path.join(ROOT, f), encoding="utf-8").read()
        except UnicodeDecodeError:
            continue
        for word, base in candidates(f, text):
            w = normal(word)
            if not w:
                continue
            rel = os.path.normpath(os.path.join(base, w))
            shown = rel + ("/" if w.endswith("/") else "")
            if any(shown.startswith(a) or (rel + "/").startswith(a) for a in ALLOWED):
                continue
            if not os.path.exists(os.path.join(ROOT, rel)):
                missing.setdefault(shown, set()).add(f)
    for p in sorted(missing):
        print("%s: named in %s" % (p, ", ".join(sorted(missing[p]))))
    print("check_paths: %d missing path%s" % (len(missing), "" if len(missing) == 1 else "s"), file=sys.stderr)
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
