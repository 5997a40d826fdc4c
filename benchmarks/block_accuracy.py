#!/usr/bin/env python3
"""Block descent's accuracy against its time: a grid of substeps x sweeps, with and without
Chebyshev acceleration, against a tight-tolerance Newton reference, on two scenes.

    benchmarks/block_accuracy.py --pce-sim PATH --results DIR [--plan full|quick]
        [--scenes hammock,ladder:8k] [--frames F] [--at A,B]
        [--substeps 1,2,5,10] [--sweeps 5,10,20] [--accelerations none,chebyshev]
        [--max-sweeps-per-frame 100] [--scene-caps hammock=10] [--configs SPEC,...]
        [--reference 1e-4] [--newton 0.01] [--chebyshev-rho R] [--threads 1]
        [--timeout S] [--note TEXT] [--dry-run]

Configurations, per scene, one run at a time, in this order:
  newton@TOL   Newton at the reference tolerance (--reference, 1e-4: the reference every
               other run is measured against), then at each --newton tolerance (0.01):
               `pce-sim SCENE --out DIR --frames F --threads T --mode newton --tolerance TOL`
  bd:SxN[+chebyshev]
               block descent, S substeps of dt/S per frame, N sweeps per substep, without
               or with Chebyshev acceleration: `pce-sim SCENE --out DIR --frames F --threads T
               --mode block_descent --iterations N --substeps S --acceleration none|chebyshev`
               (scene keys solver.substeps, solver.acceleration; solver.chebyshev_rho is the
               scene's, default 0.95, or --chebyshev-rho's, written into a copy of the scene)
The block-descent grid is every S of --substeps x N of --sweeps x --accelerations, except
those with S*N > --max-sweeps-per-frame (their cost bound; listed as skipped; full plan 100),
and on a scene named in --scene-caps those above its own cap (full plan: hammock=10, where
10 sweeps a frame already cost more than Newton at 0.01: contact dominates its sweeps). --configs
replaces the grid with the block-descent specs given (the cap does not apply to them), e.g.
`--configs bd:2x10,bd:2x10+chebyshev`. A pce-sim whose --help lacks --substeps or
--acceleration runs S = 1 without acceleration only; the others are reported as not run.

Scenes (--scenes, comma-separated):
  hammock      examples/scenes/hammock.json, 60 frames, measured at frames 30 and 60
  ladder:LVL   the scale ladder's scene at level LVL (benchmarks/scale_ladder.py: 2k, 8k, 32k,
               128k or nN), 12 frames, measured at frame 12; written to
               DIR/scenes/block_accuracy_ladder_LVL.json
  FILE.json    any scene file, its own frames, measured at its last frame
--frames F sets every scene's frames (and, without --at, measures at frame F); --at A,B
sets the frames measured. A scene whose output_every would skip a measured frame is run
from a copy (DIR/scenes/block_accuracy_NAME.json) with output_every the frames' gcd.

Per run (row): scene, label, S, N, acceleration, ms/frame (mean wall_ms of stats.jsonl over
all frames), sweeps per frame (block descent's `sweeps`, summed over the frame's substeps;
Newton's `newton_iterations` for the Newton rows), the RMS over vertices of the distance to
the reference's positions at each measured frame (frame_NNNN.obj, every vertex of the
scene), the lowest z of any vertex at the last measured frame and its relative error
|z - z_ref| / |z_ref| against the reference's, the largest intersecting_triangle_pairs of
any frame, and the Pareto flag: a row is on the front when no other row of its scene has
both a lower ms/frame and a lower RMS at the last measured frame (the reference, RMS 0, is
among the rows: what is slower than it is dominated). A run that fails (pce-sim exit 3:
non-finite state; a timeout) keeps its frames' numbers and has no RMS where its frames stop.

Writes DIR/block_accuracy.json (every number, command, the plan, commit, date; rewritten
after every run, `complete` false until the last) and DIR/block_accuracy.md (a table per
scene); the runs go to DIR/runs/block_accuracy/SCENE/TAG/. --dry-run prints the commands and
an estimate of the time from COST_GUESS (assumed costs, not measurements) and writes nothing.
--plan full (the default) is the grid above on hammock and ladder:8k; --plan quick (run_all
--quick) the ladder's 2k level for 3 frames, measured at frames 2 and 3, S in {1, 2}, N = 5,
with and without acceleration; any flag given overrides the plan's value. `benchmarks/run_all
--steps block_accuracy` runs the full plan and puts its tables and plots into
docs/benchmarks.md section 8. Timings compare within one run of this script on an otherwise
idle machine. Only the Python standard library is used.
"""

import argparse
import datetime
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scale_ladder  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
HAMMOCK = ROOT / "examples" / "scenes" / "hammock.json"
ACCELERATIONS = ("none", "chebyshev")
REFERENCE_TOLERANCE = 1e-4

# The plans: run_all's full and quick steps. Every value can be overridden on the command line.
PLANS = {
    "full": {"scenes": ["hammock", "ladder:8k"], "frames": None, "at": None, "substeps": [1, 2, 5, 10],
             "sweeps": [5, 10, 20], "accelerations": ["none", "chebyshev"], "max_sweeps_per_frame": 100,
             "scene_caps": {"hammock": 10},
             "reference": REFERENCE_TOLERANCE, "newton": [0.01], "configs": None, "chebyshev_rho": None},
    "quick": {"scenes": ["ladder:2k"], "frames": 3, "at": [2, 3], "substeps": [1, 2], "sweeps": [5],
              "accelerations": ["none", "chebyshev"], "max_sweeps_per_frame": 200,
              "reference": REFERENCE_TOLERANCE, "newton": [0.01], "configs": None, "chebyshev_rho": None},
}
SCENE_DEFAULTS = {"hammock": {"frames": 60, "at": [30, 60]}, "ladder": {"frames": 12, "at": [12]}}

# Assumed costs for --dry-run's estimate only (never reported as measurements): Newton's
# seconds per frame, block descent's seconds per sweep (one sweep of one substep of a frame).
# Hammock: ~2 s/frame for Newton, ~0.2 s a sweep at 20 sweeps (block_accuracy.md of 217b98e:
# 4.97 s/frame at 20 sweeps); ladder 8k: scale_ladder.json of 217b98e (2.19 s/frame Newton,
# 0.97 s/frame at 20 sweeps, 1 thread); 2k: a quarter of 8k.
COST_GUESS = {"hammock": {"newton_s_per_frame": 2.0, "sweep_s": 0.2},
              "ladder:8k": {"newton_s_per_frame": 2.2, "sweep_s": 0.05},
              "ladder:2k": {"newton_s_per_frame": 0.55, "sweep_s": 0.0125}}


# ---------------------------------------------------------------------------------------------
# Configurations: specs, labels, the grid.

CONFIG_RE = re.compile(r"^bd:(?P<s>\d+)[x×](?P<n>\d+)(?:\+(?P<acc>[a-z_]+))?$")


def parse_int_list(text, what):
    """'1,2,5' -> [1, 2, 5]: positive integers, each once; ValueError otherwise."""
    out = []
    for t in str(text).split(","):
        t = t.strip()
        if not re.fullmatch(r"[0-9]+", t) or int(t) < 1:
            raise ValueError(f"{what}: {t!r} is not a positive integer (in {text!r})")
        if int(t) not in out:
            out.append(int(t))
    return out


def parse_float_list(text, what):
    """'0.01,0.001' -> [0.01, 0.001]: positive numbers; '' -> []."""
    out = []
    for t in str(text).split(","):
        t = t.strip()
        if not t:
            continue
        try:
            v = float(t)
        except ValueError:
            raise ValueError(f"{what}: {t!r} is not a number") from None
        if not (v > 0 and math.isfinite(v)):
            raise ValueError(f"{what}: {t!r} is not a positive number")
        out.append(v)
    return out


def parse_scene_caps(text):
    """'hammock=20,ladder:8k=50' -> {'hammock': 20, 'ladder:8k': 50}."""
    out = {}
    for item in [x.strip() for x in text.split(",") if x.strip()]:
        scene, eq, cap = item.rpartition("=")
        if not eq or not scene or not cap.isdigit() or int(cap) < 1:
            raise ValueError(f"--scene-caps: {item!r} is not SCENE=CAP with CAP a positive integer")
        out[scene] = int(cap)
    return out


def parse_accelerations(text):
    out = []
    for t in str(text).split(","):
        t = t.strip()
        if t not in ACCELERATIONS:
            raise ValueError(f"--accelerations: {t!r} is not one of {', '.join(ACCELERATIONS)}")
        if t not in out:
            out.append(t)
    return out


def newton_config(tolerance, reference=False):
    return {"mode": "newton", "tolerance": float(tolerance), "substeps": 1, "sweeps": None, "acceleration": None,
            "reference": reference}


def block_config(substeps, sweeps, acceleration="none"):
    return {"mode": "block_descent", "tolerance": None, "substeps": substeps, "sweeps": sweeps,
            "acceleration": acceleration, "reference": False}


def parse_config(spec):
    """'newton@1e-4' or 'bd:SxN[+chebyshev]' ('×' for 'x' too; '+none' is the default) -> a
    configuration dict; ValueError for anything else."""
    spec = spec.strip()
    if spec.startswith("newton@"):
        tol = parse_float_list(spec[len("newton@"):] or "x", f"configuration {spec!r}")
        if len(tol) != 1:
            raise ValueError(f"configuration {spec!r}: newton@TOL takes one tolerance")
        return newton_config(tol[0])
    m = CONFIG_RE.match(spec)
    if not m:
        raise ValueError(f"configuration {spec!r}: not newton@TOL or bd:SxN[+chebyshev]")
    s, n, acc = int(m.group("s")), int(m.group("n")), m.group("acc") or "none"
    if s < 1 or n < 1:
        raise ValueError(f"configuration {spec!r}: substeps and sweeps must be at least 1")
    if acc not in ACCELERATIONS:
        raise ValueError(f"configuration {spec!r}: acceleration {acc!r} is not one of {', '.join(ACCELERATIONS)}")
    return block_config(s, n, acc)


def config_spec(c):
    """The canonical spec of a configuration (parse_config's inverse): 'newton@0.0001', 'bd:2x10',
    'bd:2x10+chebyshev'."""
    if c["mode"] == "newton":
        return f"newton@{c['tolerance']:g}"
    return f"bd:{c['substeps']}x{c['sweeps']}" + ("" if c["acceleration"] == "none" else f"+{c['acceleration']}")


def config_label(c):
    """A row's name in the tables: 'Newton 0.0001 (reference)', 'Newton 0.01', 'block descent
    2×10', 'block descent 2×10 Chebyshev'."""
    if c["mode"] == "newton":
        return f"Newton {c['tolerance']:g}" + (" (reference)" if c.get("reference") else "")
    return f"block descent {c['substeps']}×{c['sweeps']}" + (" Chebyshev" if c["acceleration"] == "chebyshev" else "")


def config_tag(c):
    """A run folder's name: 'newton_tol0.0001', 'bd_s2_n10_none'."""
    if c["mode"] == "newton":
        return f"newton_tol{c['tolerance']:g}"
    return f"bd_s{c['substeps']}_n{c['sweeps']}_{c['acceleration']}"


def expand_grid(substeps, sweeps, accelerations, max_sweeps_per_frame):
    """The block-descent grid, accelerations outermost, then S, then N: (configurations run,
    configurations skipped because S*N > max_sweeps_per_frame)."""
    run, skipped = [], []
    for acc in accelerations:
        for s in substeps:
            for n in sweeps:
                (skipped if max_sweeps_per_frame and s * n > max_sweeps_per_frame else run).append(
                    block_config(s, n, acc))
    return run, skipped


def plan_configs(plan):
    """Every configuration of a plan, in run order: the reference, the other Newton tolerances,
    then block descent (the grid or plan['configs']); and the grid's skipped ones."""
    out = [newton_config(plan["reference"], reference=True)]
    out += [newton_config(t) for t in plan["newton"] if t != plan["reference"]]
    if plan.get("configs"):
        bd = [parse_config(s) for s in plan["configs"]]
        if any(c["mode"] != "block_descent" for c in bd):
            raise ValueError("--configs: block descent only (bd:SxN[+chebyshev]); Newton runs are --reference and "
                             "--newton")
        skipped = []
    else:
        bd, skipped = expand_grid(plan["substeps"], plan["sweeps"], plan["accelerations"],
                                  plan["max_sweeps_per_frame"])
    seen, unique = set(), []
    for c in out + bd:
        if config_spec(c) not in seen:
            seen.add(config_spec(c))
            unique.append(c)
    return unique, skipped


def pareto_flags(points):
    """points: (x, y) pairs (y None or not finite: no point). Flag i is True when the point has
    numbers and no other point has both x < x_i and y < y_i."""
    def ok(p):
        return p[0] is not None and p[1] is not None and math.isfinite(p[0]) and math.isfinite(p[1])
    return [ok(p) and not any(ok(q) and q[0] < p[0] and q[1] < p[1] for j, q in enumerate(points) if j != i)
            for i, p in enumerate(points)]


# ---------------------------------------------------------------------------------------------
# Scenes.

def resolve_scene(spec, frames=None, at=None):
    """A scene spec ('hammock', 'ladder:8k', a .json file) with its frames and measured frames:
    {key, spec, kind, frames, at, file or level/n}."""
    spec = spec.strip()
    if spec == "hammock":
        s = {"key": "hammock", "kind": "file", "file": str(HAMMOCK), **SCENE_DEFAULTS["hammock"]}
    elif spec.startswith("ladder:"):
        level, n = scale_ladder.level_by_name(spec[len("ladder:"):])
        s = {"key": f"ladder_{level}", "kind": "ladder", "level": level, "n": n, **SCENE_DEFAULTS["ladder"]}
    elif spec.endswith(".json"):
        path = Path(spec).resolve()
        if not path.is_file():
            raise ValueError(f"--scenes: no scene file {spec}")
        own = json.loads(path.read_text()).get("frames")
        if not own and not frames:
            raise ValueError(f"--scenes: {spec} has no frames: give --frames")
        s = {"key": re.sub(r"[^A-Za-z0-9_]+", "_", path.stem), "kind": "file", "file": str(path),
             "frames": own, "at": [own]}
    else:
        raise ValueError(f"--scenes: {spec!r} is not hammock, ladder:LEVEL or a .json file")
    s["spec"] = spec
    if frames:
        s["frames"] = frames
        s["at"] = [frames]
    if at:
        s["at"] = sorted(set(at))
    if max(s["at"]) > s["frames"]:
        raise ValueError(f"scene {spec}: a measured frame ({max(s['at'])}) is beyond its {s['frames']} frames")
    return s


def output_every_for(at):
    """The output interval that writes every measured frame: their gcd."""
    g = 0
    for f in at:
        g = math.gcd(g, f)
    return g or 1


def scene_writes(scene_json, frames, at):
    """Whether a scene as it is writes every frame of `at` in a run of `frames` frames."""
    every = int(scene_json.get("output_every", 1))
    return all(f % every == 0 or f == frames for f in at)


def prepare_scene(s, results, rho=None, dry_run=False):
    """The scene file to run: the file itself when it writes every measured frame (and no
    --chebyshev-rho), else a copy in RESULTS/scenes/ with output_every = gcd(at) (relative mesh
    files made absolute); the ladder's level, generated. Nothing is written with dry_run."""
    scenes = Path(results) / "scenes"
    if s["kind"] == "ladder":
        scene = scale_ladder.make_scene(s["level"], s["n"], s["frames"])
        path = scenes / f"block_accuracy_{s['key']}.json"
    else:
        src = Path(s["file"])
        scene = json.loads(src.read_text())
        if rho is None and scene_writes(scene, s["frames"], s["at"]):
            return src
        for m in scene.get("meshes", []):
            if isinstance(m.get("file"), str) and not os.path.isabs(m["file"]):
                m["file"] = str((src.parent / m["file"]).resolve())
        path = scenes / f"block_accuracy_{s['key']}.json"
    scene["output_every"] = output_every_for(s["at"])
    if rho is not None:
        scene.setdefault("solver", {})["chebyshev_rho"] = rho
    if not dry_run:
        scenes.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(scene, indent=1) + "\n")
    return path


# ---------------------------------------------------------------------------------------------
# Runs.

def config_arguments(c, help_text):
    """pce-sim's options for configuration c; ValueError when this pce-sim (its --help text;
    None: assume every option) cannot select it."""
    def has(flag):
        return help_text is None or re.search(re.escape(flag) + r"\b", help_text) is not None
    if not has("--mode"):
        raise ValueError("this pce-sim has no --mode")
    if c["mode"] == "newton":
        return ["--mode", "newton", "--tolerance", repr(c["tolerance"])]
    args = ["--mode", "block_descent", "--iterations", str(c["sweeps"])]
    if has("--substeps"):
        args += ["--substeps", str(c["substeps"])]
    elif c["substeps"] != 1:
        raise ValueError("this pce-sim has no --substeps")
    if has("--acceleration"):
        args += ["--acceleration", c["acceleration"]]
    elif c["acceleration"] != "none":
        raise ValueError("this pce-sim has no --acceleration")
    return args


def rms_distance(a, b):
    """RMS over vertices of |a_i - b_i| (same vertex count)."""
    if len(a) != len(b) or not a:
        raise ValueError(f"vertex counts differ: {len(a)} and {len(b)}")
    return math.sqrt(sum(sum((p - q) ** 2 for p, q in zip(u, v)) for u, v in zip(a, b)) / len(a))


def frame_file(directory, f):
    return Path(directory) / f"frame_{f:04d}.obj"


def summarise(records):
    """ms/frame (mean wall_ms), iterations per frame (block descent's sweeps, summed over the
    substeps, else Newton iterations), the substeps the records report, max intersecting pairs."""
    n = len(records)
    if not n:
        return {"frames_done": 0, "ms_per_frame": None, "iterations_per_frame": None, "substeps_reported": None,
                "max_intersecting_pairs": None}
    its = [r["sweeps"] if r.get("sweeps") else r.get("newton_iterations") for r in records]
    its = [x for x in its if isinstance(x, (int, float))]
    subs = sorted({r.get("substeps", 1) for r in records})
    return {"frames_done": n, "ms_per_frame": sum(r["wall_ms"] for r in records) / n,
            "iterations_per_frame": sum(its) / len(its) if its else None,
            "substeps_reported": subs[0] if len(subs) == 1 else subs,
            "max_intersecting_pairs": max(r.get("intersecting_triangle_pairs", 0) for r in records)}


def short(cmd):
    return " ".join(str(c) for c in cmd).replace(str(ROOT) + "/", "")


def log(msg):
    print(f"[block_accuracy {datetime.datetime.now().strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def estimate_seconds(scene, c):
    """--dry-run's estimate of one run from COST_GUESS (None for a scene without a guess)."""
    g = COST_GUESS.get(scene["spec"])
    if not g:
        return None
    per_frame = g["newton_s_per_frame"] if c["mode"] == "newton" else g["sweep_s"] * c["substeps"] * c["sweeps"]
    return per_frame * scene["frames"]


def measure(rows, scene):
    """RMS to the reference at each measured frame, the lowest point and its relative error, and
    the Pareto flags, for the rows of one scene (in place)."""
    ref = next((r for r in rows if r["reference"]), None)
    last = max(scene["at"])
    ref_pos = {}
    if ref and ref["status"] == "ok":
        for f in scene["at"]:
            if frame_file(ref["dir"], f).exists():
                ref_pos[f] = scale_ladder.read_positions(frame_file(ref["dir"], f))
    ref_low = min(p[2] for p in ref_pos[last]) if last in ref_pos else None
    for r in rows:
        r["rms_m"], r["lowest_z_m"], r["reference_lowest_z_m"], r["lowest_z_rel_error"] = {}, None, ref_low, None
        if r["status"] not in ("ok", "failed") or not r.get("dir"):
            continue
        for f in scene["at"]:
            p = frame_file(r["dir"], f)
            if f in ref_pos and p.exists() and r["frames_done"] >= f:
                r["rms_m"][str(f)] = rms_distance(scale_ladder.read_positions(p), ref_pos[f])
        p = frame_file(r["dir"], last)
        if p.exists() and r["frames_done"] >= last:
            r["lowest_z_m"] = min(v[2] for v in scale_ladder.read_positions(p))
            if ref_low:
                r["lowest_z_rel_error"] = abs(r["lowest_z_m"] - ref_low) / abs(ref_low)
    flags = pareto_flags([(r.get("ms_per_frame") if r["status"] in ("ok", "failed") else None,
                           r["rms_m"].get(str(last))) for r in rows])
    for r, f in zip(rows, flags):
        r["pareto"] = f


def run_grid(exe, results, plan, threads=1, timeout=None, dry_run=False, note=None, plan_name=None):
    """Runs every scene x configuration of `plan` (PLANS' keys), one at a time; writes
    block_accuracy.json/.md into `results` (after every run); returns the summary dict (with
    dry_run: prints the commands and the estimate, writes and runs nothing, returns None)."""
    results = Path(results).resolve()
    configs, skipped = plan_configs(plan)
    scenes = [resolve_scene(sp, plan.get("frames"), plan.get("at")) for sp in plan["scenes"]]
    help_text = None if dry_run else scale_ladder.sim_help(exe)
    meta = {"pce_sim": str(exe), "plan": plan_name, "settings": {k: v for k, v in plan.items()},
            "threads": threads, "timeout_s": timeout, "commit": scale_ladder.git_commit(),
            "date_utc": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "cores": os.cpu_count(), "load_average_at_start": list(os.getloadavg()), "note": note or "",
            "skipped": [config_spec(c) for c in skipped], "scenes": scenes, "configurations": len(configs)}
    rows, total_guess = [], 0.0
    for s in scenes:
        path = prepare_scene(s, results, plan.get("chebyshev_rho"), dry_run)
        s["file_run"] = short([path])
        cap = None if plan.get("configs") else (plan.get("scene_caps") or {}).get(s["spec"])
        s["cap"], s["skipped"] = cap, []
        for c in configs:
            if cap and c["mode"] == "block_descent" and c["substeps"] * c["sweeps"] > cap:
                s["skipped"].append(config_spec(c))
                continue
            out = results / "runs" / "block_accuracy" / s["key"] / config_tag(c)
            row = {"scene": s["key"], "spec": config_spec(c), "label": config_label(c), **c,
                   "planned_sweeps_per_frame": c["substeps"] * c["sweeps"] if c["sweeps"] else None,
                   "dir": str(out), "status": None, "reason": None, "command": None}
            try:
                args = config_arguments(c, help_text)
            except ValueError as e:
                row.update(status="not run", reason=str(e))
                rows.append(row)
                continue
            cmd = [exe, path, "--out", out, "--frames", str(s["frames"]), "--threads", str(threads)] + args
            row["command"] = short(cmd)
            if dry_run:
                guess = estimate_seconds(s, c)
                total_guess += guess or 0
                print(row["command"] + (f"    # ~{guess / 60:.1f} min (assumed)" if guess is not None else ""))
                continue
            if out.exists():
                shutil.rmtree(out)  # stale frames would be compared as this run's
            log(f"{s['key']}: {row['label']} ...")
            code, wall, timed_out = scale_ladder.run_one(cmd, out, timeout)
            row.update(summarise(scale_ladder.load_records(out)), exit_code=code, wall_s=wall, timed_out=timed_out)
            if code == 0 and row["frames_done"] >= s["frames"]:
                row["status"] = "ok"
                if c["substeps"] > 1 and row["substeps_reported"] != c["substeps"]:
                    row["reason"] = f"stats.jsonl reports substeps {row['substeps_reported']}, not {c['substeps']}"
            elif code == 2:  # invalid input: nothing simulated
                row.update(status="not run", reason=scale_ladder.log_error(out))
            else:
                row.update(status="failed", reason=("timed out: " if timed_out else "")
                           + f"exit {code} after {row['frames_done']} of {s['frames']} frames: "
                           + scale_ladder.log_error(out))
            log(f"  {row['status']}: {scale_ladder.fmt(row['ms_per_frame'])} ms/frame, "
                f"{scale_ladder.fmt(row['iterations_per_frame'])} it/frame"
                + (f" ({row['reason']})" if row["reason"] else ""))
            rows.append(row)
            write_outputs(results, dict(meta, rows=rows, complete=False))
        if not dry_run:
            measure([r for r in rows if r["scene"] == s["key"]], s)
    if dry_run:
        for s in scenes:
            if s["skipped"]:
                print(f"# {s['key']}: skipped (S×N > its cap {s['cap']}): {', '.join(s['skipped'])}")
        print(f"# {len(scenes)} scene(s) x {len(configs)} configurations"
              + (f"; skipped (S×N > {plan['max_sweeps_per_frame']}): {', '.join(meta['skipped'])}"
                 if skipped else "")
              + f"; about {total_guess / 3600:.1f} h from COST_GUESS (assumed costs, see the script)")
        return None
    res = dict(meta, rows=rows, complete=True)
    write_outputs(results, res)
    if not any(r["status"] == "ok" and r["reference"] for r in rows):
        log("WARNING: no reference run finished: no RMS")
    return res


def write_outputs(results, res):
    (Path(results) / "block_accuracy.json").write_text(json.dumps(res, indent=1, default=str) + "\n")
    (Path(results) / "block_accuracy.md").write_text(markdown(res))


# ---------------------------------------------------------------------------------------------
# Tables.

def mm(x):
    return scale_ladder.fmt(1000 * x) if isinstance(x, (int, float)) else "n/a"


def scene_title(s):
    what = ("`examples/scenes/hammock.json`" if s["spec"] == "hammock" else
            f"the scale ladder's {s['level']} level" if s["kind"] == "ladder" else f"`{s['file_run']}`")
    return f"{what}, {s['frames']} frames, measured at frame{'s' if len(s['at']) > 1 else ''} " + \
        ", ".join(map(str, s["at"]))


def table_rows(res, s):
    """The markdown table of one scene's rows (header, rows)."""
    at = s["at"]
    header = (["run", "S", "N", "acceleration", "ms/frame", "sweeps/frame (Newton: iterations)"] +
              [f"RMS to ref., frame {f} (mm)" for f in at] +
              [f"lowest z, frame {max(at)} (mm)", "rel. error of lowest z", "max ∩ pairs", "Pareto"])
    out = []
    for r in [r for r in res["rows"] if r["scene"] == s["key"]]:
        measured = r["status"] in ("ok", "failed")
        out.append([r["label"] + ("" if r["status"] == "ok" else f" ({r['status']})"),
                    r["substeps"], r["sweeps"] if r["sweeps"] else "—", r["acceleration"] or "—",
                    scale_ladder.fmt(r.get("ms_per_frame")) if measured else "—",
                    scale_ladder.fmt(r.get("iterations_per_frame")) if measured else "—"] +
                   [mm(r.get("rms_m", {}).get(str(f))) if measured else "—" for f in at] +
                   [mm(r.get("lowest_z_m")) if measured else "—",
                    scale_ladder.fmt(r.get("lowest_z_rel_error")) if measured else "—",
                    scale_ladder.fmt(r.get("max_intersecting_pairs")) if measured else "—",
                    "**yes**" if r.get("pareto") else ""])
    return header, out


def table_align(n):
    """The tables' alignment: run and acceleration left, the numbers right, Pareto left."""
    return ["---"] + ["---:"] * 2 + ["---"] + ["---:"] * (n - 5) + ["---"]


def md_table(header, rows, align):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join(align) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out) + "\n"


def markdown(res, sub="##"):
    L = []
    for s in res["scenes"]:
        L.append(f"{sub} {s['key']}: {scene_title(s)}\n")
        header, rows = table_rows(res, s)
        L.append(md_table(header, rows, table_align(len(header))))
        if s.get("skipped"):
            L.append(f"Skipped on this scene (S × N above its cap of {s['cap']} sweeps per frame): "
                     + ", ".join(f"`{x}`" for x in s["skipped"]) + ".\n")
        notes = [r for r in res["rows"] if r["scene"] == s["key"] and (r["status"] != "ok" or r["reason"])]
        for r in notes:
            L.append(f"- {r['label']}: {r['status']}" + (f": {r['reason']}" if r["reason"] else ""))
        if notes:
            L.append("")
    if res.get("skipped"):
        L.append(f"Skipped (S × N above {res['settings']['max_sweeps_per_frame']} sweeps per frame): "
                 + ", ".join(f"`{x}`" for x in res["skipped"]) + ".\n")
    if not res.get("complete", True):
        L.append("Incomplete: the grid stopped before its last run.\n")
    return "\n".join(L)


# ---------------------------------------------------------------------------------------------

def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pce-sim", required=True, help="the pce-sim executable")
    ap.add_argument("--results", required=True, help="results folder (created)")
    ap.add_argument("--plan", default="full", choices=sorted(PLANS), help="the defaults below (default full)")
    ap.add_argument("--scenes", help="comma-separated: hammock, ladder:LEVEL, FILE.json")
    ap.add_argument("--frames", type=int, help="every scene's frames (default: hammock 60, ladder 12)")
    ap.add_argument("--at", help="comma-separated frames measured (default: hammock 30,60; ladder 12; --frames F: F)")
    ap.add_argument("--substeps", help="comma-separated S (full plan: 1,2,5,10)")
    ap.add_argument("--sweeps", help="comma-separated N, sweeps per substep (full plan: 5,10,20)")
    ap.add_argument("--accelerations", help="comma-separated, of none, chebyshev (default both)")
    ap.add_argument("--max-sweeps-per-frame", type=int, help="skip grid points with S*N above it (full plan 100; 0: no cap)")
    ap.add_argument("--scene-caps", help="comma-separated SCENE=CAP: a lower S*N cap for one scene's grid "
                    "(full plan: hammock=10; '' for none)")
    ap.add_argument("--configs", help="comma-separated bd:SxN[+chebyshev]: run these instead of the grid")
    ap.add_argument("--reference", type=float, help="the reference's Newton tolerance (default 1e-4)")
    ap.add_argument("--newton", help="comma-separated further Newton tolerances (default 0.01; '' for none)")
    ap.add_argument("--chebyshev-rho", type=float, help="solver.chebyshev_rho, written into a copy of each scene")
    ap.add_argument("--threads", type=int, default=1, help="pce-sim --threads (default 1)")
    ap.add_argument("--timeout", type=float, default=None, help="seconds per run, then SIGTERM (default: none)")
    ap.add_argument("--note", default=None, help="a line about the conditions, kept in the JSON")
    ap.add_argument("--dry-run", action="store_true", help="print the commands and an estimate; run nothing")
    a = ap.parse_args(argv)
    plan = dict(PLANS[a.plan])
    try:
        if a.scenes is not None:
            plan["scenes"] = [x for x in a.scenes.split(",") if x.strip()]
        if a.frames is not None:
            plan["frames"], plan["at"] = a.frames, None
        if a.at is not None:
            plan["at"] = parse_int_list(a.at, "--at")
        if a.substeps is not None:
            plan["substeps"] = parse_int_list(a.substeps, "--substeps")
        if a.sweeps is not None:
            plan["sweeps"] = parse_int_list(a.sweeps, "--sweeps")
        if a.accelerations is not None:
            plan["accelerations"] = parse_accelerations(a.accelerations)
        if a.max_sweeps_per_frame is not None:
            plan["max_sweeps_per_frame"] = a.max_sweeps_per_frame
        if a.scene_caps is not None:
            plan["scene_caps"] = parse_scene_caps(a.scene_caps)
        if a.configs is not None:
            plan["configs"] = [x for x in a.configs.split(",") if x.strip()]
        if a.reference is not None:
            plan["reference"] = a.reference
        if a.newton is not None:
            plan["newton"] = parse_float_list(a.newton, "--newton")
        if a.chebyshev_rho is not None:
            plan["chebyshev_rho"] = a.chebyshev_rho
        custom = any(getattr(a, k) is not None for k in ("scenes", "frames", "at", "substeps", "sweeps", "accelerations",
                                                          "max_sweeps_per_frame", "scene_caps", "configs", "reference", "newton",
                                                          "chebyshev_rho"))
        res = run_grid(a.pce_sim, a.results, plan, threads=a.threads, timeout=a.timeout, dry_run=a.dry_run,
                       note=a.note, plan_name=a.plan + (" (changed on the command line)" if custom else ""))
    except ValueError as e:
        ap.error(str(e))
    if res:
        print(markdown(res))
        for r in res["rows"]:
            if r["status"] == "failed":
                log(f"WARNING: {r['scene']}: {r['label']} failed: {r['reason']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
