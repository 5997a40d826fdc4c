#!/usr/bin/env python3
"""Two pce-bench binaries, one after the other, in alternating rounds on one machine.

    benchmarks/compare_pce_bench.py BEFORE AFTER ROUNDS [FILTER] [--csv OUT.csv]

BEFORE and AFTER are pce-bench executables (an older commit's built from `git archive REV`).
Each round runs both, in alternating order, each with five repetitions in random order
(`--benchmark_repetitions=5 --benchmark_enable_random_interleaving=true
--benchmark_min_time=0.05`); a row's time is the fastest of all its repetitions (ns per pair,
real time), the estimate least disturbed by other load. Rows one binary lacks are blank.
benchmarks/results/pce_bench_before_after.csv is its output for docs/pce-bench.md.
"""
import csv
import json
import subprocess
import sys


def main(argv):
    out_csv = None
    if "--csv" in argv:
        i = argv.index("--csv")
        out_csv = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    if len(argv) < 4:
        sys.exit(__doc__)
    before, after, rounds = argv[1], argv[2], int(argv[3])
    flt = argv[4] if len(argv) > 4 else "(vertex_face|edge_edge)/"
    best = {before: {}, after: {}}
    for r in range(rounds):
        for exe in ([before, after] if r % 2 == 0 else [after, before]):
            out = subprocess.run([exe, f"--benchmark_filter={flt}", "--benchmark_format=json",
                                  "--benchmark_min_time=0.05", "--benchmark_repetitions=5",
                                  "--benchmark_enable_random_interleaving=true"],
                                 capture_output=True, text=True, check=True).stdout
            for b in json.loads(out)["benchmarks"]:
                if b.get("run_type") != "iteration":
                    continue
                name = b.get("run_name", b["name"])
                best[exe][name] = min(best[exe].get(name, float("inf")), b["real_time"])
    names = sorted(set(best[before]) | set(best[after]),
                   key=lambda n: (n.split("/")[0], n.split("/")[2], n.split("/")[1]))
    rows = []
    for n in names:
        a, b = best[before].get(n), best[after].get(n)
        rows.append([n, f"{a:.1f}" if a else "", f"{b:.1f}" if b else "", f"{b / a:.3f}" if a and b else ""])
    print(f"{'row':42s} {'before':>8s} {'after':>8s} {'after/before':>12s}")
    for r in rows:
        print(f"{r[0]:42s} {r[1]:>8s} {r[2]:>8s} {r[3]:>12s}")
    if out_csv:
        with open(out_csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["benchmark", "before_ns", "after_ns", "after_over_before"])
            w.writerows(rows)


if __name__ == "__main__":
    main(sys.argv)
