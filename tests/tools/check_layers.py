#!/usr/bin/env python3
"""The layer rule through the public headers (docs/architecture.md): every library source file is
preprocessed with its own compile command (compile_commands.json) and the public headers it
reaches, directly or through other headers (cc -MM), must belong to its layer or a layer below.
The build's include paths already refuse an upward include of an internal header; this sees what
they cannot: include/adem is on every layer's path, so core could otherwise read the run's or the
studies' declarations.

    check_layers.py BUILD/compile_commands.json SOURCE_DIR [--graph]

--graph also prints, per layer, the public headers its files reach. Exit 1 on a violation.
"""
import json
import os
import shlex
import subprocess
import sys

# The layer that owns each public header (include/adem/...): the one whose code implements it.
OWNER = {
    "base.h": "kernels", "laws.h": "kernels", "vec3.h": "kernels",
    "world.h": "core", "files.h": "core",
    "case.h": "input",
    "internal/plot.h": "output", "frames.h": "output",
    "run.h": "run", "binding.h": "run",
    "studies.h": "studies", "pile.h": "studies", "drum.h": "studies", "calibrate.h": "studies",
    "fields.h": "fields",
    "adem.h": "umbrella",
}
# What each layer sits on (CMakeLists.txt's ADEM_DEPS_*). The studies and fields are written on
# the public API as a program of your own would be: any public header, never the umbrella.
BELOW = {
    "kernels": [], "core": ["kernels"], "mpi": ["core"], "input": ["core"], "output": ["core"],
    "run": ["input", "output", "mpi"],
}
OPEN = {"studies", "fields"}
DIRS = {"laws": "kernels", "core": "core", "mpi": "mpi", "input": "input", "output": "output",
        "run": "run", "studies": "studies", "fields": "fields"}


def layers_under(layer):
    seen, todo = set(), [layer]
    while todo:
        l = todo.pop()
        if l not in seen:
            seen.add(l)
            todo.extend(BELOW.get(l, []))
    return seen


def deps(entry):
    args = shlex.split(entry["command"]) if "command" in entry else list(entry["arguments"])
    out, skip = [], False
    for a in args:
        if skip:
            skip = False
            continue
        if a == "-o":
            skip = True
            continue
        if a == "-c":
            continue
        out.append(a)
    out.insert(1, "-MM")
    r = subprocess.run(out, cwd=entry["directory"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("check_layers: cc -MM failed on %s:\n%s" % (entry["file"], r.stderr))
    return [d for d in r.stdout.replace("\\\n", " ").split()[1:]]


def main():
    db, src = sys.argv[1], os.path.realpath(sys.argv[2])
    graph = "--graph" in sys.argv
    inc = os.path.join(src, "include", "adem") + os.sep
    entries, seen = [], set()
    for e in json.load(open(db)):
        f = os.path.realpath(os.path.join(e["directory"], e["file"]))
        rel = os.path.relpath(f, src).split(os.sep)
        if len(rel) == 3 and rel[0] == "src" and rel[1] in DIRS and f not in seen:
            seen.add(f)
            entries.append((DIRS[rel[1]], os.path.relpath(f, src), e))
    if len(entries) < 50:
        sys.exit("check_layers: only %d library sources in %s" % (len(entries), db))
    bad, reached = 0, {}
    for layer, rel, e in sorted(entries, key=lambda t: t[1]):
        ok = layers_under(layer)
        for d in deps(e):
            d = os.path.realpath(os.path.join(e["directory"], d))
            if not d.startswith(inc):
                continue
            h = d[len(inc):]
            reached.setdefault(layer, set()).add(h)
            owner = OWNER.get(h)
            if owner is None:
                print("%s: reaches adem/%s, which has no layer in check_layers.py" % (rel, h))
                bad += 1
            elif owner == "umbrella" or (layer not in OPEN and owner not in ok):
                print("%s (%s) reaches adem/%s (%s): an upward include" % (rel, layer, h, owner))
                bad += 1
    if graph:
        for layer in ["kernels", "core", "mpi", "input", "output", "run", "studies", "fields"]:
            if layer in reached:
                print("%-8s %s" % (layer, " ".join(sorted(reached[layer]))))
    print("check_layers: %d library sources, %d upward includes" % (len(entries), bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
