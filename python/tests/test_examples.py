# SPDX-License-Identifier: MIT
"""The Python example and the timing script run (few pairs, so in seconds) and write what
they promise."""

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
    rows = [line.split() for line in r.stdout.splitlines() if line.split()[:1] and line.split()[0] in ("analytic", "exact", "numerical")]
    assert [row[0] for row in rows] == ["analytic", "exact", "numerical"]
    assert float(rows[1][3]) < 1e-12 and float(rows[2][3]) == 0.0  # exact is numerical to roundoff


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
