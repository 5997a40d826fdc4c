#!/usr/bin/env python3
"""The scale ladder: one generated cloth scene at several mesh sizes, to measure how pce-sim's
cost grows with the vertex count, per solver mode, linear solver, friction and thread count.

    benchmarks/scale_ladder.py scene --vertices 8000 --out DIR [--frames F] [--mode VARIANT]
    benchmarks/scale_ladder.py run --pce-sim PATH --results DIR [--levels 8k,32k,128k]
                                   [--modes newton,newton/amg,newton/direct+mu0,block_descent:20]
                                   [--threads 1,2] [--frames F] [--window A-B] [--newton-levels L]
                                   [--timeout S] [--note TEXT] [--dry-run]
    benchmarks/scale_ladder.py run --pce-sim PATH --results DIR --plan full|quick [--dry-run]

The scene (`scene`): a 1 m x 1 m cloth of N x N quads (the scene format's `grid` generator,
so nothing but the JSON is written) dropped from 3 cm above a sphere (radius 0.2 m, its top
0.3 m above a floor box, slightly off the sheet's centre so the drape is not symmetric),
dt = 0.025 s. Effects: gravity, stretching, bending, damping, self_vertex_face and
self_edge_edge (closest features, unsigned, area weighted) and obstacle_contact (area
weighted), all three contacts with friction (mu 0.4, slip velocity 1 mm/s). The contact
distance is half the edge length, d = 1/(2N), and each penalty's stiffness is k = C/d, so the
contact pressure at a given fraction of d (2 k (d - L)) is the same at every level: the levels
simulate the same physics at finer resolution. The sheet touches the sphere at t = 0.078 s
(frame 4; contact forces act from frame 3, within d), its free parts land on the floor at
frame ~10 and fold onto themselves from frame ~11 (self contact), so the first 15 frames hold
all three contacts.

Levels (vertices = (N + 1)^2): 2k (N = 45, 2 116: a smoke test), 8k (N = 90, 8 281),
32k (N = 180, 32 761), 128k (N = 360, 130 321), or nN for any N x N. `scene --vertices V`
writes the level whose vertex count is closest to V (on a log scale) as DIR/scale_<level>.json
(DIR/scale_<level>_<variant>.json with a /LINEAR or +mu0 variant, below) and prints its path.

Modes and their variants (`--modes`, comma-separated; `scene --mode`):

    MODE[:N][/LINEAR[@TOL]][+mu0]

  MODE     newton, single_solve or block_descent; `:N` its iterations (block descent's sweeps
           per substep), passed as --iterations N; without `:N` the mode's defaults (block
           descent: 5 substeps x 5 sweeps a frame; the scene has no substeps key). pce-sim is given `--mode MODE [--iterations N]` when its
           --help lists --mode; an older pce-sim without it runs `newton` with no option and
           `single_solve` as --single-solve, and a mode it cannot select is reported as not run
           (the other runs go on).
  /LINEAR  writes solver.linear_solver = LINEAR into the run's scene (direct, factor_reuse,
           ldlt, cg; newer pce-sim also pcg and amg: docs/simulation.md section 5.3). Without
           it the scene has no linear_solver key (pce-sim's default, direct). The name is not
           checked here: a solver pce-sim rejects makes the run fail, reported with pce-sim's
           error line (the other runs go on).
  @TOL     also writes solver.linear_tolerance = TOL, a number in (0, 1) (the iterative
           solvers' relative residual; a pce-sim without the key rejects the scene).
  +mu0     friction off: the run's scene has no `friction` key on any contact effect, so
           pce-sim builds, evaluates and reports no friction at all (docs/simulation.md
           section 2.6; a `coefficient` of 0 would still freeze every active contact each
           step, at zero force).

e.g. newton, block_descent:20, newton/amg, newton/pcg@1e-6, newton/direct+mu0, newton+mu0.
The label (the spec as written, normalised) names the run in every table; a variant's scene is
RESULTS/scenes/scale_<level>_<variant>.json (variant: LINEAR[_tolTOL][_mu0], e.g. `amg`,
`direct_mu0`, `mu0`; scale_<level>.json for none: modes that differ only in MODE share a
scene, the mode is on the command line) and its run folder
RESULTS/runs/scale_<level>_<MODE><N>[_<variant>]_t<threads>/, e.g. scale_8k_newton_amg_mu0_t1.

`run` writes each (level, variant)'s scene into RESULTS/scenes/, then runs pce-sim once per
(level, mode variant, threads), one run at a time, the smaller levels first, with --no-frames
(only the last frame's OBJ), and reads its stats.jsonl and summary.json. It writes
RESULTS/scale_ladder.json (every run's numbers, the commands, the window, the plan's groups,
the scene parameters), RESULTS/scale_ladder.csv (one row per run) and RESULTS/scale_ladder.md
(the tables): per run vertices, mean ms per frame and its split (broad_phase_ms, pair_ms,
assembly_ms, solve_ms, line_search_ms; other = the rest of wall_ms), iterations per frame
(newton_iterations; for block descent its sweeps), linear iterations per frame
(counters.cg_iterations; n/a when the records have no such counter), factorisations per frame
(counters.factorizations), broad-phase queries per frame (counters.broad_phase_queries, both
contact effects together), the largest intersecting_triangle_pairs of any frame (pce-sim's
exact end-of-frame count, docs/simulation.md section 6.1), the first frame with obstacle
contacts and summary.json's peak_memory_mib; block descent's and the linear solver's other
counters per frame; then *friction's cost in iterations*: for every run with friction that has
a +mu0 twin (same level, mode, linear solver and tolerance, threads), it/frame with friction /
it/frame without, and ms/frame likewise; per label (mode, linear solver, +mu0: each fitted on
its own) and thread count the growth exponent p of ms/frame ~ c * vertices^p (least squares in
log-log); per level and label the speed-up of each thread count above 1 over 1 thread; and
(in the JSON, shown by run_all) the RMS distance of each run's last frame to a Newton run's.

Frames: by default 30 (2k, 8k), 20 (32k), 15 (128k); --frames F sets every level's.
--window A-B (1-based, inclusive, e.g. 5-12) computes every mean (ms/frame, the stages, the
iterations, the counters) over frames A..B instead of all frames, and the growth exponents
over the same frames; the largest and first-of values (intersecting pairs, the first contact
frame, iteration caps, line-search failures) still cover every frame; it is recorded in the
JSON (`window`, and per run) and printed in the markdown's preamble. Without a window, levels
run for different numbers of frames cover different parts of the drop, so the exponent is
fitted on the frames every run of the ladder completed (frames 1..W, W the smallest number of
completed frames), and the tables show each run's own mean.

Plans: `--plan full` runs benchmarks/run_all's scale step (`plan_groups("full")`: Newton for
NEWTON_FRAMES frames with window NEWTON_WINDOW at NEWTON_LEVELS, each linear solver of
LINEAR_LEVELS at its levels, 1 and 2 threads, and `+mu0` with each level's DEFAULT_LINEAR at 1
thread; BLOCK_DESCENT at BLOCK_LEVELS at the levels' default frames, 1 and 2 threads),
`--plan quick` run_all --quick's (2k, 3 frames: newton/direct, newton/direct+mu0,
block_descent). The constants next to plan_groups are the one place to change them.
--dry-run prints the pce-sim commands (and each run's window) and writes only the scenes.

Only the Python standard library is used. Timings are comparable only within one run of this
script on an otherwise idle machine.
"""

import argparse
import csv
import datetime
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# (name, quads per side N); vertices (N + 1)^2.
LEVELS = [("2k", 45), ("8k", 90), ("32k", 180), ("128k", 360)]
DEFAULT_FRAMES = {"2k": 30, "8k": 30, "32k": 20, "128k": 15}
STAGES = ["broad_phase_ms", "pair_ms", "assembly_ms", "solve_ms", "line_search_ms"]
# Counters shown in a table of their own when a run reports them (block descent's, the linear solver's).
BLOCK_COUNTERS = ["colours", "colourings", "bound_measurements", "bound_clamps", "initial_step",
                  "factorizations", "analyses"]
STAGE_NAMES = {"broad_phase_ms": "broad phase", "pair_ms": "pairs", "assembly_ms": "assembly",
               "solve_ms": "solve", "line_search_ms": "line search", "other_ms": "other"}

# The scene's physics. Lengths in m, times in s.
SIDE = 1.0              # the sheet's side
DT = 0.025              # time step: one step per frame (drape.json, hammock.json)
SPHERE_RADIUS = 0.2
SPHERE_CENTRE = (0.03, 0.02, 0.1)  # top 0.3 m above the floor, off the sheet's centre
GAP = 0.03              # the sheet starts GAP above the sphere's top: touches it at sqrt(2 GAP / g) = 0.078 s
FLOOR_HALF = (1.0, 1.0, 0.05)  # floor box, top face at z = 0
DENSITY = 0.1           # kg/m^2
STRETCHING = 60.0       # N/m (drape.json, hammock.json)
BENDING = 2e-5          # J (drape.json, hammock.json)
DAMPING = 0.2           # 1/s (drape.json, hammock.json)
D_OVER_EDGE = 0.5       # contact distance d = D_OVER_EDGE * edge length
SELF_KD = 20.0          # self contact k*d (J/m^3 with area weighting): the paper's hammock, k = 1000 J/m^4 at d = 0.02 m
OBSTACLE_KD = 100.0     # obstacle contact k*d: 5x the self contact's (the landing's impact is on the obstacles)
SELF_FRICTION = {"coefficient": 0.4, "slip_velocity": 0.001}      # pile.json's cloth-on-cloth
OBSTACLE_FRICTION = {"coefficient": 0.4, "slip_velocity": 0.001}  # drape.json's
TOLERANCE = 0.01
MAX_ITERATIONS = 30

# benchmarks/run_all's scale step runs plan_groups("full") (plan_groups("quick") with --quick);
# `run --plan full` runs the same. Change the ladder here.
NEWTON_FRAMES = 12                # every Newton run's frames (the drop: first contact frame 3-4, landing ~10)
NEWTON_WINDOW = (5, 12)           # Newton's means: frames 5..12 (in contact with the sphere)
NEWTON_LEVELS = ["8k", "32k", "128k"]
# CHOLMOD (pce-sim's default) at every level; BoomerAMG and block-Jacobi PCG beside it at 8k only
# (benchmarks/results/newton_ladder has them at every level: neither beat CHOLMOD, and PCG's
# iterations grow with the mesh, thousands a frame at 8k).
LINEAR_LEVELS = {"direct": ["8k", "32k", "128k"], "amg": ["8k"], "pcg": ["8k"]}
DEFAULT_LINEAR = {"8k": "direct", "32k": "direct", "128k": "direct"}  # each level's +mu0 (friction off) run
BLOCK_DESCENT = "block_descent"  # its defaults: 5 substeps x 5 sweeps a frame
BLOCK_LEVELS = ["8k", "32k", "128k"]        # at each level's default frames (DEFAULT_FRAMES), no window


def plan_groups(name, cores=None):
    """The named plan's groups (run_ladder's `groups`): 'full' (run_all's scale step) or 'quick'
    (run_all --quick: 2k, 3 frames, one /LINEAR and one +mu0 variant). Threads 1 and 2 where the
    machine has 2 cores, else 1."""
    cores = cores or os.cpu_count() or 1
    threads = [1, 2] if cores >= 2 else [1]
    if name == "quick":
        return [{"levels": ["2k"], "modes": ["newton/direct", "newton/direct+mu0", BLOCK_DESCENT], "threads": [1],
                 "frames": 3, "window": None}]
    if name != "full":
        raise ValueError(f"unknown plan {name!r} (plans: full, quick)")
    groups = [{"levels": [lv for lv in NEWTON_LEVELS if lv in levels], "modes": [f"newton/{linear}"],
               "threads": threads, "frames": NEWTON_FRAMES, "window": NEWTON_WINDOW}
              for linear, levels in LINEAR_LEVELS.items()]
    groups += [{"levels": [lv], "modes": [f"newton/{DEFAULT_LINEAR[lv]}+mu0"], "threads": [1],
                "frames": NEWTON_FRAMES, "window": NEWTON_WINDOW} for lv in NEWTON_LEVELS]
    groups.append({"levels": BLOCK_LEVELS, "modes": [BLOCK_DESCENT], "threads": threads, "frames": None,
                   "window": None})
    return groups


def level_by_name(name):
    for lv, n in LEVELS:
        if lv == name.lower():
            return lv, n
    m = re.fullmatch(r"n(\d+)", name.lower())  # a custom size: nN quads per side
    if m and 1 <= int(m.group(1)) <= 4096:
        return name.lower(), int(m.group(1))
    raise ValueError(f"unknown level {name!r} (levels: {', '.join(lv for lv, _ in LEVELS)}, or nN for N x N quads)")


def level_for_vertices(v):
    if v <= 0:
        raise ValueError("--vertices must be > 0")
    return min(LEVELS, key=lambda ln: abs(math.log((ln[1] + 1) ** 2 / v)))


VARIANT_RE = re.compile(r"(?P<mode>[a-z_]+)(?::(?P<it>[^/+@]*))?"
                        r"(?:/(?P<linear>[^/+@]*)(?:@(?P<tol>[^/+]*))?)?(?P<mu0>\+mu0)?")


def parse_variant(spec):
    """A run's spec, MODE[:N][/LINEAR[@TOL]][+mu0] (the module docstring's grammar), as a dict:
    mode, iterations (N or None), linear (LINEAR or None), linear_tolerance (TOL or None), mu0."""
    m = VARIANT_RE.fullmatch(spec.strip())
    if not m:
        raise ValueError(f"bad mode {spec!r} (expected MODE[:N][/LINEAR[@TOL]][+mu0], e.g. newton, "
                         f"block_descent:20, newton/amg, newton/direct+mu0)")
    it, linear, tol = m.group("it"), m.group("linear"), m.group("tol")
    if it is not None and not (it.isdigit() and int(it) > 0):
        raise ValueError(f"bad mode {spec!r}: the iterations after ':' must be an integer > 0")
    if linear is not None and not re.fullmatch(r"[a-z_]+", linear):
        raise ValueError(f"bad mode {spec!r}: the linear solver after '/' must be a name (a-z, _)")
    if tol is not None:
        try:
            t = float(tol)
        except ValueError:
            t = float("nan")
        if not 0 < t < 1:
            raise ValueError(f"bad mode {spec!r}: the linear tolerance after '@' must be a number in (0, 1)")
        tol = t
    return {"mode": m.group("mode"), "iterations": int(it) if it else None, "linear": linear,
            "linear_tolerance": tol, "mu0": bool(m.group("mu0"))}


def parse_mode(spec):
    """'block_descent:20' -> ('block_descent', 20); 'newton' -> ('newton', None); the mode part of
    a variant (parse_variant) only."""
    v = parse_variant(spec)
    return v["mode"], v["iterations"]


def mode_label(mode, iterations):
    return mode if iterations is None else f"{mode}:{iterations}"


def scene_suffix(v):
    """The part of a variant that is written into the scene ('' for none): 'amg', 'pcg_tol1e-06',
    'direct_mu0', 'mu0'."""
    parts = []
    if v.get("linear"):
        parts.append(v["linear"] + (f"_tol{v['linear_tolerance']:g}" if v.get("linear_tolerance") else ""))
    if v.get("mu0"):
        parts.append("mu0")
    return "_".join(parts)


def variant_label(v):
    """The label of a variant in every table: 'newton', 'block_descent:20', 'newton/amg',
    'newton/pcg@1e-06', 'newton/direct+mu0'."""
    out = mode_label(v["mode"], v["iterations"])
    if v.get("linear"):
        out += "/" + v["linear"] + (f"@{v['linear_tolerance']:g}" if v.get("linear_tolerance") else "")
    return out + ("+mu0" if v.get("mu0") else "")


def variant_tag(v):
    """The label as a file name part: 'newton', 'block_descent20', 'newton_amg', 'newton_direct_mu0'."""
    return "_".join(x for x in (mode_label(v["mode"], v["iterations"]).replace(":", ""), scene_suffix(v)) if x)


def parse_window(text):
    """'5-12' -> (5, 12): frames 5..12, 1-based, inclusive; None or '' -> None (every frame)."""
    if not text:
        return None
    m = re.fullmatch(r"\s*(\d+)\s*-\s*(\d+)\s*", str(text))
    if not m or not 1 <= int(m.group(1)) <= int(m.group(2)):
        raise ValueError(f"bad window {text!r} (expected A-B, 1 <= A <= B, e.g. 5-12)")
    return int(m.group(1)), int(m.group(2))


def in_window(records, window):
    """The records of frames A..B (each record's `frame`, else its position from 1); all without a window."""
    if not window:
        return list(records)
    a, b = window
    return [r for i, r in enumerate(records, 1) if a <= (r.get("frame") or i) <= b]


def scene_parameters(n):
    edge = SIDE / n
    d = D_OVER_EDGE * edge
    return {"quads_per_side": n, "vertices": (n + 1) ** 2, "triangles": 2 * n * n, "edge_m": edge,
            "contact_distance_m": d, "self_stiffness": float(f"{SELF_KD / d:.6g}"),
            "obstacle_stiffness": float(f"{OBSTACLE_KD / d:.6g}"),
            "dt": DT, "drop_gap_m": GAP, "sphere_radius_m": SPHERE_RADIUS, "sphere_centre": list(SPHERE_CENTRE),
            "frame_touching_sphere": math.ceil(math.sqrt(2 * GAP / 9.81) / DT)}


def make_scene(level, n, frames, mode=None, iterations=None, linear=None, linear_tolerance=None, mu0=False):
    """The level's scene; `mode`/`iterations` into solver.mode/iterations, `linear` into
    solver.linear_solver, `linear_tolerance` into solver.linear_tolerance, `mu0`: no contact
    has a friction key (pce-sim then builds no friction at all)."""
    p = scene_parameters(n)
    d = p["contact_distance_m"]
    top = SPHERE_CENTRE[2] + SPHERE_RADIUS + GAP

    def contact(kind, k, friction):
        e = {"type": kind, "penalty": {"type": "quadratic", "stiffness": k, "distance": d}, "area_weighted": True}
        if not mu0:
            e["friction"] = dict(friction)
        if kind != "obstacle_contact":
            e.update({"length": "unsigned", "hessian": "analytic", "closest_features": True})
        return e

    solver = {"mode": "newton", "tolerance": TOLERANCE, "max_iterations": MAX_ITERATIONS}
    if mode is not None:
        solver["mode"] = mode
        if iterations is not None:
            solver["iterations"] = iterations
    if linear is not None:
        solver["linear_solver"] = linear
    if linear_tolerance is not None:
        solver["linear_tolerance"] = linear_tolerance
    return {
        "description": (f"Scale ladder level {level} (benchmarks/scale_ladder.py): a {SIDE:g} m cloth of {n} x {n} "
                        f"quads ({p['vertices']} vertices, edges {1000 * p['edge_m']:.3g} mm) dropped from "
                        f"{100 * GAP:g} cm onto a sphere resting on a floor box; contact distance half an edge "
                        f"({1000 * d:.3g} mm), area-weighted quadratic penalties with k*d = {SELF_KD:g} (self) "
                        f"and {OBSTACLE_KD:g} (obstacles) J/m^3, "
                        + ("no friction (the +mu0 variant)" if mu0 else "friction on every contact")
                        + (f", linear solver {linear}" if linear else "")
                        + (f" (tolerance {linear_tolerance:g})" if linear_tolerance else "")
                        + ". Generated; not hand-edited."),
        "dt": DT,
        "frames": frames,
        "output_every": 1000000,
        "view_direction": [-0.6, -1.5, -0.9],
        "solver": solver,
        "meshes": [{"name": "cloth",
                    "generator": {"type": "grid", "width": SIDE, "height": SIDE, "nx": n, "ny": n},
                    "transform": {"translation": [0, 0, round(top, 9)]},
                    "density": DENSITY}],
        "obstacles": [
            {"name": "ball", "shape": "sphere", "radius": SPHERE_RADIUS, "position": list(SPHERE_CENTRE)},
            {"name": "floor", "shape": "box", "half_extents": list(FLOOR_HALF), "position": [0, 0, -FLOOR_HALF[2]]},
        ],
        "effects": [
            {"type": "gravity"},
            {"type": "stretching", "model": "arap", "stiffness": STRETCHING},
            {"type": "bending", "stiffness": BENDING},
            {"type": "damping", "coefficient": DAMPING},
            contact("obstacle_contact", p["obstacle_stiffness"], OBSTACLE_FRICTION),
            contact("self_vertex_face", p["self_stiffness"], SELF_FRICTION),
            contact("self_edge_edge", p["self_stiffness"], SELF_FRICTION),
        ],
    }


def write_scene(out_dir, level, n, frames, mode=None, iterations=None, linear=None, linear_tolerance=None,
                mu0=False):
    """DIR/scale_<level>.json, or DIR/scale_<level>_<suffix>.json for a linear solver or +mu0
    (scene_suffix: 'amg', 'direct_mu0', ...)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    suffix = scene_suffix({"linear": linear, "linear_tolerance": linear_tolerance, "mu0": mu0})
    path = out_dir / (f"scale_{level}_{suffix}.json" if suffix else f"scale_{level}.json")
    path.write_text(json.dumps(make_scene(level, n, frames, mode, iterations, linear, linear_tolerance, mu0),
                               indent=1) + "\n")
    return path


# ---------------------------------------------------------------------------------------------
# Numbers.

def mean(xs):
    xs = [x for x in xs if x is not None and isinstance(x, (int, float)) and math.isfinite(x)]
    return sum(xs) / len(xs) if xs else float("nan")


def fit_exponent(ns, ts):
    """Least-squares slope of log t against log n: t ~ c n^slope (nan with fewer than 2 sizes)."""
    pts = [(math.log(n), math.log(t)) for n, t in zip(ns, ts)
           if n and n > 0 and t is not None and math.isfinite(t) and t > 0]
    if len({p[0] for p in pts}) < 2:
        return float("nan")
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


def load_records(directory):
    """stats.jsonl (complete lines: a killed run keeps its completed frames), else stats.json."""
    jsonl = Path(directory) / "stats.jsonl"
    if jsonl.exists():
        out = []
        for line in jsonl.read_text().splitlines():
            try:
                out.append(json.loads(line))
            except json.JSONDecodeError:
                pass  # a line cut short
        return out
    js = Path(directory) / "stats.json"
    return json.loads(js.read_text()) if js.exists() else []


def iterations_of(rec):
    """Newton iterations per frame, or block descent's sweeps (`sweeps`, in records since they were split)."""
    if rec.get("sweeps"):
        return rec["sweeps"]
    if "newton_iterations" in rec:
        return rec["newton_iterations"]
    return len(rec.get("iterations", [])) or None


def window_numbers(records):
    """Per-frame means over `records`: ms, stages, other, iterations, queries."""
    r = {"ms_per_frame": mean([x.get("wall_ms") for x in records])}
    for k in STAGES:
        r[k] = mean([x.get(k) for x in records])
    if records:
        r["other_ms"] = max(r["ms_per_frame"] - sum(r[k] for k in STAGES if math.isfinite(r[k])), 0.0)
    else:
        r["other_ms"] = float("nan")
    r["iterations_per_frame"] = mean([iterations_of(x) for x in records])
    r["queries_per_frame"] = mean([x.get("counters", {}).get("broad_phase_queries") for x in records])
    # The linear solver's: CG iterations (counters.cg_iterations; nan, shown "n/a", when no record has
    # the counter) and factorisations per frame.
    r["linear_iterations_per_frame"] = mean([x.get("counters", {}).get("cg_iterations") for x in records])
    r["factorizations_per_frame"] = mean([x.get("counters", {}).get("factorizations") for x in records])
    return r


def summarise_run(all_records, summary, window=None):
    """A run's numbers: means over the frames of `window` ((A, B), 1-based, inclusive; None: every
    frame); the largest and first-of values (intersecting pairs, first contact, caps) over every frame."""
    records = in_window(all_records, window)
    r = window_numbers(records)
    counters = {}
    for rec in records:
        for k, v in rec.get("counters", {}).items():
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                counters.setdefault(k, []).append(v)
    contacts = {}
    for rec in records:
        for k, v in (rec.get("contacts") or {}).items():
            contacts.setdefault(k, []).append(v)
    first_contact = next((rec["frame"] for rec in all_records
                          if (rec.get("contacts") or {}).get("obstacle", 0) > 0), None)
    ips = [rec.get("intersecting_triangle_pairs") for rec in all_records
           if rec.get("intersecting_triangle_pairs") is not None]
    r.update({
        "frames_done": len(all_records),
        "window": list(window) if window else None,
        "frames_averaged": len(records),
        "vertices": summary.get("vertices"),
        "triangles": summary.get("triangles"),
        "mode_reported": summary.get("mode"),
        "max_intersecting_pairs": max(ips) if ips else None,
        "frames_with_intersections": sum(1 for x in ips if x > 0),
        "new_intersections": summary.get("new_intersections"),
        "iteration_caps": sum(1 for rec in all_records if rec.get("hit_iteration_cap")),
        "line_search_failures": sum(rec.get("line_search_failures", 0) or 0 for rec in all_records),
        "first_obstacle_contact_frame": first_contact,
        "contacts_per_frame": {k: mean(v) for k, v in contacts.items()},
        "contacts_max": {k: max(v) for k, v in contacts.items()},
        "counters_per_frame": {k: mean(v) for k, v in sorted(counters.items())},
        "peak_memory_mib": summary.get("peak_memory_mib"),
        "pce_sim_total_s": summary.get("total_s"),
        "failure": summary.get("failure"),
        "stopped_by": summary.get("stopped_by"),
        "wall_ms_per_frame_list": [rec.get("wall_ms") for rec in all_records],
    })
    return r


# ---------------------------------------------------------------------------------------------
# Running pce-sim.

def sim_help(exe):
    p = subprocess.run([str(exe), "--help"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return p.stdout


def mode_arguments(help_text, mode, iterations):
    """pce-sim options selecting the mode, or raises ValueError when this pce-sim cannot."""
    if re.search(r"--mode\b", help_text):
        args = ["--mode", mode]
        if iterations is not None:
            if not re.search(r"--iterations\b", help_text):
                raise ValueError(f"this pce-sim has --mode but no --iterations (mode {mode_label(mode, iterations)})")
            args += ["--iterations", str(iterations)]
        return args
    if iterations is not None:
        raise ValueError(f"this pce-sim has no --mode/--iterations (mode {mode_label(mode, iterations)})")
    if mode == "newton":
        return []
    if mode == "single_solve" and "--single-solve" in help_text:
        return ["--single-solve"]
    raise ValueError(f"this pce-sim has no --mode option: mode {mode} cannot be selected (not built yet?)")


def log(msg):
    print(f"[scale_ladder {datetime.datetime.now().strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def run_one(cmd, out, timeout):
    """Runs pce-sim; stdout and stderr into out/pce-sim.log. On timeout it gets SIGTERM (pce-sim
    then ends after the current frame and writes its stats) and, 30 min later, SIGKILL."""
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.monotonic()
    timed_out = False
    with open(out / "pce-sim.log", "w") as logf:
        p = subprocess.Popen([str(c) for c in cmd], stdout=logf, stderr=subprocess.STDOUT)
        try:
            p.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
            p.send_signal(signal.SIGTERM)
            try:
                p.wait(timeout=1800)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        except BaseException:  # Ctrl-C or SIGTERM to this script: stop the run too
            p.send_signal(signal.SIGTERM)
            try:
                p.wait(timeout=60)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
            raise
    return p.returncode, time.monotonic() - t0, timed_out


def log_tail(out, lines=3):
    f = out / "pce-sim.log"
    return " | ".join(f.read_text(errors="replace").strip().splitlines()[-lines:]) if f.exists() else ""


def log_error(out):
    """pce-sim's last error line in out/pce-sim.log (a line starting 'pce-sim: ' that is not its
    'wrote ...' line, e.g. a scene key it rejects), else the log's last lines."""
    f = out / "pce-sim.log"
    lines = f.read_text(errors="replace").strip().splitlines() if f.exists() else []
    err = [x for x in lines if x.startswith("pce-sim: ") and not x.startswith("pce-sim: wrote")]
    return err[-1] if err else log_tail(out)


def expand(groups):
    """The runs of a plan: (level, quads per side, frames, window, variant, threads) for every
    group's levels x modes x threads, the smaller levels first (a stopped ladder has them), each
    (level, label, threads) once. A group: levels, modes, threads, frames (None: each level's
    default), window ((A, B) or 'A-B' or None) and `only` ({mode or label: [levels]}, optional)."""
    runs, seen = [], set()
    for g in groups:
        window = parse_window(g["window"]) if isinstance(g.get("window"), str) else g.get("window")
        window = tuple(window) if window else None
        for lv in g["levels"]:
            name, n = level_by_name(lv)
            f = g.get("frames") or DEFAULT_FRAMES.get(name, 20)
            if window and window[1] > f:
                raise ValueError(f"window {window[0]}-{window[1]} ends after the last frame ({f}) of level {name}")
            for spec in g["modes"]:
                v = parse_variant(spec)
                only = g.get("only") or {}
                allowed = only.get(variant_label(v), only.get(v["mode"]))
                if allowed is not None and name not in allowed:
                    continue
                for t in g["threads"]:
                    key = (name, variant_label(v), t)
                    if key not in seen:
                        seen.add(key)
                        runs.append((name, n, f, window, v, t))
    order = {name: i for i, name in enumerate(dict.fromkeys([r[0] for r in runs]))}
    return sorted(runs, key=lambda r: ((r[1], order[r[0]])))


def run_ladder(exe, results, levels=(), modes=(), threads=(1,), frames=None, timeout=None, dry_run=False, note=None,
               only=None, window=None, groups=None):
    """Runs every (level, mode variant, threads); writes scale_ladder.json/.csv/.md into `results`;
    returns the summary dict (None with `dry_run`, which prints the commands). Either `levels`,
    `modes` (MODE[:N][/LINEAR[@TOL]][+mu0]), `threads`, `frames`, `window` ((A, B) or 'A-B'; None:
    every frame) and `only` ({mode or label: [levels]}: that mode only at those levels), or
    `groups`, a list of such dicts (plan_groups' form) whose runs are run together as one ladder."""
    exe = Path(exe).resolve()
    results = Path(results).resolve()
    results.mkdir(parents=True, exist_ok=True)
    if groups is None:
        groups = [{"levels": list(levels), "modes": list(modes), "threads": list(threads), "frames": frames,
                   "window": window, "only": only}]
    plan = expand(groups)
    help_text = sim_help(exe)
    rows = []
    started = datetime.datetime.now(datetime.timezone.utc)
    windows = sorted({r[3] for r in plan} - {None})
    meta = {
        "pce_sim": str(exe), "date_utc": started.strftime("%Y-%m-%d %H:%M UTC"), "cores": os.cpu_count(),
        "load_average_at_start": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
        "note": note, "levels": list(dict.fromkeys(r[0] for r in plan)),
        "modes": list(dict.fromkeys(variant_label(r[4]) for r in plan)),
        "threads": sorted({r[5] for r in plan}), "frames_override": frames if len(groups) == 1 else None,
        "window": list(windows[0]) if len(windows) == 1 and all(r[3] for r in plan) else None,
        "groups": [dict(g, window=(list(g["window"]) if isinstance(g.get("window"), (tuple, list))
                                   else g.get("window"))) for g in groups],
        "scene_parameters": {name: scene_parameters(n) for name, n, *_ in plan},
        "physics": {"side_m": SIDE, "dt": DT, "gap_m": GAP, "sphere_radius_m": SPHERE_RADIUS,
                    "sphere_centre": list(SPHERE_CENTRE), "floor_half_extents": list(FLOOR_HALF),
                    "density": DENSITY, "stretching": STRETCHING, "bending": BENDING, "damping": DAMPING,
                    "d_over_edge": D_OVER_EDGE, "self_k_times_d": SELF_KD, "obstacle_k_times_d": OBSTACLE_KD,
                    "self_friction": SELF_FRICTION, "obstacle_friction": OBSTACLE_FRICTION,
                    "tolerance": TOLERANCE, "max_iterations": MAX_ITERATIONS},
        "commit": git_commit(),
    }
    scenes = {}
    for name, n, f, win, v, t in plan:
        mode, it = v["mode"], v["iterations"]
        key = (name, scene_suffix(v))
        if key not in scenes:  # one scene per level and variant; the command's --frames is the run's
            scenes[key] = write_scene(results / "scenes", name, n, f, linear=v["linear"],
                                      linear_tolerance=v["linear_tolerance"], mu0=v["mu0"])
        scene = scenes[key]
        label = variant_label(v)
        tag = f"scale_{name}_{variant_tag(v)}_t{t}"
        out = results / "runs" / tag
        row = {"level": name, "quads_per_side": n, "mode": mode, "mode_iterations": it, "mode_label": label,
               "linear_solver": v["linear"], "linear_tolerance": v["linear_tolerance"], "mu0": v["mu0"],
               "threads": t, "frames": f, "window": list(win) if win else None, "tag": tag, "out": str(out),
               "scene": str(scene)}
        try:
            margs = mode_arguments(help_text, mode, it)
        except ValueError as e:
            row.update({"status": "not run", "reason": str(e)})
            log(f"{tag}: not run: {e}")
            rows.append(row)
            continue
        cmd = [exe, scene, "--out", out, "--frames", str(f), "--threads", str(t), "--no-frames"] + margs
        row["command"] = " ".join(str(c) for c in cmd)
        if dry_run:
            print(row["command"] + (f"   # means over frames {win[0]}-{win[1]}" if win else ""))
            continue
        if out.exists():
            shutil.rmtree(out)
        log(f"{tag}: {f} frames of {(n + 1) ** 2} vertices ...")
        code, wall_s, timed_out = run_one(cmd, out, timeout)
        summary_path = out / "summary.json"
        summary = json.loads(summary_path.read_text()) if summary_path.exists() else {}
        records = load_records(out)
        row.update({"exit_code": code, "process_wall_s": wall_s, "timed_out": timed_out})
        if not records:
            row.update({"status": "failed", "reason": f"exit {code}, no frame completed: {log_error(out)}"})
            log(f"{tag}: FAILED: {row['reason']}")
            rows.append(row)
            continue
        row.update(summarise_run(records, summary, win))
        row["status"] = "ok" if code == 0 else ("timed out" if timed_out else "failed")
        if code != 0:
            row["reason"] = f"exit {code}: {summary.get('failure') or log_error(out)}"
        elif row.get("mode_reported") not in (None, mode):
            row["status"] = "wrong mode"
            row["reason"] = f"asked for mode {mode}, summary.json says {row['mode_reported']}"
        log(f"{tag}: {row['ms_per_frame']:.0f} ms/frame, {row['iterations_per_frame']:.2f} it/frame, "
            f"{row['frames_done']} frames, max {row['max_intersecting_pairs']} intersecting pairs"
            + (f" ({row['status']}: {row.get('reason')})" if row["status"] != "ok" else ""))
        rows.append(row)
        write_outputs(results, rows, meta, complete=False)  # a stopped ladder keeps the runs it finished
    if dry_run:
        return None
    result = write_outputs(results, rows, meta, complete=True)
    log(f"wrote {results / 'scale_ladder.md'}, scale_ladder.json, scale_ladder.csv")
    return result


def write_outputs(results, rows, meta, complete):
    """scale_ladder.json/.csv/.md from the runs so far (`complete`: every planned run is in `rows`)."""
    result = analyse([dict(r) for r in rows])
    result.update(meta)
    result["complete"] = complete
    (results / "scale_ladder.json").write_text(json.dumps(result, indent=1, default=str) + "\n")
    write_csv(results / "scale_ladder.csv", result["runs"])
    (results / "scale_ladder.md").write_text(markdown(result))
    return result


def git_commit():
    try:
        p = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
        d = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True)
        if p.returncode != 0 or not p.stdout.strip():
            return None
        return p.stdout.strip() + (" (with uncommitted changes)" if d.stdout.strip() else "")
    except OSError:
        return None


def same_variant(a, b, **differ):
    """Whether runs a and b have the same level, mode, iterations, linear solver and tolerance,
    friction (mu0) and thread count, except the keys given in `differ` (key=True: ignore it)."""
    keys = ["level", "mode", "mode_iterations", "linear_solver", "linear_tolerance", "mu0", "threads"]
    return all(a.get(k) == b.get(k) for k in keys if not differ.get(k))


def analyse(rows):
    """Adds the fitted window's numbers to each run; fits exponents; computes speed-ups, friction's
    cost and each run's distance to a Newton run's last frame."""
    ran = [r for r in rows if r.get("frames_done")]
    # The fitted window of a run: its --window (A, B) when it has one; otherwise frames 1..W, W
    # the smallest number of frames any completed run without a window has (a failed or stopped
    # run would cut it short for all; it is fitted only if it reached the window).
    free = [r for r in ran if not r.get("window")]
    done = [r for r in free if r.get("status") == "ok"] or free
    common = min((r["frames_done"] for r in done), default=0)
    for r in ran:
        fw = tuple(r["window"]) if r.get("window") else (1, common)
        recs = in_window(load_records(r["out"]), fw)
        w = window_numbers(recs)
        r["fit_window"] = list(fw)
        r["window_frames"] = fw[1] - fw[0] + 1
        r["window_ms_per_frame"] = w["ms_per_frame"]
        for k in STAGES + ["other_ms"]:
            r["window_" + k] = w[k]
        r["window_iterations_per_frame"] = w["iterations_per_frame"]
        r["window_linear_iterations_per_frame"] = w["linear_iterations_per_frame"]
    exponents = []
    # Grouped by the full label (mode, iterations, linear solver, mu0): each variant is fitted on its own.
    for label in dict.fromkeys(r["mode_label"] for r in ran):
        for t in sorted({r["threads"] for r in ran if r["mode_label"] == label}):
            for fw in dict.fromkeys(tuple(r["fit_window"]) for r in ran
                                    if r["mode_label"] == label and r["threads"] == t):
                sel = sorted([r for r in ran if r["mode_label"] == label and r["threads"] == t
                              and tuple(r["fit_window"]) == fw and r["frames_done"] >= fw[1]],
                             key=lambda r: r["vertices"] or 0)
                if len({r["vertices"] for r in sel}) < 2:
                    continue
                vs = [r["vertices"] for r in sel]
                e = {"mode": label, "threads": t, "levels": [r["level"] for r in sel], "fit_window": list(fw),
                     "window_frames": fw[1] - fw[0] + 1, "explicit_window": bool(sel[0].get("window")),
                     "ms_per_frame": fit_exponent(vs, [r["window_ms_per_frame"] for r in sel]),
                     "ms_per_frame_own_frames": fit_exponent(vs, [r["ms_per_frame"] for r in sel]),
                     "ms_per_iteration": fit_exponent(vs, [r["window_ms_per_frame"] / r["window_iterations_per_frame"]
                                                           if r["window_iterations_per_frame"] else float("nan")
                                                           for r in sel]),
                     "iterations_per_frame": fit_exponent(vs, [r["window_iterations_per_frame"] for r in sel])}
                for k in STAGES + ["other_ms"]:
                    e[k] = fit_exponent(vs, [r["window_" + k] for r in sel])
                exponents.append(e)
    speedups = []
    for r in ran:
        if r["threads"] == 1:
            continue
        base = next((b for b in ran if b["threads"] == 1 and same_variant(b, r, threads=True)
                     and b["frames_done"] == r["frames_done"] and b.get("window") == r.get("window")), None)
        if base:
            s = {"level": r["level"], "vertices": r["vertices"], "mode": r["mode_label"], "threads": r["threads"],
                 "frames": r["frames_done"], "window": r.get("window"), "ms_per_frame_1": base["ms_per_frame"],
                 "ms_per_frame_t": r["ms_per_frame"],
                 "speedup": base["ms_per_frame"] / r["ms_per_frame"] if r["ms_per_frame"] else float("nan"),
                 "same_iterations": base["iterations_per_frame"] == r["iterations_per_frame"]}
            for k in STAGES + ["other_ms"]:
                s["speedup_" + k] = base[k] / r[k] if r[k] else float("nan")
            speedups.append(s)
    # Friction's cost: each run with friction against its +mu0 twin (same level, mode, linear
    # solver and threads), over the fitted windows.
    friction = []
    for r in ran:
        if r.get("mu0"):
            continue
        b = next((b for b in ran if b.get("mu0") and same_variant(b, r, mu0=True)), None)
        if not b:
            continue

        def ratio(x, y):
            return x / y if x is not None and y and math.isfinite(x) and math.isfinite(y) else float("nan")
        friction.append({"level": r["level"], "vertices": r["vertices"], "mode": r["mode_label"],
                         "without": b["mode_label"], "threads": r["threads"],
                         "fit_window": r["fit_window"], "fit_window_without": b["fit_window"],
                         "iterations_per_frame": r["window_iterations_per_frame"],
                         "iterations_per_frame_mu0": b["window_iterations_per_frame"],
                         "iterations_ratio": ratio(r["window_iterations_per_frame"], b["window_iterations_per_frame"]),
                         "ms_per_frame": r["window_ms_per_frame"], "ms_per_frame_mu0": b["window_ms_per_frame"],
                         "ms_ratio": ratio(r["window_ms_per_frame"], b["window_ms_per_frame"]),
                         "linear_iterations_per_frame": r["window_linear_iterations_per_frame"],
                         "linear_iterations_per_frame_mu0": b["window_linear_iterations_per_frame"]})
    # How far each run's last frame lies from a Newton run's (same level, friction and frames):
    # the RMS over vertices of the distance between their last OBJ files, metres. The reference:
    # Newton with the default or the direct linear solver, else the first Newton run; 1 thread first.
    agreement = []
    for r in ran:
        refs = [b for b in ran if b["mode"] == "newton" and b["level"] == r["level"]
                and bool(b.get("mu0")) == bool(r.get("mu0")) and b["frames_done"] == r["frames_done"]]
        refs.sort(key=lambda b: (b.get("linear_solver") not in (None, "direct"), b["threads"] != 1))
        if not refs or refs[0] is r:
            continue
        ref = refs[0]
        a, b = last_obj(r["out"]), last_obj(ref["out"])
        if a and b:
            pa, pb = read_positions(a), read_positions(b)
            if len(pa) == len(pb) and pa:
                agreement.append({"level": r["level"], "mode": r["mode_label"], "threads": r["threads"],
                                  "reference": ref["mode_label"], "reference_threads": ref["threads"],
                                  "frame": r["frames_done"],
                                  "rms_to_newton_m": math.sqrt(sum((x - y) ** 2 for p, q in zip(pa, pb)
                                                                   for x, y in zip(p, q)) / len(pa)),
                                  "lowest_z_m": min(p[2] for p in pa), "newton_lowest_z_m": min(p[2] for p in pb)})
    return {"runs": rows, "window_frames": common, "exponents": exponents, "speedups": speedups,
            "friction": friction, "agreement": agreement}


def last_obj(directory):
    """The highest-numbered frame_NNNN.obj a run wrote, or None."""
    files = sorted(Path(directory).glob("frame_*.obj"))
    return files[-1] if files else None


def read_positions(path):
    """The vertex positions of an OBJ file, in order."""
    with open(path) as f:
        return [tuple(float(t) for t in line.split()[1:4]) for line in f if line.startswith("v ")]


def window_text(w):
    """[5, 12] -> '5-12'; None -> ''."""
    return f"{w[0]}-{w[1]}" if w else ""


def write_csv(path, rows):
    cols = ["level", "vertices", "mode_label", "mode", "mode_iterations", "linear_solver", "linear_tolerance", "mu0",
            "threads", "frames", "frames_done", "window", "frames_averaged", "status", "ms_per_frame"] + \
        STAGES + ["other_ms", "iterations_per_frame", "linear_iterations_per_frame", "factorizations_per_frame",
                  "queries_per_frame", "max_intersecting_pairs",
                  "frames_with_intersections", "iteration_caps", "line_search_failures",
                  "first_obstacle_contact_frame", "fit_window", "window_frames", "window_ms_per_frame",
                  "window_iterations_per_frame", "peak_memory_mib", "process_wall_s", "exit_code", "reason", "command"]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (window_text(v) if k in ("window", "fit_window") else
                            f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def fmt(x, digits=3):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "n/a"
    if isinstance(x, bool):
        return str(x)
    if isinstance(x, int):
        return f"{x:,}".replace(",", " ")
    a = abs(x)
    if a >= 1000:
        return f"{x:,.0f}".replace(",", " ")
    if a == 0:
        return "0"
    if a >= 0.01:
        return f"{x:.{digits}g}"
    return f"{x:.1e}"


def md_table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join(["---"] * 3 + ["---:"] * (len(header) - 3)) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out) + "\n"


def counter_mean(r, key, counter):
    """r[key], or (results written before it had the key) the counter's mean in counters_per_frame."""
    return r[key] if key in r else (r.get("counters_per_frame") or {}).get(counter)


def windows_sentence(runs):
    """Which frames each run's means cover, from the runs' own `window` keys."""
    by = {}
    for r in runs:
        by.setdefault(window_text(r.get("window")) or None, []).append(r["mode_label"])
    if set(by) == {None}:
        return "Each run's means are over all its frames (no `--window`)."
    parts = []
    for w, labels in by.items():
        labels = ", ".join(f"`{x}`" for x in dict.fromkeys(labels))
        parts.append(f"over frames {w.replace('-', '–')}" + (f" ({labels})" if len(by) > 1 else "") if w
                     else f"over all its frames ({labels})")
    return ("Each run's means (ms/frame, the stages, the iterations, the counters) are " + "; ".join(parts) +
            " (`--window A-B`: frames A..B, 1-based, inclusive); *max ∩* and *contact* cover every frame.")


def markdown(res, title="# Scale ladder", sub="##"):
    """The tables as markdown: `title` first, sections headed by `sub` (run_all's page embeds it
    as a section of its own). Paths inside the repository are shown relative to it."""
    L = []
    A = L.append
    A(title + "\n")
    A(f"pce-sim `{res['pce_sim']}`" + (f", commit {res['commit']}" if res.get("commit") else "") +
      f", {res['date_utc']}, {res['cores']} cores"
      + (f", load average at start {res['load_average_at_start'][0]:.2f}" if res.get("load_average_at_start") else "")
      + (f"; {res['note']}" if res.get("note") else "") + ".\n")
    ph = res["physics"]
    A(f"Scene (`benchmarks/scale_ladder.py`): a {ph['side_m']:g} m cloth of N × N quads dropped from "
      f"{100 * ph['gap_m']:g} cm onto a sphere (r = {ph['sphere_radius_m']:g} m) on a floor box, dt = {ph['dt']:g} s; "
      f"self contact (vertex-face, edge-edge; closest features) and obstacle contact, area weighted, "
      f"d = {ph['d_over_edge']:g} × edge, k·d = {ph['self_k_times_d']:g} (self) and {ph['obstacle_k_times_d']:g} "
      f"(obstacles), friction μ = {ph['self_friction']['coefficient']:g} / {ph['obstacle_friction']['coefficient']:g}. "
      "A run's label is its mode (`MODE[:N]`), then `/LINEAR` when the scene sets `solver.linear_solver` (none: "
      "pce-sim's default) and `+mu0` when the scene has no friction key on any contact. "
      "Times are means of `stats.jsonl` per frame (ms); the stages are `broad_phase_ms`, `pair_ms`, `assembly_ms`, "
      "`solve_ms`, `line_search_ms` (they overlap a little: `pair_ms` includes the line search's pair passes), and "
      "*other* is the rest of `wall_ms` (at least 0). *it* is `newton_iterations` per frame (block descent: `sweeps`), "
      "*lin it* `counters.cg_iterations` per frame (the linear solver's iterations; n/a where pce-sim does not "
      "report it), *fact* `counters.factorizations` per frame, "
      "*queries* `counters.broad_phase_queries` per frame (both contact effects), *max ∩* the largest "
      "`intersecting_triangle_pairs` of any frame, *contact* the first frame with obstacle contacts, *peak MiB* "
      "`summary.json`'s `peak_memory_mib`. " + windows_sentence([r for r in res["runs"] if r.get("frames_done")]
                                                              or res["runs"]) + "\n")
    if not res.get("complete", True):
        A("**Incomplete**: the ladder was stopped or is still running; these are the runs it finished.\n")
    A(f"{sub} Runs\n")
    rows = []
    notes = []
    cols = STAGES + ["other_ms"]
    for r in res["runs"]:
        if r.get("status") != "ok":
            notes.append(f"- {r['level']}, {r['mode_label']}, {r['threads']} thread(s): {r.get('status', '?')}: "
                         f"{r.get('reason', '')}")
        if not r.get("frames_done"):
            rows.append([r["level"], fmt((r["quads_per_side"] + 1) ** 2), r["mode_label"], r["threads"],
                         r.get("status", "?")] + ["—"] * (len(cols) + 9))
            continue
        rows.append([r["level"], fmt(r["vertices"]), r["mode_label"], r["threads"],
                     f"{r['frames_done']}" + ("" if r["status"] == "ok" else f" ({r['status']})"),
                     fmt(r["ms_per_frame"])] + [fmt(r[k]) for k in cols] +
                    [fmt(r["iterations_per_frame"]), fmt(counter_mean(r, "linear_iterations_per_frame", "cg_iterations")),
                     fmt(counter_mean(r, "factorizations_per_frame", "factorizations")), fmt(r["queries_per_frame"]),
                     fmt(r["max_intersecting_pairs"]), fmt(r["first_obstacle_contact_frame"]),
                     fmt(r["peak_memory_mib"])])
    A(md_table(["level", "vertices", "mode", "threads", "frames", "ms/frame"] + [STAGE_NAMES[k] for k in STAGES] +
               ["other", "it/frame", "lin it/frame", "fact/frame", "queries/frame", "max ∩", "contact", "peak MiB"],
               rows))
    if notes:
        A("Runs that did not complete:\n\n" + "\n".join(notes) + "\n")
    # factorizations has its column in the runs table.
    extra = [k for k in BLOCK_COUNTERS if k != "factorizations"
             and any(k in (r.get("counters_per_frame") or {}) for r in res["runs"])]
    if extra:
        A("Solver counters per frame (`counters` in `stats.jsonl`, where a run reports them):\n")
        A(md_table(["level", "mode", "threads"] + extra,
                   [[r["level"], r["mode_label"], r["threads"]] + [fmt(r["counters_per_frame"].get(k)) for k in extra]
                    for r in res["runs"] if r.get("frames_done")]))
    if res.get("friction"):
        A(f"{sub} Friction's cost in iterations\n\nEach run with friction against the same level, mode, linear "
          "solver and threads without it (`+mu0`: no friction key, so pce-sim builds no friction), means over each "
          "run's fitted frames (the growth exponents' window): it/frame with friction ÷ it/frame without, and "
          "ms/frame likewise.\n")
        A(md_table(["level", "vertices", "mode", "threads", "frames", "it/frame", "it/frame (+mu0)", "it ratio",
                    "lin it/frame", "lin it/frame (+mu0)", "ms/frame", "ms/frame (+mu0)", "ms ratio"],
                   [[f["level"], fmt(f["vertices"]), f["mode"], f["threads"],
                     window_text(f["fit_window"]).replace("-", "–") +
                     ("" if f["fit_window"] == f["fit_window_without"]
                      else f" / {window_text(f['fit_window_without']).replace('-', '–')}"),
                     fmt(f["iterations_per_frame"]), fmt(f["iterations_per_frame_mu0"]), fmt(f["iterations_ratio"]),
                     fmt(f["linear_iterations_per_frame"]), fmt(f["linear_iterations_per_frame_mu0"]),
                     fmt(f["ms_per_frame"]), fmt(f["ms_per_frame_mu0"]), fmt(f["ms_ratio"])]
                    for f in res["friction"]]))
    if res["exponents"]:
        A(f"{sub} Growth exponents\n\nms/frame ≈ c · vertices^p, least squares in log-log over the levels, per "
          "label (mode, linear solver, friction) and thread count, each run's mean over the *frames* column: the "
          "run's `--window` where it has one, otherwise frames 1–W with W the fewest frames any completed run "
          "without a window has; *own frames*: each run's mean as in the runs table.\n")
        A(md_table(["mode", "threads", "levels", "frames", "p (ms/frame)", "p (own frames)", "p (ms/iteration)",
                    "p (it/frame)"] + [f"p ({STAGE_NAMES[k]})" for k in cols],
                   [[e["mode"], e["threads"], ", ".join(e["levels"]), window_text(e.get("fit_window") or [1, e["window_frames"]]).replace("-", "–"),
                     fmt(e["ms_per_frame"]), fmt(e["ms_per_frame_own_frames"]), fmt(e["ms_per_iteration"]),
                     fmt(e["iterations_per_frame"])] + [fmt(e[k]) for k in cols] for e in res["exponents"]]))
    if res["speedups"]:
        A(f"{sub} Thread speed-up\n\nms/frame with 1 thread ÷ ms/frame with T threads, same level, label (mode, "
          "linear solver, friction) and frames.\n")
        A(md_table(["level", "vertices", "mode", "threads", "ms/frame (1)", "ms/frame (T)", "speed-up",
                    "same it/frame"] + [STAGE_NAMES[k] for k in cols],
                   [[s["level"], fmt(s["vertices"]), s["mode"], s["threads"], fmt(s["ms_per_frame_1"]),
                     fmt(s["ms_per_frame_t"]), fmt(s["speedup"]), "yes" if s["same_iterations"] else "no"] +
                    [fmt(s["speedup_" + k]) for k in cols] for s in res["speedups"]]))
    A(f"{sub} Commands\n\n```sh\n" + "\n".join(r["command"] for r in res["runs"] if r.get("command")) + "\n```\n")
    return "\n".join(L).replace(str(ROOT) + "/", "")


# ---------------------------------------------------------------------------------------------

def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    s = sub.add_parser("scene", help="write one level's scene JSON")
    g = s.add_mutually_exclusive_group(required=True)
    g.add_argument("--vertices", type=int, help="the level closest to this vertex count")
    g.add_argument("--level", help="a level by name (%s) or nN" % ", ".join(lv for lv, _ in LEVELS))
    s.add_argument("--out", required=True, help="output folder (created)")
    s.add_argument("--frames", type=int, default=None, help="frames (default: the level's)")
    s.add_argument("--mode", default=None, help="MODE[:N][/LINEAR[@TOL]][+mu0]: write solver.mode (solver.iterations, "
                   "solver.linear_solver, solver.linear_tolerance; +mu0: no friction key) into the scene")
    r = sub.add_parser("run", help="run the ladder and write the summary")
    r.add_argument("--pce-sim", required=True, help="the pce-sim executable")
    r.add_argument("--results", required=True, help="results folder (created)")
    r.add_argument("--levels", default="8k,32k,128k", help="comma-separated levels (default 8k,32k,128k)")
    r.add_argument("--modes", default="newton", help="comma-separated MODE[:N][/LINEAR[@TOL]][+mu0] (default newton)")
    r.add_argument("--threads", default="1,2", help="comma-separated thread counts (default 1,2)")
    r.add_argument("--frames", type=int, default=None, help="frames of every level (default: 2k 30, 8k 30, 32k 20, 128k 15)")
    r.add_argument("--timeout", type=float, default=None, help="seconds per run, then SIGTERM (default: none)")
    r.add_argument("--note", default=None, help="a line about the conditions, kept in the summary")
    r.add_argument("--dry-run", action="store_true", help="print the pce-sim commands only")
    r.add_argument("--newton-levels", default=None, help="comma-separated levels Newton runs at (default: all)")
    r.add_argument("--window", default=None, metavar="A-B",
                   help="every mean over frames A..B (1-based, inclusive) instead of all frames")
    r.add_argument("--plan", default=None, choices=["full", "quick"],
                   help="run benchmarks/run_all's plan (plan_groups: full, or quick as run_all --quick); replaces --levels, "
                        "--modes, --threads, --frames, --window and --newton-levels")
    a = ap.parse_args(argv)

    def stop(signum, frame):
        raise KeyboardInterrupt
    signal.signal(signal.SIGTERM, stop)
    if a.command == "scene":
        name, n = level_by_name(a.level) if a.level else level_for_vertices(a.vertices)
        v = parse_variant(a.mode) if a.mode else {"mode": None, "iterations": None, "linear": None,
                                                   "linear_tolerance": None, "mu0": False}
        if a.frames is not None and a.frames < 1:
            raise ValueError("--frames must be >= 1")
        path = write_scene(a.out, name, n, a.frames or DEFAULT_FRAMES.get(name, 20), v["mode"], v["iterations"],
                           v["linear"], v["linear_tolerance"], v["mu0"])
        print(path)
        return 0
    if a.frames is not None and a.frames < 1:
        raise ValueError("--frames must be >= 1")
    threads = [int(t) for t in a.threads.split(",") if t.strip()]
    if not threads or any(t < 0 for t in threads):
        raise ValueError("--threads: comma-separated integers >= 0")
    levels = [x.strip() for x in a.levels.split(",") if x.strip()]
    modes = [x.strip() for x in a.modes.split(",") if x.strip()]
    for m in modes:
        parse_variant(m)
    for lv in levels:
        level_by_name(lv)
    window = parse_window(a.window)
    if not (Path(a.pce_sim).is_file() and os.access(a.pce_sim, os.X_OK)):
        raise ValueError(f"--pce-sim {a.pce_sim}: not an executable file")
    only = {"newton": a.newton_levels.split(",")} if a.newton_levels else None
    groups = plan_groups(a.plan) if a.plan else None
    res = run_ladder(a.pce_sim, a.results, levels, modes, threads, a.frames, a.timeout, a.dry_run, a.note, only,
                     window, groups)
    if res is None:
        return 0
    bad = [r for r in res["runs"] if r.get("status") not in ("ok", "not run")]
    return 1 if bad else 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (ValueError, OSError) as e:
        print(f"scale_ladder: {e}", file=sys.stderr)
        sys.exit(2)
    except KeyboardInterrupt:
        print("scale_ladder: stopped (the runs finished so far are in the results folder's scale_ladder.*)",
              file=sys.stderr)
        sys.exit(130)
