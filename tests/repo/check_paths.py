#!/usr/bin/env python3
"""Every repository path that a comment, README or configuration names exists (the repository explains itself:
no reference to a file that is not in it). Paths are taken as words starting with a top-level folder; words
with placeholders (<service>, {turbine}, *, ..) are patterns, not paths."""
import os
import re
import subprocess
import sys

TOP = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PATH = re.compile(r"(?<![\w/.-])((?:common|services|deploy|tests|idl|plant_sim|docs|\.ci)/[\w./@+-]*[\w/])")
SKIP_EXT = (".csv", ".sqlite", ".gz", ".png")


def main():
    try:
        files = subprocess.run(["git", "-C", TOP, "ls-files"], capture_output=True, text=True,
                               check=True).stdout.split()
    except (OSError, subprocess.CalledProcessError):  # a source tree without git: every file but builds
        files = [os.path.relpath(os.path.join(d, f), TOP) for d, dirs, fs in os.walk(TOP) for f in fs
                 if not os.path.relpath(d, TOP).startswith(("build", ".git"))]
    missing = []
    for f in files:
        if f.endswith(SKIP_EXT) or f.startswith("tests/repo/"):
            continue  # data, and the repository checks themselves (they create scratch paths)
        try:
            text = open(os.path.join(TOP, f), encoding="utf-8").read()
        except (UnicodeDecodeError, OSError):
            continue
        for n, line in enumerate(text.splitlines(), 1):
            for m in PATH.finditer(line):
                p = m.group(1)
                rest = line[m.end():m.end() + 2].lstrip("-_.")
                if rest[:1] in ("<", "{", "*", "$") or ".." in p:
                    continue  # a pattern such as deploy/config/<service>.yaml
                path = os.path.join(TOP, p.rstrip("/"))
                if not (os.path.exists(path) or os.path.exists(path + ".cpp")):  # a program by its source
                    missing.append(f"{f}:{n}: {p}")
    for m in missing:
        print(m)
    print(f"check_paths: {len(files)} files, {len(missing)} missing path(s)")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
