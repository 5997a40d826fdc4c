#!/usr/bin/env python3
"""What block descent's speed costs in accuracy, on a scene (by default the hammock).

    benchmarks/block_accuracy.py --pce-sim PATH --results DIR [--scene FILE] [--frames 60]
                                 [--at 30,60] [--sweeps 10,20,50,100] [--newton 0.01]
                                 [--reference 1e-4] [--threads 1]

Runs the scene once per configuration, one run at a time: Newton at the reference tolerance
(the "exact" answer), Newton at each `--newton` tolerance and block descent at each number
of sweeps per step, all for `--frames` frames, writing every frame the scene writes. Then,
for each configuration and each frame of `--at`, the RMS over vertices of the distance to
the reference's positions (metres), and the mean ms/frame over all frames (wall_ms of
stats.jsonl), and the largest intersecting_triangle_pairs of any frame. Writes
DIR/block_accuracy.json and DIR/block_accuracy.md (the table). Timings compare within one
run of this script on an otherwise idle machine. Only the Python standard library is used.
"""

import argparse
import json
import os
import subprocess
import sys
import time

from run_all import deviation
from run_all import read_obj_vertices as read_obj
from scale_ladder import load_records as stats


def rms(a, b):
    """RMS over vertices of the distance between two runs' positions."""
    return deviation(a, b)[0]


def run(exe, scene, out, frames, threads, extra):
    cmd = [exe, scene, "--frames", str(frames), "--threads", str(threads), "--out", out] + extra
    t = time.monotonic()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return cmd, time.monotonic() - t


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pce-sim", required=True)
    ap.add_argument("--results", required=True)
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--scene", default=os.path.join(here, "..", "examples", "scenes", "hammock.json"))
    ap.add_argument("--frames", type=int, default=60)
    ap.add_argument("--at", default="30,60")
    ap.add_argument("--sweeps", default="10,20,50,100")
    ap.add_argument("--newton", default="0.01")
    ap.add_argument("--reference", type=float, default=1e-4)
    ap.add_argument("--threads", type=int, default=1)
    a = ap.parse_args(argv)
    at = [int(f) for f in a.at.split(",")]
    if max(at) > a.frames:
        ap.error("--at lists a frame beyond --frames")
    os.makedirs(a.results, exist_ok=True)
    configs = [("newton", f"tolerance {a.reference:g} (reference)", ["--tolerance", repr(a.reference)])]
    configs += [("newton", f"tolerance {t}", ["--tolerance", t]) for t in a.newton.split(",") if t]
    configs += [("block_descent", f"{n} sweeps", ["--mode", "block_descent", "--iterations", n])
                for n in a.sweeps.split(",") if n]
    rows = []
    for i, (mode, label, extra) in enumerate(configs):
        out = os.path.join(a.results, "runs", f"accuracy_{i}")
        print(f"{mode} {label} ...", file=sys.stderr, flush=True)
        cmd, seconds = run(a.pce_sim, a.scene, out, a.frames, a.threads, extra)
        records = stats(out)
        rows.append({"mode": mode, "label": label, "command": " ".join(cmd), "dir": out, "seconds": seconds,
                     "ms_per_frame": sum(r["wall_ms"] for r in records) / len(records),
                     "iterations_per_frame": sum(r.get("sweeps") or r["newton_iterations"] for r in records) / len(records),
                     "max_intersecting_pairs": max(r.get("intersecting_triangle_pairs", 0) for r in records)})
    reference = rows[0]
    for r in rows:
        r["rms"] = {}
        for f in at:
            r["rms"][str(f)] = rms(read_obj(os.path.join(r["dir"], f"frame_{f:04d}.obj")),
                                   read_obj(os.path.join(reference["dir"], f"frame_{f:04d}.obj")))
    with open(os.path.join(a.results, "block_accuracy.json"), "w") as f:
        json.dump({"scene": a.scene, "frames": a.frames, "threads": a.threads, "rows": rows}, f, indent=1)
    lines = [f"| run | ms/frame | iterations/frame | " + " | ".join(f"RMS to reference, frame {f} (mm)" for f in at)
             + " | intersecting pairs |", "|---|---|---|" + "---|" * len(at) + "---|"]
    for r in rows:
        lines.append(f"| {r['mode']}, {r['label']} | {r['ms_per_frame']:.0f} | {r['iterations_per_frame']:.1f} | "
                     + " | ".join(f"{1000 * r['rms'][str(f)]:.3g}" for f in at) + f" | {r['max_intersecting_pairs']} |")
    with open(os.path.join(a.results, "block_accuracy.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
