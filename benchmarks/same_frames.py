#!/usr/bin/env python3
"""Checks that two pce-sim builds simulate the shipped scenes to the same bits.

    benchmarks/same_frames.py record DIR PCE_SIM       # run the scenes, keep their outputs in DIR
    benchmarks/same_frames.py compare DIR_A DIR_B      # compare two recorded sets
    benchmarks/same_frames.py check DIR PCE_SIM        # record into DIR.new and compare with DIR

Each shipped scene runs for a few frames (twist, drape, strands, crumple, ball_drop, pile:
20; hammock, hammock_frictionless: 15), with `--threads 1` and with `--threads 2`, writing
every frame's OBJ. Two sets are the same when every OBJ file is byte for byte the same and
every stats.jsonl record is the same with its timing fields (`*_ms`, `wall_ms` and the
counters ending in `_ms`) left out. Keys only the second set's records have (counters a
change added) are listed once and not compared. This is for a change meant not to change results (a
restructure), made on one machine: the last bits of a simulation depend on the CPU's libm
and BLAS code paths, so a set recorded on another machine is not comparable.
"""
import filecmp
import json
import os
import subprocess
import sys

SCENES = [("twist", 20), ("drape", 20), ("strands", 20), ("crumple", 20), ("ball_drop", 20), ("pile", 20),
          ("hammock", 15), ("hammock_frictionless", 15)]
THREADS = [1, 2]
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def record(out, exe):
    for scene, frames in SCENES:
        for threads in THREADS:
            d = os.path.join(out, f"{scene}_t{threads}")
            cmd = [exe, os.path.join(ROOT, "examples", "scenes", scene + ".json"), "--frames", str(frames),
                   "--threads", str(threads), "--out", d]
            print(" ".join(cmd[1:]), flush=True)
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def untimed(value):
    """A stats record without its timing fields."""
    if isinstance(value, dict):
        return {k: untimed(v) for k, v in value.items()
                if not (k.endswith("_ms") or k == "effects")}  # `effects` holds ms per effect
    if isinstance(value, list):
        return [untimed(v) for v in value]
    return value


def common(a, b, added, path=""):
    """b's record restricted to the keys a's has (recursively); the keys only b has go into `added`."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = {}
        for k, v in b.items():
            if k in a:
                out[k] = common(a[k], v, added, path + k + ".")
            else:
                added.add(path + k)
        return out
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        return [common(x, y, added, path) for x, y in zip(a, b)]
    return b


def compare(a, b):
    differences = 0
    runs = 0
    added = set()
    for scene, _ in SCENES:
        for threads in THREADS:
            name = f"{scene}_t{threads}"
            da, db = os.path.join(a, name), os.path.join(b, name)
            objs = sorted(f for f in os.listdir(da) if f.endswith(".obj"))
            if objs != sorted(f for f in os.listdir(db) if f.endswith(".obj")):
                print(f"{name}: different frame files")
                differences += 1
                continue
            _, mismatch, errors = filecmp.cmpfiles(da, db, objs, shallow=False)
            with open(os.path.join(da, "stats.jsonl")) as fa, open(os.path.join(db, "stats.jsonl")) as fb:
                ra = [untimed(json.loads(line)) for line in fa if line.strip()]
                rb = [untimed(json.loads(line)) for line in fb if line.strip()]
            rb = [common(x, y, added) for x, y in zip(ra, rb)] + rb[len(ra):]
            stats_same = ra == rb
            runs += 1
            if mismatch or errors or not stats_same:
                differences += 1
                print(f"{name}: {len(mismatch) + len(errors)} of {len(objs)} OBJ frames differ"
                      f"{'' if stats_same else ', stats.jsonl differs'}")
            else:
                print(f"{name}: {len(objs)} OBJ frames byte-identical, stats.jsonl equal without timings")
    if added:
        print("keys only the second set has (not compared): " + ", ".join(sorted(added)))
    print(f"{runs - differences} of {runs} runs the same")
    return differences == 0


def main(argv):
    if len(argv) == 3 and argv[0] == "record":
        record(argv[1], os.path.abspath(argv[2]))
        return 0
    if len(argv) == 3 and argv[0] == "compare":
        return 0 if compare(argv[1], argv[2]) else 1
    if len(argv) == 3 and argv[0] == "check":
        new = argv[1].rstrip("/") + ".new"
        record(new, os.path.abspath(argv[2]))
        return 0 if compare(argv[1], new) else 1
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
