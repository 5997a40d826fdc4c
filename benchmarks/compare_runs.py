#!/usr/bin/env python3
"""Summarises pce-sim runs side by side, one CSV row per run.

    benchmarks/compare_runs.py OUT.csv LABEL=DIR [LABEL=DIR ...]

Each DIR is a pce-sim output directory (stats.jsonl, or stats.json of versions that wrote
no stats.jsonl). A row holds the run's label, frames, mean ms per frame and its stages,
Newton iterations and broad-phase queries per frame (per contact effect: the counter sums
both effects' queries), iteration caps, line-search failures and frames with intersecting
triangle pairs, and, where stats.json records Newton iterations, how many were cut by a
step limit and how many backtracked. benchmarks/results/scenes_before_after.csv is its
output for the comparisons quoted in docs/simulation.md and CHANGELOG.md: each shipped
scene at 7b22ee2 and at later commits, labelled by commit. Rows marked "(one after the
other)" ran alone, one after the other on one machine; the threads rows ran alone; every
other pair of rows ran side by side on the two cores of one machine (one thread each).
A label "run with C" marks an older commit run again in the same session as C's rows, to
be compared with those.
"""
import csv
import json
import os
import sys

STAGES = ["broad_phase_ms", "pair_ms", "line_search_ms", "solve_ms", "assembly_ms"]


def load(directory):
    jsonl = os.path.join(directory, "stats.jsonl")
    if os.path.exists(jsonl):
        with open(jsonl) as f:
            return [json.loads(line) for line in f if line.strip()]
    with open(os.path.join(directory, "stats.json")) as f:
        return json.load(f)


def contact_effects(record):
    return sum(1 for name in record.get("effects", {}) if name in ("self_vertex_face", "self_edge_edge")) or 1


def row(label, records):
    n = len(records)
    mean = lambda key: sum(r[key] for r in records) / n
    out = {
        "run": label,
        "frames": n,
        "ms_per_frame": mean("wall_ms"),
        "newton_per_frame": mean("newton_iterations"),
        "queries_per_frame_per_effect": sum(r["counters"].get("broad_phase_queries", 0) / contact_effects(r)
                                            for r in records) / n,
        "iteration_caps": sum(1 for r in records if r["hit_iteration_cap"]),
        "line_search_failures": sum(r["line_search_failures"] for r in records),
        "frames_with_intersections": sum(1 for r in records if r["intersecting_triangle_pairs"] > 0),
    }
    for key in STAGES:
        out[key] = mean(key)
    if all("iterations" in r for r in records):
        its = [it for r in records for it in r["iterations"]]
        out["step_limited_iterations"] = sum(1 for it in its if it["step_limit"] < 1)
        out["backtracked_iterations"] = sum(1 for it in its if it["alpha"] < it["step_limit"])
    return out


def main(argv):
    if len(argv) < 3 or any("=" not in a for a in argv[2:]):
        print(__doc__, file=sys.stderr)
        return 2
    rows = [row(label, load(directory)) for label, directory in (a.split("=", 1) for a in argv[2:])]
    columns = list(dict.fromkeys(k for r in rows for k in r))
    with open(argv[1], "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in r.items()})
    for r in rows:
        print(", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in r.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
