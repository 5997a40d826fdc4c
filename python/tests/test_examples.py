# SPDX-License-Identifier: MIT
"""The Python example and the timing script run (few pairs, so in seconds), write what they
promise, and what they compare differs where it should and agrees where it must."""

import json
import subprocess
import sys

from conftest import REPO


def test_accuracy_vs_cost_example_runs_and_writes_its_plot(tmp_path):
    out = tmp_path / "plot.png"
    r = subprocess.run(
        [sys.executable, str(REPO / "examples/python/accuracy_vs_cost.py"), "--pairs", "300", "--out", str(out)],
        check=True, capture_output=True, text=True,
    )  # fmt: skip
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    names = ("analytic", "exact", "gauss_newton", "abs", "numerical")
    rows = {line.split()[0]: line.split() for line in r.stdout.splitlines() if line.split()[:1] and line.split()[0] in names}
    assert sorted(rows) == sorted(names)
    distance = {name: float(row[3]) for name, row in rows.items()}
    # exact is the numerical projection to roundoff; the approximations are measurably not
    # (300 pairs, seed 1: analytic 6e-4, Gauss-Newton 2.3e-3, abs 2.6e-3), so the comparison
    # would notice two strategies computing the same matrix
    assert distance["numerical"] == 0.0 and distance["exact"] < 1e-12
    assert all(distance[name] > 1e-5 for name in ("analytic", "gauss_newton", "abs"))
    assert distance["gauss_newton"] != distance["abs"] != distance["analytic"]


def test_python_batch_timing_script_runs(pce_bench, tmp_path):
    out = tmp_path / "timing.json"
    subprocess.run(
        [sys.executable, str(REPO / "benchmarks/python_batch.py"), "--pce-bench", str(pce_bench), "--pairs", "3000",
         "--rounds", "1", "--json", str(out)],
        check=True, capture_output=True, text=True,
    )  # fmt: skip
    result = json.loads(out.read_text())
    assert result["pairs"] == 3000 and len(result["python"]) == 7
    assert all(row["ns_per_pair"] > 0 for row in result["python"])
    # What the timed cases compute: the float64 variants (out=, two threads, every output,
    # blocks of 1 024) exactly the plain call's; float32 its own rounding (3000 pairs, seed
    # 2023: 2e-4 of the largest magnitude), so the float32 case is not float64 by mistake.
    diff = result["largest_difference_to_plain_call"]
    assert [diff[case] for case in ("out=", "2 threads", "every output", "blocks")] == [0.0] * 4
    assert 0.0 < diff["float32"] < 1e-3 * diff["float64 magnitude"]


def test_lift_from_arrays_example_follows_the_hand():
    """The tutorial's Python scene: built from NumPy arrays, its pinned corner moved from
    Python each frame; after 40 frames (lifted 0.35 m) the corner is within the pin's give
    of the hand (the canvas's weight over k = 1e4 N/m: 0.05 mm) and the silk has moved."""
    r = subprocess.run(
        [sys.executable, str(REPO / "examples/python/lift_from_arrays.py"), "--frames", "40"],
        check=True, capture_output=True, text=True,
    )  # fmt: skip
    words = r.stdout.split()
    assert words[:2] == ["frame", "40:"]
    assert 0 <= float(words[3]) < 0.05  # mm from the hand
    assert float(words[-2]) > 0.05  # the silk dragged along, m
