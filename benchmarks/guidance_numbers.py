#!/usr/bin/env python3
"""The numbers of benchmarks/guidance.md, computed from a results folder.

    benchmarks/guidance_numbers.py [--results DIR] [--page FILE]    rewrite the page's numbers
    benchmarks/guidance_numbers.py --check [--results DIR] [--page FILE]

guidance.md is hand-written advice whose every measured number sits in a marked span,
<!-- gen:NAME -->value<!-- /gen -->. This script computes each NAME from the results folder
(default benchmarks/results: machine.json, pce_bench.csv, accuracy.json, accuracy.log,
broad_phase.csv, threads.csv, scenes.csv) and writes the values into the spans; nothing
outside the spans changes. benchmarks/run_all calls it when it writes docs/benchmarks.md.

It also checks the claims the advice makes in words (for example "analytic is PSD on every
measured pair"); a claim the results contradict is printed. --check rewrites nothing: it
exits 1 when a span differs from what the results give, a value cannot be computed, a span
names no known value, a claim fails (the advice must then be rewritten by hand), or
docs/benchmarks.md does not show the advice as guidance.md gives it, and 0 otherwise. Python 3 standard library only.
"""

import argparse
import csv
import difflib
import json
import math
import re
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SPAN = re.compile(r"<!-- gen:([a-z0-9_]+) -->(.*?)<!-- /gen -->", re.S)
SHORT_SCENES = ["hammock_coarse", "drape", "strands", "twist"]  # run at tolerances 0.1, 0.01, 0.001
STRATEGIES = ["analytic", "abs", "exact", "gauss_newton", "numerical"]
KINDS = ["vertex_face", "edge_edge", "point_edge"]  # point_point: every strategy but abs is exact there


class Missing(Exception):
    """A value the results folder cannot give (a quick run, a step not run)."""


# ---------------------------------------------------------------------------------------------
# Formatting.

def thousands(x):
    """74000 -> '74 000' (a space between groups, as docs/benchmarks.md writes them)."""
    return f"{x:,.0f}".replace(",", " ")


def sig(x, digits=2):
    """x to `digits` significant digits, without an exponent for 0.01 <= |x| < 10^digits."""
    if x == 0:
        return "0"
    if 0.01 <= abs(x) < 10 ** digits:
        d = max(digits - 1 - math.floor(math.log10(abs(x))), 0)
        return f"{x:.{d}f}"
    return thousands(float(f"{x:.{digits - 1}e}"))


SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def sci(x, digits=1):
    """3.7e-16 -> '4e-16' (digits=1) or '3.7e-16' (digits=2); a minus sign as '−'."""
    m, e = f"{x:.{digits - 1}e}".split("e")
    return f"{m}e{int(e)}".replace("-", "−", 1 if x < 0 else 0)


def power(x):
    """1.39e6 -> '1.4·10⁶'."""
    m, e = f"{x:.1e}".split("e")
    return f"{m}·10{str(int(e)).translate(SUPERSCRIPT)}"


def pct(x):
    """0.0417 -> '4' (percent, no sign)."""
    return f"{100 * x:.0f}"


def signed_pct(x):
    s = f"{100 * x:+.0f}"
    return s.replace("-", "−") + " %"


def span(lo, hi, f=sig, sep="–"):
    """'lo–hi', or one value when both print alike."""
    a, b = f(lo), f(hi)
    return a if a == b else f"{a}{sep}{b}"


def vspan(values, f=sig):
    """The range of `values`."""
    values = list(values)
    return span(min(values), max(values), f)


def pct_span(values):
    return span(min(values), max(values), pct) + " %"


# ---------------------------------------------------------------------------------------------
# Reading the results folder.

class Results:
    def __init__(self, folder):
        self.folder = Path(folder)
        self._cache = {}

    def _file(self, name):
        p = self.folder / name
        if not p.is_file():
            raise Missing(f"{p} not found")
        return p

    def _csv(self, name):
        if name not in self._cache:
            with open(self._file(name), newline="") as f:
                rows = list(csv.DictReader(f))
            for r in rows:
                for k, v in r.items():
                    try:
                        r[k] = float(v)
                    except (TypeError, ValueError):
                        r[k] = None if v == "" else v
            self._cache[name] = rows
        return self._cache[name]

    def machine(self):
        return json.loads(self._file("machine.json").read_text())

    def ns(self, pair, quantity, scalar="double"):
        for r in self._csv("pce_bench.csv"):
            if (r["pair"], r["quantity"], r["scalar"]) == (pair, quantity, scalar):
                return r["ns_per_pair"]
        raise Missing(f"pce_bench.csv: no {pair}/{quantity}/{scalar}")

    def accuracy(self):
        if "accuracy" not in self._cache:
            self._cache["accuracy"] = json.loads(self._file("accuracy.json").read_text())
        return self._cache["accuracy"]

    def acc_rows(self, pair=None, scalar=None, strategy=None, family=None):
        return [r for r in self.accuracy()["rows"]
                if (pair is None or r["pair"] == pair) and (scalar is None or r["scalar"] == scalar)
                and (strategy is None or r["strategy"] == strategy) and (family is None or r["family"] == family)]

    def median_dist(self, pair, strategy, family, scalar="double"):
        """The median of the groups' median distances, as docs/benchmarks.md's tables."""
        meds = [r["rel_dist_median"] for r in self.acc_rows(pair, scalar, strategy, family)
                if r["rel_dist_median"] is not None]
        if not meds:
            raise Missing(f"accuracy.json: no {pair}/{strategy}/{family}/{scalar}")
        return statistics.median(meds)

    def max_dist(self, pair, strategy, family, scalar="double"):
        mx = [r["rel_dist_max"] for r in self.acc_rows(pair, scalar, strategy, family) if r["rel_dist_max"] is not None]
        if not mx:
            raise Missing(f"accuracy.json: no {pair}/{strategy}/{family}/{scalar}")
        return max(mx)

    def worst_psd_violation(self, scalar, strategy):
        """accuracy.log: the most negative λ_min/max|λ| of a strategy (None if no violation)."""
        text = self._file("accuracy.log").read_text()
        m = re.search(rf"^{scalar} {strategy}\s+(\d+) violation\(s\), worst (\S+)", text, re.M)
        return (int(m.group(1)), float(m.group(2))) if m else (0, None)

    def scene(self, scene, strategy, mode="newton", tol=0.01, kind="config"):
        for r in self._csv("scenes.csv"):
            if (r["scene"], r["strategy"], r["mode"], r["kind"]) == (scene, strategy, mode, kind) and \
                    (r["tolerance"] == tol or (tol is None and r["tolerance"] is None)):
                return r
        raise Missing(f"scenes.csv: no {scene}/{kind}/{strategy}/{mode}/{tol}")

    def broad_phase(self):
        rows = self._csv("broad_phase.csv")
        sizes = sorted({r["triangles"] for r in rows})
        by = {(r["broad_phase"], r["triangles"]): r for r in rows}
        return sizes, by

    def threads(self):
        rows = self._csv("threads.csv")
        if len(rows) < 2:
            raise Missing("threads.csv: one thread count only")
        return rows[-1]


# ---------------------------------------------------------------------------------------------
# The values. Each entry: name -> function of Results returning the text of the span.

def newton_rows(R, scenes=SHORT_SCENES, tols=(0.1, 0.01, 0.001)):
    """(scene, tolerance) -> {strategy: row} for every Newton configuration present."""
    out = {}
    for s in scenes:
        for t in tols:
            try:
                out[(s, t)] = {k: R.scene(s, k, "newton", t) for k in STRATEGIES}
            except Missing:
                continue
    if not out:
        raise Missing("scenes.csv: no Newton rows")
    return out


def ms_ratios(R, exclude):
    """ms/frame of each strategy over analytic's at the same scene and tolerance."""
    rows = newton_rows(R)
    try:
        rows[("hammock", None)] = {k: R.scene("hammock", k, "newton", None) for k in STRATEGIES}
    except Missing:
        pass
    return [(sc, t, k, rs[k]["ms_per_frame"] / rs["analytic"]["ms_per_frame"] - 1)
            for (sc, t), rs in rows.items() for k in STRATEGIES if k != "analytic" and not exclude(sc, t, k)]


def strategy_ms_range(R):
    r = [x for *_, x in ms_ratios(R, lambda sc, t, k: (k == "numerical" and sc == "strands") or
                                  (k == "gauss_newton" and sc == "hammock_coarse" and t == 0.1))]
    return f"{signed_pct(min(r))} to {signed_pct(max(r))}"


def numerical_strands(R):
    r = [x for sc, t, k, x in ms_ratios(R, lambda sc, t, k: not (k == "numerical" and sc == "strands"))]
    return f"{signed_pct(min(r))} to {signed_pct(max(r))}"


def pair_share(R, scene, strategy):
    r = R.scene(scene, strategy)
    return r["pair_ms"] / r["ms_per_frame"]


def stage_shares(R, key):
    """Shares of a frame, Newton, analytic, each scene at its own tolerance (0.01)."""
    rows = [R.scene(s, "analytic") for s in SHORT_SCENES]
    try:
        rows.append(R.scene("hammock", "analytic", "newton", None))
    except Missing:
        pass
    return pct_span([r[key] / r["ms_per_frame"] for r in rows])


def tolerance_cost(R, loose, tight):
    rows = newton_rows(R)
    r = [rows[(s, tight)][k]["ms_per_frame"] / rows[(s, loose)][k]["ms_per_frame"]
         for s in SHORT_SCENES for k in STRATEGIES if (s, tight) in rows and (s, loose) in rows]
    if not r:
        raise Missing("scenes.csv: tolerances missing")
    return span(min(r), max(r)) + "×"


NOT_GN = [k for k in STRATEGIES if k != "gauss_newton"]


def deviation(R, scene, tol, strategies, unit="m"):
    """Range of the final states' RMS deviation from the reference over `strategies`."""
    d = [R.scene(scene, k, "newton", tol)["dev_rms"] for k in strategies]
    if any(x is None for x in d):
        raise Missing(f"scenes.csv: {scene} has no deviations")
    if unit == "m":
        return span(min(d), max(d)) + " m"
    scale = {"cm": 100, "mm": 1000}[unit]
    return span(min(d) * scale, max(d) * scale, lambda x: f"{x:.0f}") + " " + unit


def hammock_ms_range(R):
    ms = [R.scene("hammock", k, tol=None)["ms_per_frame"] / 1000 for k in STRATEGIES]
    return span(min(ms), max(ms), lambda x: f"{x:.1f}") + " s"


def newton_deviation_range(R, scene, unit):
    d = [r[k]["dev_rms"] for (s, t), r in newton_rows(R, [scene]).items() for k in STRATEGIES]
    if any(x is None for x in d):
        raise Missing(f"scenes.csv: {scene} has no deviations")
    scale = {"m": 1, "cm": 100, "mm": 1000}[unit]
    return span(min(d) * scale, max(d) * scale, lambda x: f"{x:.0f}") + " " + unit


def noise_floor(R, scene):
    r = R.scene(scene, "numerical", "newton", 1e-5, kind="noise_floor")
    if r["dev_rms"] is None:
        raise Missing(f"scenes.csv: {scene} has no noise floor")
    return r["dev_rms"]


def single_rows(R):
    rows = [(R.scene(s, k, "single", None), R.scene(s, k)) for s in SHORT_SCENES for k in STRATEGIES]
    return rows


def single_speedup(R):
    r = [n["ms_per_frame"] / s["ms_per_frame"] for s, n in single_rows(R)]
    return span(min(r), max(r), lambda x: f"{x:.0f}") + "×"


def single_residual(R):
    r = [s["residual_median"] for s, _ in single_rows(R)]
    return span(min(r), max(r), lambda x: f"{x:.1f}")


def single_deviation(R):
    r = [s["dev_rms"] for s, _ in single_rows(R)]
    if any(x is None for x in r):
        raise Missing("scenes.csv: single-solve rows have no deviations")
    return span(min(r), max(r)) + " m"


def psd_per_10k(R, scalar):
    n, _ = R.worst_psd_violation(scalar, "exact")
    ok = sum(r["configurations"] - r["not_ok"] for r in R.acc_rows(scalar=scalar, strategy="exact"))
    return f"{1e4 * n / ok:.0f}"


def bullet_over_fcl(R, key, sizes):
    _, by = R.broad_phase()
    return [by[("bullet", n)][key] / by[("fcl", n)][key] for n in sizes]


def bp_sizes(R, lo=None, hi=None):
    sizes, by = R.broad_phase()
    s = [n for n in sizes if ("bullet", n) in by and ("fcl", n) in by and (lo is None or n >= lo)
         and (hi is None or n < hi)]
    if not s:
        raise Missing("broad_phase.csv: no sizes in range")
    return s


def bp_exponent(R, kinds, key="query_ms"):
    sizes, by = R.broad_phase()
    out = []
    for kind in kinds:
        pts = [(math.log(n), math.log(by[(kind, n)][key])) for n in sizes
               if (kind, n) in by and by[(kind, n)]["n"] >= 40 and by[(kind, n)][key]]
        if len(pts) < 2:
            raise Missing(f"broad_phase.csv: too few {kind} sizes")
        mx = sum(p[0] for p in pts) / len(pts)
        my = sum(p[1] for p in pts) / len(pts)
        out.append(sum((p[0] - mx) * (p[1] - my) for p in pts) / sum((p[0] - mx) ** 2 for p in pts))
    return out


LARGE = 10000  # triangles: where Bullet's queries become slower than FCL's
BUILD_LARGE = 30000


def vf(R, q, scalar="double"):
    return R.ns("vertex_face", q, scalar)


VALUES = {
    "run": lambda R: "{date_utc} at commit {commit}".format(**R.machine()),
    # 1. analytic
    "measured_pairs": lambda R: thousands(round(R.accuracy()["settings"]["samples_measured"], -3)),
    "analytic_x_exact_hessian": lambda R: sig(vf(R, "analytic") / vf(R, "exact_hessian"), 3),
    "numerical_over_analytic": lambda R: sig(vf(R, "numerical") / vf(R, "analytic")),
    "analytic_vs_exact_iterations": lambda R: pct(max(
        abs(r["analytic"]["newton_per_frame"] / r["exact"]["newton_per_frame"] - 1) for r in newton_rows(R).values())),
    "analytic_random": lambda R: pct_span([R.median_dist(k, "analytic", "random") for k in KINDS]),
    # 2. exact
    "exact_random_double": lambda R: sci(R.median_dist("vertex_face", "exact", "random")),
    "exact_random_float": lambda R: sci(R.median_dist("vertex_face", "exact", "random", "float")),
    "exact_x_analytic": lambda R: sig(vf(R, "exact") / vf(R, "analytic")),
    "numerical_over_exact": lambda R: f"{vf(R, 'numerical') / vf(R, 'exact'):.0f}",
    "exact_psd_per_10k_double": lambda R: psd_per_10k(R, "double"),
    "exact_psd_per_10k_float": lambda R: psd_per_10k(R, "float"),
    "exact_worst_lambda_double": lambda R: sci(-abs(R.worst_psd_violation("double", "exact")[1] or 0)),
    "exact_worst_lambda_float": lambda R: sci(-abs(R.worst_psd_violation("float", "exact")[1] or 0)),
    # 3. numerical
    "numerical_x_exact": lambda R: f"{vf(R, 'numerical') / vf(R, 'exact'):.0f}",
    "numerical_float_pp_near": lambda R: sci(R.median_dist("point_point", "numerical", "near_contact", "float")),
    "exact_float_pp_near": lambda R: sci(R.median_dist("point_point", "exact", "near_contact", "float")),
    "numerical_float_pe_near": lambda R: sci(R.median_dist("point_edge", "numerical", "near_contact", "float"), 2),
    "exact_float_pe_near": lambda R: sci(R.median_dist("point_edge", "exact", "near_contact", "float"), 2),
    # 4. gauss_newton
    "gn_x_analytic": lambda R: sig(vf(R, "gauss_newton") / vf(R, "analytic")),
    "gn_random": lambda R: pct_span([R.median_dist(k, "gauss_newton", "random") for k in KINDS]),
    "gn_near": lambda R: pct_span([R.median_dist(k, "gauss_newton", "near_contact") for k in KINDS]),
    "gn_iterations_short": lambda R: pct(max(
        abs(r["gauss_newton"]["newton_per_frame"] / r["analytic"]["newton_per_frame"] - 1)
        for (s, t), r in newton_rows(R).items() if t in (0.01, 0.001))),
    "gn_hammock_iterations": lambda R: "{} against {}".format(
        sig(R.scene("hammock", "gauss_newton", tol=None)["newton_per_frame"]),
        sig(R.scene("hammock", "analytic", tol=None)["newton_per_frame"])),
    "gn_coarse_loose_more": lambda R: pct(R.scene("hammock_coarse", "gauss_newton", tol=0.1)["newton_per_frame"] /
                                          R.scene("hammock_coarse", "analytic", tol=0.1)["newton_per_frame"] - 1),
    "gn_coarse_loose_iterations": lambda R: "{} against {}".format(
        sig(R.scene("hammock_coarse", "gauss_newton", tol=0.1)["newton_per_frame"]),
        sig(R.scene("hammock_coarse", "analytic", tol=0.1)["newton_per_frame"])),
    "gn_coarse_loose_deviation": lambda R: "{} m against {} m".format(
        sig(R.scene("hammock_coarse", "gauss_newton", tol=0.1)["dev_rms"]),
        sig(R.scene("hammock_coarse", "analytic", tol=0.1)["dev_rms"])),
    # 5. abs
    "abs_near_point": lambda R: vspan([R.median_dist(k, "abs", "near_contact") for k in ("point_edge", "point_point")],
                                     f=lambda x: thousands(float(f"{x:.1e}"))),
    "abs_near_point_max": lambda R: power(max(R.max_dist(k, "abs", "near_contact") for k in ("point_edge", "point_point"))),
    "abs_elsewhere": lambda R: pct_span([R.median_dist(k, "abs", "random") for k in KINDS + ["point_point"]] +
                                        [R.median_dist(k, "abs", "near_contact") for k in ("vertex_face", "edge_edge")]),
    # 6. scenes
    "strategy_ms_range": strategy_ms_range,
    "hammock_ms_range": lambda R: hammock_ms_range(R),
    "numerical_strands": numerical_strands,
    "strands_pair_share": lambda R: "{} % against {} %".format(pct(pair_share(R, "strands", "numerical")),
                                                            pct(pair_share(R, "strands", "analytic"))),
    "gn_coarse_loose_ms": lambda R: signed_pct(R.scene("hammock_coarse", "gauss_newton", tol=0.1)["ms_per_frame"] /
                                               R.scene("hammock_coarse", "analytic", tol=0.1)["ms_per_frame"] - 1),
    "solve_share": lambda R: stage_shares(R, "solve_ms"),
    "pair_share": lambda R: stage_shares(R, "pair_ms"),
    "tolerance_cost_loose": lambda R: tolerance_cost(R, 0.1, 0.01),
    "tolerance_cost_tight": lambda R: tolerance_cost(R, 0.01, 0.001),
    "coarse_dev_loose": lambda R: deviation(R, "hammock_coarse", 0.1, NOT_GN),
    "coarse_dev_scene": lambda R: deviation(R, "hammock_coarse", 0.01, NOT_GN, "mm"),
    "coarse_dev_tight": lambda R: deviation(R, "hammock_coarse", 0.001, STRATEGIES, "mm"),
    "twist_dev": lambda R: ", ".join(f"{1000 * R.scene('twist', 'analytic', tol=t)['dev_rms']:.0f}"
                                     for t in (0.1, 0.01, 0.001)) + " mm",
    "drape_dev": lambda R: newton_deviation_range(R, "drape", "cm"),
    "drape_noise": lambda R: sci(noise_floor(R, "drape")) + " m",
    "strands_noise": lambda R: f"{100 * noise_floor(R, 'strands'):.0f} cm",
    "strands_dev": lambda R: newton_deviation_range(R, "strands", "cm"),
    # 7. single solve
    "single_speedup": single_speedup,
    "single_residual": single_residual,
    "single_deviation": single_deviation,
    # 8. float
    "float_cheaper": lambda R: pct(1 - vf(R, "analytic", "float") / vf(R, "analytic")),
    # 9. broad phase
    "tree_exponents": lambda R: vspan(bp_exponent(R, ["fcl", "bullet"]), f=lambda x: f"{x:.1f}"),
    "brute_exponent": lambda R: f"{bp_exponent(R, ['brute'])[0]:.1f}",
    "bp_smallest": lambda R: "{}× faster than FCL's at {} triangles".format(
        sig(1 / bullet_over_fcl(R, "query_ms", bp_sizes(R)[:1])[0]), thousands(bp_sizes(R)[0])),
    "bp_middle": lambda R: "{}× FCL's time from {} to {} triangles".format(
        vspan(bullet_over_fcl(R, "query_ms", bp_sizes(R, hi=LARGE)[1:]), f=lambda x: f"{x:.2f}"),
        thousands(bp_sizes(R, hi=LARGE)[1]), thousands(bp_sizes(R, hi=LARGE)[-1])),
    "bp_large": lambda R: "{}× slower from {} to {} triangles".format(
        vspan(bullet_over_fcl(R, "query_ms", bp_sizes(R, lo=LARGE)), f=lambda x: f"{x:.1f}"),
        thousands(bp_sizes(R, lo=LARGE)[0]), thousands(bp_sizes(R, lo=LARGE)[-1])),
    "bp_build": lambda R: "{}× slower from {} triangles on".format(
        vspan(bullet_over_fcl(R, "build_ms", bp_sizes(R, lo=BUILD_LARGE)), f=lambda x: f"{x:.1f}"),
        thousands(bp_sizes(R, lo=BUILD_LARGE)[0])),
    # 10. threads
    "threads_pair": lambda R: f"{R.threads()['speedup_pair_ms']:.1f}",
    "threads_count": lambda R: f"{R.threads()['threads']:.0f}",
    "threads_frame": lambda R: f"{R.threads()['speedup_ms_per_frame']:.1f}",
    "threads_scene": lambda R: R.threads()["scene"].replace("hammock_coarse", "coarse hammock"),
}


# ---------------------------------------------------------------------------------------------
# Claims the advice makes in words: (description, check). A claim whose data is missing is
# not checked.

CLAIMS = [
    ("analytic is PSD on every measured pair",
     lambda R: sum(r["psd_violations"] for r in R.acc_rows(strategy="analytic")) == 0),
    ("analytic's distance is the same in float as in double (random pairs)",
     lambda R: all(abs(R.median_dist(k, "analytic", "random", "float") / R.median_dist(k, "analytic", "random") - 1)
                   < 0.01 for k in KINDS)),
    ("exact has PSD violations (a few per 10 000)",
     lambda R: R.worst_psd_violation("double", "exact")[0] > 0),
    ("numerical is the most expensive strategy per pair",
     lambda R: all(R.ns(p, "numerical") > R.ns(p, k) for p in KINDS + ["point_point"] for k in STRATEGIES
                   if k != "numerical")),
    ("gauss_newton is the cheapest strategy per pair (vertex-face, double)",
     lambda R: all(vf(R, "gauss_newton") <= vf(R, k) for k in STRATEGIES)),
    ("gauss_newton needs fewer iterations than analytic on the full hammock",
     lambda R: R.scene("hammock", "gauss_newton", tol=None)["newton_per_frame"] <
     R.scene("hammock", "analytic", tol=None)["newton_per_frame"]),
    ("gauss_newton at 0.1 on the coarse hammock needs more iterations and ends closer to the reference",
     lambda R: R.scene("hammock_coarse", "gauss_newton", tol=0.1)["newton_per_frame"] >
     R.scene("hammock_coarse", "analytic", tol=0.1)["newton_per_frame"] and
     R.scene("hammock_coarse", "gauss_newton", tol=0.1)["dev_rms"] <
     R.scene("hammock_coarse", "analytic", tol=0.1)["dev_rms"]),
    ("the drape's deviation is far above its noise floor (a different branch)",
     lambda R: noise_floor(R, "drape") < 1e-3 * min(r[k]["dev_rms"] for r in newton_rows(R, ["drape"]).values()
                                                     for k in STRATEGIES)),
    ("every strands Newton run ends farther from the reference than the second tight run",
     lambda R: noise_floor(R, "strands") < min(r[k]["dev_rms"] for r in newton_rows(R, ["strands"]).values()
                                               for k in STRATEGIES)),
    ("single solve is cheaper per frame than Newton at 0.01 everywhere",
     lambda R: all(s["ms_per_frame"] < n["ms_per_frame"] for s, n in single_rows(R))),
    ("Bullet's queries are faster than FCL's at the smallest size and slower at every large one",
     lambda R: bullet_over_fcl(R, "query_ms", bp_sizes(R)[:1])[0] < 1 and
     min(bullet_over_fcl(R, "query_ms", bp_sizes(R, lo=LARGE))) > 1),
    ("Bullet builds its trees more slowly than FCL at every large size",
     lambda R: min(bullet_over_fcl(R, "build_ms", bp_sizes(R, lo=BUILD_LARGE))) > 1),
    ("a whole frame gains less from threads than pair evaluation",
     lambda R: R.threads()["speedup_ms_per_frame"] < R.threads()["speedup_pair_ms"]),
]


# ---------------------------------------------------------------------------------------------

def compute(results_dir):
    """name -> text (or None when the results cannot give it), and the failed claims."""
    R = Results(results_dir)
    values = {}
    for name, f in VALUES.items():
        try:
            values[name] = f(R)
        except (Missing, KeyError, ValueError, ZeroDivisionError, TypeError, IndexError):
            values[name] = None
    failed = []
    for text, check in CLAIMS:
        try:
            if not check(R):
                failed.append(text)
        except (Missing, KeyError, ValueError, ZeroDivisionError, TypeError, IndexError):
            pass
    return values, failed


def render(page, values):
    """The page with every span's value replaced; unknown names raise KeyError."""
    unknown = sorted({m.group(1) for m in SPAN.finditer(page)} - set(values))
    if unknown:
        raise KeyError("unknown value(s) in the page: " + ", ".join(unknown))
    return SPAN.sub(lambda m: f"<!-- gen:{m.group(1)} -->{values[m.group(1)] or 'n/a'}<!-- /gen -->", page)


def strip(page):
    """The page without the markers (what docs/benchmarks.md shows)."""
    return SPAN.sub(lambda m: m.group(2), page)


def guidance_numbers_in(page):
    """The text docs/benchmarks.md shows for a rendered guidance page."""
    return strip(page).strip()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", default=str(ROOT / "benchmarks" / "results"), help="results folder")
    ap.add_argument("--page", default=str(ROOT / "benchmarks" / "guidance.md"), help="the page with the spans")
    ap.add_argument("--docs", default=str(ROOT / "docs" / "benchmarks.md"),
                    help="with --check: the generated page that must contain the advice (skipped if absent)")
    ap.add_argument("--check", action="store_true", help="rewrite nothing; exit 1 if the page is out of date")
    args = ap.parse_args(argv)
    page_path = Path(args.page)
    page = page_path.read_text()
    values, failed = compute(args.results)
    try:
        new = render(page, values)
    except KeyError as e:
        print(f"guidance_numbers: {page_path}: {e.args[0]}", file=sys.stderr)
        return 1
    used = {m.group(1) for m in SPAN.finditer(page)}
    missing = sorted(n for n in used if values[n] is None)
    for n in missing:
        print(f"guidance_numbers: '{n}' cannot be computed from {args.results}", file=sys.stderr)
    for text in failed:
        print(f"guidance_numbers: the results contradict the advice: {text}", file=sys.stderr)
    if args.check:
        if new != page:
            sys.stderr.writelines(difflib.unified_diff(page.splitlines(True), new.splitlines(True),
                                                       str(page_path), "from " + str(args.results)))
            print(f"guidance_numbers: {page_path} differs from {args.results}: run "
                  "benchmarks/guidance_numbers.py (without --check) to rewrite its numbers", file=sys.stderr)
        stale_docs = False
        docs = Path(args.docs)
        if docs.is_file() and guidance_numbers_in(new) not in docs.read_text():
            stale_docs = True
            print(f"guidance_numbers: {docs} does not contain the advice as {page_path} gives it: run "
                  "benchmarks/run_all --steps none (rewrites the page from the results, runs nothing)",
                  file=sys.stderr)
        ok = new == page and not missing and not failed and not stale_docs
        print("guidance_numbers: " + ("ok: every number matches the results" if ok else "FAILED"))
        return 0 if ok else 1
    if new != page:
        page_path.write_text(new)
        print(f"guidance_numbers: rewrote {page_path}")
    else:
        print(f"guidance_numbers: {page_path} already matches the results")
    return 1 if missing or failed else 0


if __name__ == "__main__":
    sys.exit(main())
