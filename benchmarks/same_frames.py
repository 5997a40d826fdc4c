#!/usr/bin/env python3
"""Checks that two pce-sim builds simulate the shipped scenes to the same bits.

    benchmarks/same_frames.py record DIR PCE_SIM       # run the scenes, keep their outputs in DIR
    benchmarks/same_frames.py compare DIR_A DIR_B      # compare two recorded sets
    benchmarks/same_frames.py check DIR PCE_SIM        # record into DIR.new and compare with DIR

Every shipped scene (examples/scenes/*.json) runs for a few frames (SCENES: 20 for most, 15
for the hammocks and lift_two_cloths, 2 for drop_130k), under Newton (`--mode newton`) and
under block descent (`--mode block_descent`), each with `--threads 1` and `--threads 2`,
writing every frame's OBJ. Two sets are the same when every OBJ file is byte for byte the
same and every stats.jsonl record is the same with its timing fields (`*_ms`, `wall_ms` and
the counters ending in `_ms`) left out. Keys only the second set's records have (counters a
change added) are listed once and not compared. A block-descent record of a build that
counted sweeps as Newton iterations (before `sweeps` and `sweep_records`) is read as the
newer form: its `newton_iterations` as `sweeps`, its `iterations` (residuals) as
`sweep_records`, `stop` "block_descent" as "sweeps", its counter `detections` as
`bound_measurements`, and without Newton's linear-solver counters, which block descent no
longer reports. This is for a change meant not to change
results (a restructure), made on one machine: the last bits of a simulation depend on the
CPU's libm and BLAS code paths, so a set recorded on another machine is not comparable.
"""
import filecmp
import json
import os
import subprocess
import sys

SCENES = [("twist", 20), ("drape", 20), ("strands", 20), ("crumple", 20), ("ball_drop", 20), ("pile", 20),
          ("hammock", 15), ("hammock_frictionless", 15), ("lift_two_cloths", 15), ("drop_130k", 2)]
MODES = ["newton", "block_descent"]
THREADS = [1, 2]
# What block descent reported under Newton's names before it had its own records.
NEWTON_ONLY_COUNTERS = ["analyses", "analyze_ms", "cg_iterations", "factorizations", "factorize_ms",
                        "pattern_blocks"]
RENAMED_COUNTERS = {"detections": "bound_measurements"}
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def all_runs():
    """(run name, scene, frames, mode, threads) of every run."""
    shipped = sorted(f[:-5] for f in os.listdir(os.path.join(ROOT, "examples", "scenes")) if f.endswith(".json"))
    listed = [scene for scene, _ in SCENES]
    missing = [scene for scene in shipped if scene not in listed]
    if missing:
        raise SystemExit("same_frames.py: shipped scenes without an entry in SCENES: " + ", ".join(missing))
    for scene, frames in SCENES:
        for mode in MODES:
            for threads in THREADS:
                yield f"{scene}_{mode}_t{threads}", scene, frames, mode, threads


def record(out, exe):
    for name, scene, frames, mode, threads in all_runs():
        d = os.path.join(out, name)
        cmd = [exe, os.path.join(ROOT, "examples", "scenes", scene + ".json"), "--frames", str(frames),
               "--mode", mode, "--threads", str(threads), "--out", d]
        print(" ".join(cmd[1:]), flush=True)
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def as_sweeps(record):
    """A block-descent record of a build before `sweeps`, in the newer form (see the docstring)."""
    if record.get("stop") != "block_descent" or "sweeps" in record:
        return record
    record = dict(record)
    record["sweeps"] = record["newton_iterations"]
    record["newton_iterations"] = 0
    record["sweep_records"] = [{"residual": it["residual"]} for it in record["iterations"]]
    record["iterations"] = []
    record["stop"] = "sweeps"
    record["counters"] = {RENAMED_COUNTERS.get(k, k): v for k, v in record["counters"].items()
                          if k not in NEWTON_ONLY_COUNTERS}
    return record


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
    for name, *_ in all_runs():
        da, db = os.path.join(a, name), os.path.join(b, name)
        objs = sorted(f for f in os.listdir(da) if f.endswith(".obj"))
        if objs != sorted(f for f in os.listdir(db) if f.endswith(".obj")):
            print(f"{name}: different frame files")
            differences += 1
            continue
        _, mismatch, errors = filecmp.cmpfiles(da, db, objs, shallow=False)
        with open(os.path.join(da, "stats.jsonl")) as fa, open(os.path.join(db, "stats.jsonl")) as fb:
            ra = [untimed(as_sweeps(json.loads(line))) for line in fa if line.strip()]
            rb = [untimed(as_sweeps(json.loads(line))) for line in fb if line.strip()]
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
