#!/usr/bin/python3
"""Replace the umbrella include "adem/adem.h" in library code by the public headers the file uses.

    scripts/public-includes.py [FILE...]      (default: every file of src/ and app/ that has it,
                                               or one of the headers that are gone, below)

Headers that are gone are replaced too: "files.h", "fileio.h" (src/core, src/output) and
"adem/output.h" by "adem/files.h" (and "adem/internal/plot.h" where gnuplot plots are used),
"plot.h" (src/output) by "adem/internal/plot.h"; a study that uses adem_table_* or
adem_validation_plot/_path gets "table.h".

Which header declares a name is read from the headers themselves (each preprocessed alone; the
names on its own lines are its own), so the script needs no list of names. A file then includes
the headers whose names it uses, less adem/base.h when another of them brings it. Run it after a
merge that brought files written against the umbrella; `ctest -R unit_layers_public_headers`
then says whether a layer reaches above itself.
"""
import os
import re
import subprocess
import sys

ROOT = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
# Headers that define a name come before those that only mention it (binding.h forward-declares
# adem_world and adem_case): the base first, the layers upwards.
ORDER = ["base", "vec3", "laws", "world", "files", "case", "frames", "run", "binding", "fields",
         "pile", "drum", "calibrate", "studies"]
IDENT = re.compile(r"\b(?:adem_|ADEM_|v3)\w*")


def owners():
    own = {}
    names = ORDER + sorted(os.path.splitext(h)[0] for h in os.listdir(os.path.join(ROOT, "include", "adem"))
                           if h.endswith(".h") and os.path.splitext(h)[0] not in ORDER + ["adem"])
    for n in names + ["internal/" + os.path.splitext(h)[0]
                      for h in sorted(os.listdir(os.path.join(ROOT, "include", "adem", "internal")))]:
        rel = "adem/%s.h" % n
        path = os.path.join(ROOT, "include", rel)
        out = subprocess.run(["cc", "-std=c17", "-E", "-I" + os.path.join(ROOT, "include"), path],
                             capture_output=True, text=True, check=True).stdout
        cur = None
        for line in out.splitlines():
            m = re.match(r'# \d+ "([^"]+)"', line)
            if m:
                cur = os.path.realpath(m.group(1))
                continue
            if cur == os.path.realpath(path):
                for t in IDENT.findall(line):
                    own.setdefault(t, rel)
        for t in re.findall(r"#define\s+((?:ADEM_|adem_)\w*)", open(path).read()):
            own.setdefault(t, rel)
    return own


def code_of(text):
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    return re.sub(r'"(\\.|[^"\\\n])*"', '""', text)


GONE = re.compile(r'^#include "(adem/output|files|fileio|plot)\.h"\n', flags=re.M)


def gone(path, own):
    """The includes of headers that are gone, replaced by the ones that hold their names now."""
    text = open(path).read()
    if not GONE.search(text):
        if not ("/studies/" in path and re.search(r"\badem_(table_|validation_(plot|path)\b)", code_of(text))
                and '#include "table.h"' not in text):
            return
    used = {own[t] for t in set(IDENT.findall(code_of(text))) if t in own}
    have = set(re.findall(r'#include ["<](adem/[\w/]+\.h)[">]', text))
    add = [h for h in ("adem/files.h", "adem/internal/plot.h") if h in used and h not in have]
    m = GONE.search(text)
    new = "".join('#include "%s"\n' % h for h in add)
    if m:
        text = text[:m.start()] + new + text[m.end():]
        text = GONE.sub("", text)
    elif new:
        last = list(re.finditer(r'^#include "adem/[\w/]+\.h"\n', text, flags=re.M))[-1]
        text = text[:last.end()] + new + text[last.end():]
    if ("/studies/" in path and re.search(r"\badem_(table_|validation_(plot|path)\b)", code_of(text))
            and '#include "table.h"' not in text):
        last = list(re.finditer(r'^#include "[\w/]+\.h"\n', text, flags=re.M))[-1]
        text = text[:last.end()] + '#include "table.h"\n' + text[last.end():]
    open(path, "w").write(text)
    print("%s: headers that are gone replaced" % os.path.relpath(path, ROOT))


def main():
    files = sys.argv[1:]
    if not files:
        out = subprocess.run(["git", "-C", ROOT, "grep", "-lE",
                              '#include "(adem/adem|adem/output|files|fileio|plot)\\.h"', "--",
                              "src", "app"], capture_output=True, text=True).stdout
        files = [os.path.join(ROOT, f) for f in out.split()]
    own = owners()
    for path in files:
        gone(path, own)
        text = open(path).read()
        m = re.search(r'^#include ["<]adem/adem\.h[">]\n', text, flags=re.M)
        if not m:
            continue
        need = {own[t] for t in set(IDENT.findall(code_of(text))) if t in own}
        have = set(re.findall(r'#include ["<](adem/[\w/]+\.h)[">]', text)) - {"adem/adem.h"}
        need -= have
        if (need | have) - {"adem/base.h", "adem/laws.h"}:
            need.discard("adem/base.h")  # every other public header but laws.h includes it
        if not need and not have:
            need = {"adem/base.h"}
        new = "".join('#include "%s"\n' % h for h in sorted(need))
        open(path, "w").write(text[:m.start()] + new + text[m.end():])
        print("%s: %s" % (os.path.relpath(path, ROOT), " ".join(sorted(need)) or "(nothing more)"))


if __name__ == "__main__":
    main()
