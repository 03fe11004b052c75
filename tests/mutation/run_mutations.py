#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Mutation testing: does the default test run notice a deliberate defect?

Each mutation in a JSON file is [name, file, old text, new text]. It is applied to a git
worktree of HEAD (its own build folder, so the working tree and build/ are left alone),
built, and judged by the default test run (ctest -LE slow): KILLED when a test fails,
SURVIVED when every test passes, COMPILE ERROR, or SKIP when the old text is not found
exactly once (the code has moved on: update the file). A --focus regex runs the likely
tests first, which kills most mutations in seconds; a survivor always gets the whole run.

    python3 tests/mutation/run_mutations.py tests/mutation/analysis.json \\
        --focus 'debris|photo' --out /tmp/analysis.tsv
"""
import argparse
import json
import pathlib
import subprocess
import sys
import time


def run(cmd, cwd):
    return subprocess.run(cmd, cwd=cwd, shell=True, capture_output=True, text=True)


def first_failure(output):
    for line in output.splitlines():
        if "***Failed" in line or "***Exception" in line or "***Timeout" in line:
            return " ".join(line.split())[:160]
    return "ctest failed"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mutations", help="JSON list of [name, file, old, new]")
    ap.add_argument("--focus", help="ctest -R regex of the tests to try first")
    ap.add_argument("--worktree", default="/tmp/fesph_mutants",
                    help="git worktree of HEAD to mutate (made when missing)")
    ap.add_argument("--out", default="-", help="results, one tab-separated line each")
    args = ap.parse_args()

    repo = pathlib.Path(__file__).resolve().parents[2]
    wt = pathlib.Path(args.worktree)
    if not wt.exists():
        r = run(f"git worktree add --detach {wt} HEAD", repo)
        if r.returncode != 0:
            sys.exit(r.stderr)
    build = wt / "build"
    if not (build / "CMakeCache.txt").exists():
        r = run("cmake -S . -B build -DCMAKE_BUILD_TYPE=Release", wt)
        if r.returncode != 0:
            sys.exit(r.stdout + r.stderr)
    if run("cmake --build build -j2", wt).returncode != 0:
        sys.exit(f"{wt}: the unmutated code does not build")

    out = sys.stdout if args.out == "-" else open(args.out, "a")
    # a mutation that makes a test hang is killed by the timeout (a test takes < 2 min here)
    ctest = "ctest --test-dir build -LE slow -j2 --stop-on-failure --timeout 300"
    for name, file, old, new in json.load(open(args.mutations)):
        path = wt / file
        text = path.read_text()
        if text.count(old) != 1:
            out.write(f"{name}\tSKIP (old text found {text.count(old)} times)\n")
            out.flush()
            continue
        start = time.time()
        path.write_text(text.replace(old, new))
        try:
            if run("cmake --build build -j2", wt).returncode != 0:
                result = "COMPILE ERROR"
            else:
                result = "SURVIVED"
                for extra in ([f"-R '{args.focus}'"] if args.focus else []) + [""]:
                    r = run(f"{ctest} {extra}", wt)
                    if r.returncode != 0:
                        result = "KILLED: " + first_failure(r.stdout)
                        break
        finally:
            path.write_text(text)
        out.write(f"{name}\t{result}\t{time.time() - start:.0f} s\n")
        out.flush()
    run("cmake --build build -j2", wt)  # leave the worktree's build unmutated


if __name__ == "__main__":
    main()
