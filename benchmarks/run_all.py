"""What accuracy costs in time: runs every benchmark and rewrites docs/benchmarks.md.

    benchmarks/run_all [--quick] [--build DIR] [--results DIR] [--docs FILE] [--jobs N] [--steps S]
                       [--before REV]

The executables come from --build DIR as they are. Without --build: from build/ when it has
every executable the steps need, otherwise run_all configures build-benchmarks/ (Release,
tests and benchmarks on, examples and pce-probe off) and builds just those targets there.

Steps, in this order (each writes JSON/CSV into the results folder):
  machine      machine.json: CPU, cores, memory, OS, compiler, library versions, commit
  pair_cost    pce_bench.json: pce-bench, ns per pair (median of interleaved repetitions)
  accuracy     accuracy.json/.csv: pce-accuracy, distance to the 50-digit nearest-PSD Hessian
  broad_phase  broad_phase.json/.csv: pce-broad-phase-bench, FCL vs Bullet vs brute force
  threads      threads.csv: pce-sim at 1 and 2 threads, stage times
  scenes       scenes.json/.csv: pce-sim per scene x strategy x mode x tolerance, deviation
               from a tight-tolerance reference run (threads and scenes run the shipped scenes
               without their friction objects)
  hammock      hammock.csv: pce-sim on the shipped hammock without friction
               (examples/scenes/hammock_frictionless.json: older pce-sim versions reject the
               friction key, so a before/after compares like with like), frames 1-120, full
               Newton and single solve, one thread, each run alone: ms per frame and its split,
               Newton iterations, queries, factorisations, analyses, CG iterations. With
               --before REV the same runs of commit REV's pce-sim (built from `git archive REV`
               in build-before/REV), interleaved with this build's: a before/after table
  friction     friction.csv: friction's cost on the hammock: hammock_frictionless.json, then
               hammock.json (the same scene with friction), frames 1-120, full Newton, one
               thread, each run alone: ms per frame, Newton iterations, friction ms and
               friction contacts per frame (the *_friction_ms and *_friction_contacts counters),
               line-search failures, iteration caps, frames with intersections
  compile_time compile_time.json/.csv: a header-only library's cost to its users: wall time
               (median of 3, --quick: 1), CPU time and peak memory of compiling, one at a time,
               benchmarks/compile_time/minimal_runtime.cpp (strategy at run time) and
               minimal_template.cpp (at compile time), each example and `#include <pce/pce.hpp>`
               alone, header-only and with -DPCE_PRECOMPILED (pce::precompiled), with the
               compiler of the build folder's CMakeCache.txt; --quick: the three fast ones.
               It needs no executable, and run alone it leaves machine.json as it is (its own
               JSON records compiler, commit and date); --note TEXT is kept in its JSON.
  scale        scale_ladder.json/.csv/.md: benchmarks/scale_ladder.py, a generated 1 m cloth dropped
               onto a sphere and a floor, each run alone, the plan scale_ladder.plan_groups("full"):
               full Newton at 8k, 32k and 128k vertices with linear solver direct (every
               level), amg and pcg (8k), 1 and 2 threads, and friction off (+mu0) with the
               default linear solver (direct), 1 thread, all 12 frames with
               means over frames 5-12; block descent (20 iterations; reported as not run by a
               pce-sim without --mode) at 8k, 32k, 128k, 1 and 2 threads, frames 30, 20, 15.
               ms per frame and its split, iterations, linear iterations, factorisations,
               queries, intersecting pairs, peak memory, the growth exponent of ms/frame in
               the vertex count per label, the 2-thread speed-up, friction's cost (with ÷
               without); --quick: 2k vertices, newton/direct, newton/direct+mu0 and block
               descent, 3 frames
  block_accuracy
               block_accuracy.json/.md: benchmarks/block_accuracy.py --plan full, block descent's
               accuracy against its time on the hammock (60 frames, RMS at frames 30 and 60) and
               the scale ladder's 8k level (12 frames, RMS at frame 12), one run at a time, one
               thread: Newton at tolerance 1e-4 (the reference) and 0.01, and block descent over
               the grid substeps S in {1, 2, 5, 10} x sweeps per substep N in {5, 10, 20}, without
               and with Chebyshev acceleration (S*N above 100 skipped: 10 x 20; on the hammock
               above 10, where 10 sweeps a frame already cost more than Newton). Per run
               ms/frame, sweeps per frame, the RMS distance to the reference at the measured
               frames, the lowest point and its relative error, the most intersecting pairs, and
               whether it is on the Pareto front of ms/frame against the last frame's RMS; a
               Pareto plot per scene (images/benchmarks/block_accuracy_<scene>.png) and a
               subsection of section 8. Hours, not minutes (block_accuracy.py --dry-run prints the
               commands and an estimate); --quick: --plan quick, the ladder's 2k level for 3
               frames, S in {1, 2}, N = 5, both accelerations
then draws the PNG plots (next to the docs file, in images/benchmarks/) and writes the docs
file, whose last section is benchmarks/guidance.md with its numbers recomputed from the
results folder by benchmarks/guidance_numbers.py (when the results folder is
benchmarks/results, guidance.md itself is rewritten too). --quick runs a few-second subset of every step (the test suite's smoke test) and
writes its docs file into the results folder unless --docs says otherwise.

Timings are only compared within one run; nothing here asserts a timing. The script exits
non-zero when a step fails or an output is missing.
"""

import argparse
import concurrent.futures
import csv
import datetime
import json
import math
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
import block_accuracy  # noqa: E402
import compare_runs  # noqa: E402
import guidance_numbers  # noqa: E402
import scale_ladder  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
STRATEGIES = ["analytic", "abs", "exact", "gauss_newton", "numerical"]
PAIRS = ["vertex_face", "edge_edge", "point_edge", "point_point"]
STAGES = ["broad_phase_ms", "pair_ms", "assembly_ms", "solve_ms", "line_search_ms"]
STAGE_NAMES = {"broad_phase_ms": "broad phase", "pair_ms": "pair evaluation", "assembly_ms": "assembly",
               "solve_ms": "linear solve", "line_search_ms": "line search", "other_ms": "other"}
COLORS = {"analytic": "tab:blue", "abs": "tab:orange", "exact": "tab:green", "gauss_newton": "tab:red",
          "numerical": "tab:purple"}


# ---------------------------------------------------------------------------------------------
# Plans: what runs in full and in quick mode.

def scene_plan(quick):
    """Scene variants: name -> (shipped scene, changes). Shortened where the full one is too long."""
    if quick:
        return {"twist": ("twist", {"frames": 4})}
    return {
        "twist": ("twist", {"frames": 110}),        # contact from frame ~31; the last 30 frames are at rest
        "drape": ("drape", {"frames": 30}),         # the cloth lands on the ball (frames 8-30)
        "strands": ("strands", {"frames": 40}),     # 48 strands land on the capsule and the floor
        "hammock_coarse": ("hammock", {"frames": 40, "resolution": 22}),  # first sheet lands; 1/4 the vertices
    }


def scene_configs(quick):
    """(strategy, mode, tolerance) triples run on every scene; mode 'newton' or 'single'."""
    if quick:
        return [("analytic", "newton", 1e-2), ("numerical", "newton", 1e-2), ("analytic", "single", None)]
    out = []
    for s in STRATEGIES:
        out.append((s, "single", None))
        for tol in (1e-1, 1e-2, 1e-3):
            out.append((s, "newton", tol))
    return out


ALL_STEPS = ["pair_cost", "accuracy", "broad_phase", "threads", "scenes", "hammock", "friction", "compile_time",
             "scale", "block_accuracy"]
OPTIONAL_STEPS = {"friction", "compile_time", "scale", "block_accuracy"}  # steps whose missing results the page reports as not measured
FRICTION_KINDS = ["vertex_face", "edge_edge", "obstacle"]  # the contact kinds' friction counters' prefixes
FRICTION_SCENES = [("without friction", "hammock_frictionless.json"), ("with friction", "hammock.json")]
REFERENCE = ("exact", "newton", 1e-5)      # the tight-tolerance reference of every scene
NOISE_FLOOR = ("numerical", "newton", 1e-5)  # a second tight run: how far two converged runs differ
HEADLINE_SCENE = ("hammock", {"frames": 20})  # full resolution, every strategy at the scene's tolerance


# ---------------------------------------------------------------------------------------------
# Small utilities.

def log(msg):
    print(f"[run_all {datetime.datetime.now().strftime('%H:%M:%S')}] {msg}", flush=True)


def run(cmd, stdout=None, cwd=None, check=True):
    """Runs a command; on failure prints its stderr tail and raises."""
    t0 = time.monotonic()
    p = subprocess.run([str(c) for c in cmd], stdout=stdout or subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                       cwd=cwd)
    if check and p.returncode != 0:
        tail = "\n".join(p.stderr.strip().splitlines()[-15:])
        raise RuntimeError(f"command failed ({p.returncode}): {' '.join(map(str, cmd))}\n{tail}")
    p.wall_s = time.monotonic() - t0
    return p


def median(xs):
    xs = [x for x in xs if x is not None and math.isfinite(x)]
    return statistics.median(xs) if xs else float("nan")


def fit_exponent(ns, ts):
    """Least-squares slope of log t against log n: t ~ c n^slope."""
    pts = [(math.log(n), math.log(t)) for n, t in zip(ns, ts) if n > 0 and t and t > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx > 0 else float("nan")


def read_obj_vertices(path):
    vs = []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vs.append(tuple(float(t) for t in line.split()[1:4]))
    return vs


def deviation(a, b):
    """RMS and max over vertices of |a_i - b_i| (same vertex count)."""
    if len(a) != len(b) or not a:
        raise ValueError(f"vertex counts differ: {len(a)} and {len(b)}")
    d2 = [sum((p - q) ** 2 for p, q in zip(u, v)) for u, v in zip(a, b)]
    return math.sqrt(sum(d2) / len(d2)), math.sqrt(max(d2))


def write_csv(path, rows, columns=None):
    columns = columns or (list(rows[0].keys()) if rows else [])
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow(r)


def fmt(x, digits=3):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "n/a"
    if isinstance(x, float) and math.isinf(x):
        return "∞" if x > 0 else "−∞"
    if isinstance(x, int):
        return str(x)
    if x == 0:
        return "0"
    a = abs(x)
    if a >= 1000:
        return f"{x:,.0f}".replace(",", " ")
    if a >= 0.01:
        return f"{x:.{digits}g}"
    return f"{x:.1e}"


def md_table(header, rows, align=None):
    align = align or ["---"] + ["---:"] * (len(header) - 1)
    out = ["| " + " | ".join(header) + " |", "|" + "|".join(align) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------
# Steps.

class Context:
    def __init__(self, args):
        self.args = args
        self.quick = args.quick
        self.build = Path(args.build).resolve()
        self.results = Path(args.results).resolve()
        self.docs = Path(args.docs).resolve()
        self.images = self.docs.parent / "images" / "benchmarks"
        self.jobs = args.jobs
        self.before = args.before
        self.note = args.note

    def exe(self, name):
        p = find_exe(self.build, name)
        if p:
            return p
        raise RuntimeError(f"{name} not found under {self.build}: build it first "
                           f"(cmake --build {self.build} --target {name})")


BUILD_SUBDIRS = ("benchmarks", "src/sim", "tests", "src/probe", ".")


def find_exe(build, name):
    for sub in BUILD_SUBDIRS:
        p = Path(build) / sub / name
        if p.is_file() and os.access(p, os.X_OK):
            return p
    return None


def default_build(targets, jobs):
    """The build folder when --build is not given: build/ if it has every executable in
    `targets` (a developer's full build), else build-benchmarks/, which run_all configures
    (Release, with the tests' support library that pce-accuracy needs) and in which it builds
    just `targets`. The README's quick start (bash .ci/demo) configures build/ without tests
    and benchmarks, so after it the benchmarks are built here, leaving build/ as it is."""
    targets = sorted(set(targets))
    main_build = ROOT / "build"
    if all(find_exe(main_build, t) for t in targets):
        return main_build
    own = ROOT / "build-benchmarks"
    missing = [t for t in targets if not find_exe(main_build, t)]
    log(f"{main_build} has no {', '.join(missing)}: building {', '.join(targets)} in {own}")
    if not (own / "CMakeCache.txt").exists():
        cmd = ["cmake", "-S", ROOT, "-B", own] + (["-G", "Ninja"] if shutil.which("ninja") else []) + [
            "-DCMAKE_BUILD_TYPE=Release", "-DPCE_BUILD_TESTS=ON", "-DPCE_BUILD_BENCHMARKS=ON", "-DPCE_BUILD_SIM=ON",
            "-DPCE_BUILD_EXAMPLES=OFF", "-DPCE_BUILD_PROBE=OFF"]
        if subprocess.run([str(c) for c in cmd]).returncode != 0:
            raise RuntimeError(f"configuring {own} failed: {' '.join(map(str, cmd))}")
    cmd = ["cmake", "--build", own, "--parallel", str(max(jobs, 1)), "--target"] + targets
    if subprocess.run([str(c) for c in cmd]).returncode != 0:
        raise RuntimeError(f"building in {own} failed: {' '.join(map(str, cmd))}")
    return own


def step_machine(ctx):
    def sh(cmd):
        try:
            return subprocess.run(cmd, shell=True, capture_output=True, text=True).stdout.strip()
        except OSError:
            return ""
    cpu = sh("lscpu | sed -n 's/^Model name:[ ]*//p' | head -1") or platform.processor()
    mem = sh("awk '/MemTotal/ {printf \"%.1f GiB\", $2/1048576}' /proc/meminfo")
    osr = sh(". /etc/os-release && echo $PRETTY_NAME")
    cache = {}
    cc = ctx.build / "CMakeCache.txt"
    if cc.exists():
        for line in cc.read_text().splitlines():
            m = re.match(r"^(CMAKE_BUILD_TYPE|CMAKE_CXX_COMPILER|CMAKE_CXX_FLAGS_RELEASE|CMAKE_CXX_FLAGS):\w+=(.*)$", line)
            if m:
                cache[m.group(1)] = m.group(2)
    compiler = sh(f"{cache.get('CMAKE_CXX_COMPILER', 'c++')} --version | head -1")
    eigen = sh("awk '/#define EIGEN_(WORLD|MAJOR|MINOR)_VERSION/ {printf \"%s.\", $3}' "
               "/usr/include/eigen3/Eigen/src/Core/util/Macros.h").rstrip(".")
    m = {
        "date_utc": datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC"),
        "cpu": cpu, "cores": os.cpu_count(), "memory": mem, "os": osr, "compiler": compiler,
        "build_type": cache.get("CMAKE_BUILD_TYPE", "?"),
        "flags": (cache.get("CMAKE_CXX_FLAGS", "") + " " + cache.get("CMAKE_CXX_FLAGS_RELEASE", "")).strip(),
        "eigen": eigen, "fcl": sh("pkg-config --modversion fcl"), "bullet": sh("pkg-config --modversion bullet-float64"),
        "commit": sh(f"git -C {ROOT} rev-parse --short HEAD"),
        "dirty": bool(sh(f"git -C {ROOT} status --porcelain --untracked-files=no")),
        "quick": ctx.quick,
    }
    (ctx.results / "machine.json").write_text(json.dumps(m, indent=1))
    return m


def step_pair_cost(ctx):
    cmd = [ctx.exe("pce-bench"), "--benchmark_format=json"]
    if ctx.quick:
        cmd += ["--benchmark_min_time=0.001", "--benchmark_filter=^(vertex_face|point_point)/"]
    else:
        cmd += ["--benchmark_repetitions=5", "--benchmark_enable_random_interleaving=true",
                "--benchmark_min_time=0.05", "--benchmark_display_aggregates_only=true"]
    p = run(cmd)
    (ctx.results / "pce_bench.json").write_text(p.stdout)
    (ctx.results / "pce_bench.log").write_text(p.stderr)
    data = json.loads(p.stdout)
    ns = {}
    for b in data["benchmarks"]:
        # The median of the repetitions (the single run in quick mode).
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
            continue
        name = b.get("run_name", b["name"])
        ns[name] = b["real_time"]
    rows = []
    for name, t in sorted(ns.items()):
        pair, quantity, scalar = name.split("/")
        rows.append({"pair": pair, "quantity": quantity, "scalar": scalar, "ns_per_pair": t})
    write_csv(ctx.results / "pce_bench.csv", rows)
    return {"ns": ns, "command": " ".join(["pce-bench"] + [str(c) for c in cmd[1:]])}


def step_accuracy(ctx):
    cmd = [ctx.exe("pce-accuracy"), "--out", ctx.results / "accuracy.json", "--csv", ctx.results / "accuracy.csv"]
    if ctx.quick:
        cmd.append("--quick")
    p = run(cmd)
    (ctx.results / "accuracy.log").write_text(p.stdout + p.stderr)
    data = json.loads((ctx.results / "accuracy.json").read_text())
    data["wall_s"] = p.wall_s
    data["command"] = "pce-accuracy" + (" --quick" if ctx.quick else "")
    return data


def step_broad_phase(ctx):
    cmd = [ctx.exe("pce-broad-phase-bench"), "--out", ctx.results / "broad_phase.json"]
    if ctx.quick:
        cmd.append("--quick")
    p = run(cmd)
    (ctx.results / "broad_phase.log").write_text(p.stdout + p.stderr)
    data = json.loads((ctx.results / "broad_phase.json").read_text())
    write_csv(ctx.results / "broad_phase.csv", data["rows"])
    data["command"] = "pce-broad-phase-bench" + (" --quick" if ctx.quick else "")
    return data


def make_scene(ctx, name, base, changes):
    """Writes a variant of a shipped scene into the results folder; returns its path. Friction is
    taken out: these runs compare the contact Hessian's strategies, tolerances and threads, and
    the friction potential is the same whatever the strategy (its cost: the friction step)."""
    scene = json.loads((ROOT / "examples" / "scenes" / f"{base}.json").read_text())
    for effect in scene.get("effects", []):
        effect.pop("friction", None)
    if "frames" in changes:
        scene["frames"] = changes["frames"]
    if "resolution" in changes:
        for m in scene["meshes"]:
            g = m.get("generator", {})
            if g.get("type") == "grid":
                g["nx"] = g["ny"] = changes["resolution"]
    if "max_iterations" in changes:
        scene.setdefault("solver", {})["max_iterations"] = changes["max_iterations"]
    scene["output_every"] = 1000000
    d = ctx.results / "scenes"
    d.mkdir(exist_ok=True)
    path = d / f"{name}.json"
    path.write_text(json.dumps(scene, indent=1))
    return path


def run_sim(ctx, scene_path, tag, strategy, mode, tol, threads=1):
    out = ctx.results / "runs" / tag
    if out.exists():
        shutil.rmtree(out)
    cmd = [ctx.exe("pce-sim"), scene_path, "--out", out, "--no-frames", "--threads", str(threads), "--hessian", strategy]
    if mode == "single":
        cmd.append("--single-solve")
    if tol is not None:
        cmd += ["--tolerance", repr(tol)]
    p = run(cmd, check=False)
    summary_path = out / "summary.json"
    if not summary_path.exists():
        raise RuntimeError(f"pce-sim wrote no summary for {tag} (exit {p.returncode}):\n{p.stderr[-1500:]}")
    summary = json.loads(summary_path.read_text())
    stats = json.loads((out / "stats.json").read_text())
    n = max(len(stats), 1)
    r = {
        "tag": tag, "strategy": strategy, "mode": mode, "tolerance": tol, "threads": threads,
        "frames": summary["frames_done"], "vertices": summary["vertices"],
        "ms_per_frame": summary["mean_ms_per_frame"], "newton_per_frame": summary["mean_newton_iterations"],
        "residual_median": median([s["residual"] for s in stats]),
        "residual_max": max([s["residual"] for s in stats if s["residual"] is not None] or [float("nan")]),
        "peak_mib": summary["peak_memory_mib"],
        "line_search_failures": sum(s["line_search_failures"] for s in stats),
        "iteration_caps": sum(1 for s in stats if s["hit_iteration_cap"]),
        "frames_with_intersections": sum(1 for s in stats if s["intersecting_triangle_pairs"] > 0),
        "failure": summary["failure"], "exit_code": p.returncode, "wall_s": p.wall_s,
    }
    for k in STAGES:
        r[k] = sum(s[k] for s in stats) / n
    r["other_ms"] = max(r["ms_per_frame"] - sum(r[k] for k in STAGES), 0.0)
    last = out / f"frame_{summary['frames_done']:04d}.obj"
    r["final_obj"] = str(last) if last.exists() else None
    return r


def step_threads(ctx):
    """pce-sim at 1 and 2 threads (the machine's cores), one at a time on an idle machine."""
    name, (base, changes) = ("twist", ("twist", {"frames": 4})) if ctx.quick else \
        ("hammock_coarse", ("hammock", {"frames": 25, "resolution": 22}))
    scene = make_scene(ctx, f"threads_{name}", base, changes)
    rows = []
    counts = [1, 2] if (os.cpu_count() or 1) >= 2 else [1]
    for t in counts:
        r = run_sim(ctx, scene, f"threads_{name}_{t}", "analytic", "newton", None, threads=t)
        r["scene"] = name
        rows.append(r)
    base_row = rows[0]
    for r in rows:
        for k in ["ms_per_frame"] + STAGES:
            r["speedup_" + k] = base_row[k] / r[k] if r[k] > 0 else float("nan")
    write_csv(ctx.results / "threads.csv", rows, ["scene", "threads", "frames", "ms_per_frame", "newton_per_frame"] +
              STAGES + ["other_ms"] + ["speedup_" + k for k in ["ms_per_frame"] + STAGES])
    return {"scene": name, "changes": changes, "rows": rows}


def step_scenes(ctx):
    plan = scene_plan(ctx.quick)
    tasks = []  # (scene name, scene path, strategy, mode, tol, kind)
    for name, (base, changes) in plan.items():
        path = make_scene(ctx, name, base, changes)
        ref_path = make_scene(ctx, name + "_reference", base, dict(changes, max_iterations=300))
        for (s, mode, tol) in scene_configs(ctx.quick):
            tasks.append((name, path, s, mode, tol, "config"))
        tasks.append((name, ref_path, *REFERENCE, "reference"))
        if not ctx.quick:
            tasks.append((name, ref_path, *NOISE_FLOOR, "noise_floor"))
    if not ctx.quick:
        base, changes = HEADLINE_SCENE
        path = make_scene(ctx, "hammock", base, changes)
        for s in STRATEGIES:
            tasks.append(("hammock", path, s, "newton", None, "config"))

    def one(t):
        name, path, s, mode, tol, kind = t
        tag = f"{name}_{kind}_{s}_{mode}_{'default' if tol is None else f'{tol:g}'}"
        r = run_sim(ctx, path, tag, s, mode, tol)
        r.update({"scene": name, "kind": kind})
        log(f"  {tag}: {r['ms_per_frame']:.0f} ms/frame, {r['newton_per_frame']:.2f} it/frame"
            + (f", FAILED: {r['failure']}" if r["failure"] else ""))
        return r

    # Longest first (hammock, then the Newton runs at tight tolerances) so two workers balance.
    weight = {"hammock": 100, "hammock_coarse": 20, "drape": 6, "twist": 5, "strands": 4}
    tasks.sort(key=lambda t: -(weight.get(t[0], 1) * (3 if t[5] != "config" else 1) *
                               (1 if t[3] == "single" else 2 + (t[4] is not None and t[4] < 1e-2))))
    with concurrent.futures.ThreadPoolExecutor(max_workers=ctx.jobs) as pool:
        rows = list(pool.map(one, tasks))
    # Deviation of every run's final state from its scene's reference.
    refs = {r["scene"]: r for r in rows if r["kind"] == "reference"}
    for r in rows:
        ref = refs.get(r["scene"])
        r["dev_rms"] = r["dev_max"] = None
        if ref and ref["final_obj"] and r["final_obj"] and r["frames"] == ref["frames"]:
            r["dev_rms"], r["dev_max"] = deviation(read_obj_vertices(r["final_obj"]), read_obj_vertices(ref["final_obj"]))
    columns = ["scene", "kind", "strategy", "mode", "tolerance", "frames", "vertices", "ms_per_frame",
               "newton_per_frame", "residual_median", "residual_max", "peak_mib", "line_search_failures",
               "iteration_caps", "frames_with_intersections", "dev_rms", "dev_max", "failure"] + STAGES + ["other_ms"]
    write_csv(ctx.results / "scenes.csv", rows, columns)
    return {"plan": {k: {"base": b, **c} for k, (b, c) in plan.items()},
            "headline": None if ctx.quick else {"base": HEADLINE_SCENE[0], **HEADLINE_SCENE[1]},
            "rows": rows}


def build_before(ctx, rev):
    """pce-sim of commit `rev`, built once from `git archive` in build-before/<commit> (sources
    and build side by side; reused when it is there). Only pce::sim and pce-sim are built."""
    p = run(["git", "-C", ROOT, "rev-parse", "--verify", "--short", rev + "^{commit}"], check=False)
    if p.returncode != 0:
        raise ValueError(f"--before {rev}: not a commit of {ROOT}")
    commit = p.stdout.strip()
    top = ROOT / "build-before" / commit
    exe = find_exe(top / "build", "pce-sim")
    if exe:
        return commit, exe
    src = top / "src"
    if src.exists():
        shutil.rmtree(src)
    src.mkdir(parents=True)
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", "--format=tar", commit], stdout=subprocess.PIPE)
    if archive.returncode != 0:
        raise RuntimeError(f"git archive {commit} failed")
    subprocess.run(["tar", "-x", "-C", str(src)], input=archive.stdout, check=True)
    log(f"building pce-sim of {commit} in {top / 'build'}")
    run(["cmake", "-S", src, "-B", top / "build"] + (["-G", "Ninja"] if shutil.which("ninja") else []) + [
        "-DCMAKE_BUILD_TYPE=Release", "-DPCE_BUILD_SIM=ON", "-DPCE_BUILD_TESTS=OFF", "-DPCE_BUILD_BENCHMARKS=OFF",
        "-DPCE_BUILD_EXAMPLES=OFF", "-DPCE_BUILD_PROBE=OFF"])
    run(["cmake", "--build", top / "build", "--parallel", str(max(ctx.jobs, 1)), "--target", "pce-sim"])
    exe = find_exe(top / "build", "pce-sim")
    if not exe:
        raise RuntimeError(f"building {commit} made no pce-sim in {top / 'build'}")
    return commit, exe


def hammock_row(label, exe, directory):
    """One run's row: compare_runs.row (ms per frame, stages, iterations, queries, caps, line-search
    failures, frames with intersections) and the linear solver's counters per frame."""
    records = compare_runs.load(directory)
    r = compare_runs.row(label, records)
    n = max(len(records), 1)
    for key in ("factorizations", "analyses", "cg_iterations", "factorize_ms", "analyze_ms"):
        # None (n/a) for a version that did not count it
        r[key] = sum(rec["counters"].get(key, 0) for rec in records) / n if any(
            key in rec["counters"] for rec in records) else None
    r["broad_phase_share"] = r["broad_phase_ms"] / r["ms_per_frame"] if r["ms_per_frame"] else float("nan")
    r["exe"] = str(exe)
    return r


def step_hammock(ctx):
    """The shipped hammock without friction (hammock_frictionless.json: older pce-sim versions
    reject the friction key, so before and after run the same scene), frames 1-120, one thread,
    full Newton and single solve, every run alone; with --before, REV's pce-sim the same way,
    each mode's two runs one after the other. --quick: twist, 10 frames."""
    scene = ROOT / "examples" / "scenes" / ("twist.json" if ctx.quick else "hammock_frictionless.json")
    frames = 10 if ctx.quick else 120
    builds = []
    if ctx.before:
        commit, exe = build_before(ctx, ctx.before)
        builds.append((f"before ({commit})", commit, exe))
    builds.append(("this build", "this build", ctx.exe("pce-sim")))
    rows = []
    for mode in ("newton", "single"):
        for label, tag, exe in builds:
            out = ctx.results / "runs" / f"hammock_{tag.replace(' ', '_')}_{mode}"
            if out.exists():
                shutil.rmtree(out)
            cmd = [exe, scene, "--frames", str(frames), "--no-frames", "--threads", "1", "--out", out]
            if mode == "single":
                cmd.append("--single-solve")
            log(f"  hammock: {label}, {mode}")
            run(cmd)
            r = hammock_row(label, exe, out)
            r.update({"mode": mode, "command": " ".join(str(c) for c in cmd[1:]).replace(str(ROOT) + "/", "")})
            rows.append(r)
    for r in rows:
        first = next(x for x in rows if x["mode"] == r["mode"])
        r["ratio"] = r["ms_per_frame"] / first["ms_per_frame"] if first["ms_per_frame"] else float("nan")
    columns = ["run", "mode", "frames", "ms_per_frame", "ratio", "newton_per_frame", "queries_per_frame_per_effect",
               "factorizations", "analyses", "cg_iterations", "broad_phase_share"] + compare_runs.STAGES + [
               "factorize_ms", "analyze_ms", "iteration_caps", "line_search_failures", "frames_with_intersections"]
    write_csv(ctx.results / "hammock.csv", rows, columns)
    return {"scene": scene.name, "frames": frames, "before": ctx.before, "rows": rows}


def friction_per_frame(records):
    """Friction ms, contacts and sticking contacts per frame: each the sum over the contact kinds'
    *_friction_<what> counters (0 where a record has none: no friction on that kind, or a
    pce-sim without friction), averaged over the records."""
    n = max(len(records), 1)
    out = {}
    for what in ("ms", "contacts", "sticking"):
        out[f"friction_{what}_per_frame"] = sum(rec.get("counters", {}).get(f"{k}_friction_{what}") or 0
                                                for rec in records for k in FRICTION_KINDS) / n
    return out


def step_friction(ctx):
    """Friction's cost on the hammock: hammock_frictionless.json, then hammock.json (the same
    scene with friction), frames 1-120 (--quick: 3), one thread, full Newton, each run alone;
    with --before, REV's pce-sim on hammock.json between the two (its stopping rule against
    this build's, one run after the other)."""
    frames = 3 if ctx.quick else 120
    runs = [(label, name, "this build", ctx.exe("pce-sim")) for label, name in FRICTION_SCENES]
    if ctx.before:
        commit, exe = build_before(ctx, ctx.before)
        runs.insert(1, (f"with friction, before ({commit})", FRICTION_SCENES[1][1], commit, exe))
    rows = []
    for label, name, build, exe in runs:
        scene = ROOT / "examples" / "scenes" / name
        out = ctx.results / "runs" / f"friction_{Path(name).stem}_{build.replace(' ', '_')}"
        if out.exists():
            shutil.rmtree(out)
        cmd = [exe, scene, "--frames", str(frames), "--no-frames", "--threads", "1", "--out", out]
        log(f"  friction: {name} ({build})")
        run(cmd)
        records = compare_runs.load(out)
        r = compare_runs.row(label, records)
        r.update(friction_per_frame(records))
        r.update({"scene": name, "build": build,
                  "command": " ".join(str(c) for c in cmd[1:]).replace(str(ROOT) + "/", "")})
        rows.append(r)
    first = rows[0]
    for r in rows:  # with friction / without, per frame
        r["ms_ratio"] = r["ms_per_frame"] / first["ms_per_frame"] if first["ms_per_frame"] else float("nan")
        r["newton_ratio"] = (r["newton_per_frame"] / first["newton_per_frame"] if first["newton_per_frame"]
                             else float("nan"))
    columns = ["run", "scene", "build", "frames", "ms_per_frame", "ms_ratio", "newton_per_frame", "newton_ratio",
               "friction_ms_per_frame", "friction_contacts_per_frame", "friction_sticking_per_frame",
               "line_search_failures", "iteration_caps", "frames_with_intersections"] + compare_runs.STAGES
    write_csv(ctx.results / "friction.csv", rows, columns)
    return {"frames": frames, "scenes": [name for _, name in FRICTION_SCENES], "before": ctx.before, "rows": rows}


def scale_plan(quick):
    """The scale step's plan: scale_ladder.plan_groups('quick' or 'full'), where the levels, modes
    (MODE[:N][/LINEAR][+mu0]), thread counts, frames and windows are set (one place: the
    NEWTON_* / LINEAR_LEVELS / DEFAULT_LINEAR / BLOCK_* constants there). Returns {name, groups,
    and levels, modes, threads: every group's together}."""
    name = "quick" if quick else "full"
    groups = scale_ladder.plan_groups(name)
    return {"name": name, "groups": groups,
            "levels": list(dict.fromkeys(lv for g in groups for lv in g["levels"])),
            "modes": list(dict.fromkeys(m for g in groups for m in g["modes"])),
            "threads": sorted({t for g in groups for t in g["threads"]})}


def step_scale(ctx):
    """The scale ladder (benchmarks/scale_ladder.py): its generated cloth drop at each level, mode
    variant and thread count of the plan, one run at a time; scenes into scenes/scale_<level>[_<variant>].json,
    runs into runs/scale_*, scale_ladder.json/.csv/.md into the results folder. A mode this pce-sim
    cannot select is reported as not run; a failed run (a linear solver pce-sim rejects, too) is
    reported, and fails the step in quick mode."""
    plan = scale_plan(ctx.quick)
    log(f"  scale: plan {plan['name']}: levels {', '.join(plan['levels'])}, modes {', '.join(plan['modes'])}, "
        f"threads {', '.join(map(str, plan['threads']))}")
    res = scale_ladder.run_ladder(ctx.exe("pce-sim"), ctx.results, note=ctx.note, groups=plan["groups"])
    failed = [r for r in res["runs"] if r.get("status") not in ("ok", "not run")]
    if failed and ctx.quick:
        raise RuntimeError("scale runs failed: " + "; ".join(f"{r['tag']}: {r.get('reason')}" for r in failed))
    return dict(res, plan=plan)


def step_block_accuracy(ctx):
    """Block descent's accuracy against its time (benchmarks/block_accuracy.py): its plan 'full'
    (--quick: 'quick'), one run at a time; scenes into scenes/block_accuracy_*.json, runs into
    runs/block_accuracy/, block_accuracy.json/.md into the results folder. A configuration this
    pce-sim cannot select is reported as not run; in quick mode a failed run, or a reference that
    did not finish, fails the step."""
    name = "quick" if ctx.quick else "full"
    plan = dict(block_accuracy.PLANS[name])
    configs, skipped = block_accuracy.plan_configs(plan)
    log(f"  block_accuracy: plan {name}: scenes {', '.join(plan['scenes'])}, {len(configs)} configurations each"
        + (f", {len(skipped)} skipped" if skipped else ""))
    res = block_accuracy.run_grid(ctx.exe("pce-sim"), ctx.results, plan, note=ctx.note, plan_name=name)
    failed = [r for r in res["rows"] if r["status"] == "failed"]
    no_ref = [s["key"] for s in res["scenes"]
              if not any(r["scene"] == s["key"] and r["reference"] and r["status"] == "ok" for r in res["rows"])]
    if ctx.quick and (failed or no_ref):
        raise RuntimeError("block_accuracy: " + "; ".join([f"{r['scene']} {r['label']}: {r['reason']}" for r in failed]
                                                          + [f"{k}: the reference did not finish" for k in no_ref]))
    return res


def scale_plan_sentence(plan):
    """The plan's groups in words, from the plan itself: '`newton/direct` at 8k, 32k, 1 and 2
    threads, 12 frames, means over frames 5–12; ...'."""
    out = []
    for g in plan["groups"]:
        w = g.get("window")
        frames = (f"{g['frames']} frames" if g.get("frames") else
                  "each level's frames (" + ", ".join(f"{lv} {scale_ladder.DEFAULT_FRAMES.get(lv, 20)}"
                                                      for lv in g["levels"]) + ")")
        out.append(f"{', '.join(f'`{m}`' for m in g['modes'])} at {', '.join(g['levels'])}, "
                   f"{' and '.join(map(str, g['threads']))} thread{'s' if g['threads'] != [1] else ''}, {frames}, "
                   + (f"means over frames {w[0]}–{w[1]}" if w else "means over all frames"))
    return "; ".join(out)


def window_contact_sentence(runs):
    """Whether the windowed runs' obstacle contact began before their windows (the runs' own
    first_obstacle_contact_frame), in words; '' without windowed runs."""
    win = [r for r in runs if r.get("window") and r.get("frames_done")]
    if not win:
        return ""
    before = [r for r in win if r.get("first_obstacle_contact_frame") and
              r["first_obstacle_contact_frame"] < r["window"][0]]
    if len(before) == len(win):
        return " In every windowed run the obstacle contact began before its window (the *contact* column)."
    return (f" In {len(win) - len(before)} of the {len(win)} windowed runs the obstacle contact did not begin before "
            "the window (the *contact* column).")


def write_scale_section(A, scale):
    """Section 8: the scale ladder, from step_scale (not measured when its results are missing)."""
    A("## 8. Scale ladder\n")
    if not scale or not scale.get("runs"):
        A("Not measured: the results folder has no `step_scale.json` (`benchmarks/run_all --steps scale` measures "
          "it).\n")
        return
    plan = scale["plan"]
    intro = ("How the cost of a frame grows with the mesh: `benchmarks/scale_ladder.py` (its docstring has the "
             "scene) runs one generated scene, a 1 m cloth of N × N quads dropped onto a sphere and a floor with self "
             "and obstacle contact (area weighted, contact distance half an edge) and friction, at several sizes, "
             "each run alone.")
    if plan.get("groups"):
        has_linear = any("/" in m for m in plan["modes"])
        has_mu0 = any("+mu0" in m for m in plan["modes"])
        A(intro + " The runs: " + scale_plan_sentence(plan) + ". A label is the mode (`MODE[:N]`)"
          + (", then `/LINEAR`, the scene's `solver.linear_solver` (docs/simulation.md §5.3)" if has_linear else "")
          + (", then `+mu0`: the same scene with no friction key on any contact (pce-sim builds no friction)"
             if has_mu0 else "")
          + "; growth exponents and speed-ups are per label, so each linear solver is fitted on its own"
          + ("; *Friction's cost in iterations* divides each run with friction by its `+mu0` twin" if has_mu0 else "")
          + "." + (" A window (frames A–B) leaves the frames before A and after B out of every mean of its runs; "
                   "*max ∩* and *contact* still cover every frame." + window_contact_sentence(scale["runs"])
                   if any(g.get("window") for g in plan["groups"]) else "")
          + " `benchmarks/scale_ladder.py run --pce-sim build/src/sim/pce-sim --results DIR --plan %s` repeats it "
            "(`scale_ladder.csv` has every run; the plan is `plan_groups` in `scale_ladder.py`).\n" % plan["name"])
    else:  # a step_scale.json from before the plan had groups
        A(intro + " `benchmarks/scale_ladder.py run --pce-sim build/src/sim/pce-sim --results DIR --levels %s --modes %s "
          "--threads %s` repeats it (`scale_ladder.csv` has every run).\n"
          % (",".join(plan["levels"]), ",".join(plan["modes"]), ",".join(map(str, plan["threads"]))))
    A(scale_ladder.markdown(scale, title="", sub="###").lstrip("\n"))
    if scale.get("agreement"):
        A("### Last frames against Newton's\n")
        A(("The frames block descent computes are not Newton's: its sweeps stop before each step's minimiser (a "
           "stiff sheet's bulk motion converges slowest under Gauss–Seidel) and the difference carries from step "
           "to step, so the sheet lands and folds elsewhere. "
           if any(g["mode"].startswith("block_descent") for g in scale["agreement"]) else "") +
          "RMS over vertices of the distance between each run's last frame and a Newton run's (same level, "
          "friction and frames; the reference is Newton with the default or direct linear solver where the level "
          "has one, 1 thread first), and the lowest point of each:\n")
        A("| level | mode | threads | reference | frame | RMS to reference (mm) | lowest z (mm) | "
          "reference's lowest z (mm) |")
        A("|---|---|---:|---|---:|---:|---:|---:|")
        for g in scale["agreement"]:
            ref = g.get("reference", "newton") + (f", {g['reference_threads']} thread(s)"
                                                  if g.get("reference_threads") else "")
            A(f"| {g['level']} | {g['mode']} | {g['threads']} | {ref} | {g['frame']} | "
              f"{1000 * g['rms_to_newton_m']:.1f} | {1000 * g['lowest_z_m']:.1f} | {1000 * g['newton_lowest_z_m']:.1f} |")
        A("")


BLOCK_ACCURACY_HEADING = "### Block descent: accuracy against time"


def numbers_sentence(xs):
    """[1, 2, 5] -> '{1, 2, 5}'."""
    return "{" + ", ".join(f"{x:g}" if isinstance(x, float) else str(x) for x in xs) + "}"


def write_block_accuracy_section(A, res, img):
    """Section 8's subsection: block descent's grid against Newton, from step_block_accuracy (not
    measured when its results are missing); a table and a Pareto plot per scene."""
    A(BLOCK_ACCURACY_HEADING + "\n")
    if not res or not res.get("rows"):
        A("Not measured: the results folder has no `step_block_accuracy.json` (`benchmarks/run_all --steps "
          "block_accuracy` measures it).\n")
        return
    st = res["settings"]
    plan = (res.get("plan") or "full").split(" ")[0]
    tols = [t for t in st["newton"] if t != st["reference"]]
    if st.get("configs"):
        grid = "block descent at " + ", ".join(f"`{c}`" for c in st["configs"])
    else:
        grid = ("block descent over the grid S ∈ %s substeps of dt/S per frame × N ∈ %s sweeps per substep, %s"
                % (numbers_sentence(st["substeps"]), numbers_sentence(st["sweeps"]),
                   "without and with Chebyshev acceleration" if len(st["accelerations"]) > 1 else
                   "with Chebyshev acceleration" if st["accelerations"] == ["chebyshev"] else "without acceleration")
                + (", except S × N above %d sweeps per frame (%s)" % (st["max_sweeps_per_frame"],
                                                                         ", ".join(f"`{x}`" for x in res["skipped"]))
                   if res.get("skipped") else "")
                + "".join("; on %s only S × N up to %d (%s skipped)" % (s["key"], s["cap"], ", ".join(f"`{x}`" for x in s["skipped"]))
                          for s in res.get("scenes", []) if s.get("skipped")))
    rho = (f"Chebyshev's ρ: `solver.chebyshev_rho` {st['chebyshev_rho']:g}" if st.get("chebyshev_rho") is not None
           else "Chebyshev's ρ: the scene's `solver.chebyshev_rho`, pce-sim's default where it has none")
    A("What block descent's speed costs in accuracy, and what substeps, sweeps and Chebyshev acceleration buy "
      "back: `benchmarks/block_accuracy.py --pce-sim build/src/sim/pce-sim --results DIR --plan %s` regenerates "
      "it (`benchmarks/run_all --steps block_accuracy%s` runs the same and rewrites this page; `block_accuracy.py "
      "--dry-run` prints the commands). Per scene, one run at a time, %d thread%s: Newton at tolerance %g (the "
      "reference)%s, and %s (`--mode block_descent --iterations N --substeps S --acceleration none|chebyshev`; "
      "%s). A row's *sweeps/frame* is block descent's `sweeps` summed over a frame's substeps (Newton's rows: "
      "its iterations); *RMS to ref.* is the RMS over every vertex of the distance to the reference's position at "
      "that frame; *lowest z* is the lowest vertex at the last measured frame and *rel. error* its |z − z_ref| / "
      "|z_ref|; *max ∩ pairs* the most intersecting triangle pairs of any frame. A row is on the *Pareto* front "
      "when no other row of its scene has both a lower ms/frame and a lower RMS at the last measured frame (the "
      "reference, RMS 0, is one of the rows). Each plot has ms/frame against that RMS, log–log: block descent's "
      "points labelled S×N, circles without acceleration and triangles with Chebyshev's, colour by S; %sthe "
      "reference's ms/frame as the dashed line; the front joined in red. "
      "Measured at commit %s, %s, %s cores (`block_accuracy.json` has every number and command).\n"
      % (plan, " --quick" if plan == "quick" else "", res["threads"], "s" if res["threads"] != 1 else "",
         st["reference"], (", Newton at " + ", ".join(f"{t:g}" for t in tols)) if tols else "", grid, rho,
         "Newton at its other tolerance%s as squares; " % ("s" if len(tols) > 1 else "") if tols else "",
         res.get("commit") or "?", res.get("date_utc", "?"), res.get("cores", "?")))
    for s in res["scenes"]:
        own = s["kind"] == "file" and s.get("file") and s["file_run"] == os.path.relpath(s["file"], ROOT)
        A(f"**{s['key']}**: {block_accuracy.scene_title(s)}" + ("" if own else f" (scene `{s['file_run']}`)") + "\n")
        A(f"![{s['key']}: block descent's accuracy against time]({img}/block_accuracy_{s['key']}.png)\n")
        header, rows = block_accuracy.table_rows(res, s)
        A(md_table(header, rows, block_accuracy.table_align(len(header))) + "\n")
        notes = [r for r in res["rows"] if r["scene"] == s["key"] and (r["status"] != "ok" or r.get("reason"))]
        for r in notes:
            A(f"- {r['label']}: {r['status']}" + (f": {r['reason']}" if r.get("reason") else ""))
        if notes:
            A("")
    if not res.get("complete", True):
        A("The grid stopped before its last run: the rows above are the runs it finished.\n")


# The compile_time step: what including pce costs a user's build.
COMPILE_EXAMPLES = ["basic_energies", "custom_penalty", "newton_assembly", "strategy_per_pair", "closest_features"]
COMPILE_FLOOR = "#include <pce/pce.hpp> alone"  # the floor's file label (an empty main written to a temporary file)
PRECOMPILED = "pce::precompiled"  # the variant compiled with -DPCE_PRECOMPILED


def compile_jobs(quick):
    """(file, variant, optimisation, extra flags) of every compilation, in the table's order;
    file is relative to the repository, or COMPILE_FLOOR. --quick: the three that take seconds."""
    rt, tp = "benchmarks/compile_time/minimal_runtime.cpp", "benchmarks/compile_time/minimal_template.cpp"
    jobs = [(COMPILE_FLOOR, "header-only", "-O2", []), (tp, "header-only", "-O2", [])]
    if not quick:
        jobs += [(rt, "header-only", "-O2", []), (rt, "header-only", "-O0", [])]
    jobs.append((rt, PRECOMPILED, "-O2", ["-DPCE_PRECOMPILED"]))
    if quick:
        return jobs
    for ex in COMPILE_EXAMPLES:
        f = f"examples/{ex}/main.cpp"
        jobs += [(f, "header-only", "-O2", []), (f, PRECOMPILED, "-O2", ["-DPCE_PRECOMPILED"])]
    # pce::sim links pce::precompiled, so its users always have the macro: no header-only row.
    jobs.append(("examples/sim_from_cpp/main.cpp", PRECOMPILED, "-O2",
                 ["-DPCE_PRECOMPILED", "-I", "src/sim/include", "-fopenmp"]))
    return jobs


def cmake_cache(build):
    """The build folder's CMakeCache.txt as a dict ({} without one)."""
    out = {}
    cc = Path(build) / "CMakeCache.txt"
    if cc.exists():
        for line in cc.read_text().splitlines():
            m = re.match(r"^([A-Za-z0-9_.+-]+):\w+=(.*)$", line)
            if m:
                out[m.group(1)] = m.group(2)
    return out


def eigen_include(eigen3_dir):
    """Eigen's include folder: the one Eigen3Config.cmake in `eigen3_dir` (CMake's Eigen3_DIR)
    names, else an include/eigen3 above it, else /usr/include/eigen3."""
    candidates = []
    if eigen3_dir and Path(eigen3_dir).is_dir():
        d = Path(eigen3_dir).resolve()
        cfg = d / "Eigen3Config.cmake"
        if cfg.exists():
            prefix = (d / ".." / ".." / "..").resolve()
            for m in re.finditer(r'set\s*\(\s*EIGEN3_INCLUDE_DIRS?\s+"([^"]+)"', cfg.read_text()):
                candidates.append(Path(m.group(1).replace("${PACKAGE_PREFIX_DIR}", str(prefix))))
        candidates += [p / "include" / "eigen3" for p in d.parents]
    candidates.append(Path("/usr/include/eigen3"))
    for c in candidates:
        if (c / "Eigen" / "Core").is_file():
            return c.resolve()
    raise RuntimeError(f"Eigen's include folder not found (Eigen3_DIR {eigen3_dir or 'not set'}, "
                       "no /usr/include/eigen3)")


def timed_compile(cmd, log_path):
    """One compilation: wall s, CPU s (user + system of the driver and the compiler it runs) and
    peak resident MiB, from wait4; raises with the compiler's messages when it fails."""
    with open(log_path, "w") as err:
        t0 = time.monotonic()
        p = subprocess.Popen([str(c) for c in cmd], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=err,
                             cwd=ROOT)
        _, status, ru = os.wait4(p.pid, 0)
        wall = time.monotonic() - t0
    p.returncode = os.waitstatus_to_exitcode(status)  # reaped here: Popen must not wait again
    if p.returncode != 0:
        tail = "\n".join(Path(log_path).read_text().strip().splitlines()[-15:])
        raise RuntimeError(f"compilation failed ({p.returncode}): {' '.join(map(str, cmd))}\n{tail}")
    return wall, ru.ru_utime + ru.ru_stime, ru.ru_maxrss / 1024


def step_compile_time(ctx):
    """Compile time of a user's file: every compile_jobs entry, one compilation at a time, in
    REPEATS rounds over all of them (so a change in the machine's load spreads over every row);
    per row the median wall time, the median CPU time and the largest peak memory."""
    cache = cmake_cache(ctx.build)
    cxx = cache.get("CMAKE_CXX_COMPILER") or shutil.which("c++") or "c++"
    eigen = eigen_include(cache.get("Eigen3_DIR"))
    version = run([cxx, "--version"]).stdout.strip().splitlines()[0]
    repeats = 1 if ctx.quick else 3
    jobs = compile_jobs(ctx.quick)
    times = {i: [] for i in range(len(jobs))}
    load_before = os.getloadavg()
    with tempfile.TemporaryDirectory(prefix="pce_compile_time_") as tmp:
        floor = Path(tmp) / "pce_hpp_only.cpp"
        floor.write_text("#include <pce/pce.hpp>\n\nint main() { return 0; }\n")
        for rnd in range(repeats):
            for i, (f, variant, opt, extra) in enumerate(jobs):
                src = floor if f == COMPILE_FLOOR else f
                cmd = [cxx, "-std=c++17", opt, "-c", src, "-o", "/dev/null", "-I", "include", "-I", eigen] + extra
                wall, cpu, mib = timed_compile(cmd, Path(tmp) / "stderr.txt")
                times[i].append((wall, cpu, mib))
                log(f"  compile {rnd + 1}/{repeats}: {f} {variant} {opt}: {wall:.1f} s")
    load_after = os.getloadavg()
    rows = []
    for i, (f, variant, opt, extra) in enumerate(jobs):
        ts = times[i]
        rows.append({"file": f, "variant": variant, "optimisation": opt,
                     "flags": " ".join(["-std=c++17", opt, "-c", "FILE" if f == COMPILE_FLOOR else f, "-o", "/dev/null",
                                        "-I", "include", "-I", str(eigen)] + extra),
                     "seconds": round(median([t[0] for t in ts]), 3),
                     "cpu_seconds": round(median([t[1] for t in ts]), 3), "peak_mib": round(max(t[2] for t in ts), 1),
                     "repeats": len(ts), "all_seconds": [round(t[0], 3) for t in ts]})
    write_csv(ctx.results / "compile_time.csv", rows,
              ["file", "variant", "optimisation", "flags", "seconds", "cpu_seconds", "peak_mib", "repeats"])

    def sh(cmd):
        return subprocess.run(cmd, shell=True, capture_output=True, text=True).stdout.strip()
    out = {
        "compiler": version, "compiler_path": str(cxx), "eigen_include": str(eigen), "repeats": repeats,
        "command": f"{Path(str(cxx)).name} -std=c++17 -O2 -c FILE -o /dev/null -I include -I {eigen} "
                   "[-DPCE_PRECOMPILED]",
        "date_utc": datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC"),
        "commit": sh(f"git -C {ROOT} rev-parse --short HEAD"),
        "dirty": bool(sh(f"git -C {ROOT} status --porcelain --untracked-files=no")),
        "cpu": sh("lscpu | sed -n 's/^Model name:[ ]*//p' | head -1") or platform.processor(),
        "cores": os.cpu_count(), "load_average_before": list(load_before), "load_average_after": list(load_after),
        "note": ctx.note or "", "quick": ctx.quick, "rows": rows,
    }
    (ctx.results / "compile_time.json").write_text(json.dumps(out, indent=1))
    return out


def write_friction_section(A, friction):
    """Section 6: friction's cost on the hammock, from step_friction (not measured when its
    results are missing)."""
    A("## 6. Friction's cost on the hammock\n")
    if not friction or not friction.get("rows"):
        A("Not measured: the results folder has no `step_friction.json` "
          "(`benchmarks/run_all --steps friction` measures it).\n")
        return
    rows = friction["rows"]
    A("`pce-sim examples/scenes/SCENE --frames %d --no-frames --threads 1` (full Newton, `analytic`, the scene's "
      "tolerance) with SCENE `%s`, then `%s` (the same scene with friction on its two self-contact effects), "
      "each run alone on the machine. Per frame: wall time, Newton iterations, the time spent freezing the friction "
      "contacts and evaluating their potential (part of the frame's time) and the contacts frozen with "
      "friction for the step's last solve, each summed over the vertex-face, edge-edge and obstacle contacts "
      "(`stats.jsonl` counters `*_friction_ms` and `*_friction_contacts`, 0 without friction); then line-search "
      "failures, iteration caps and frames with intersecting triangle pairs over the run "
      "(`benchmarks/results/friction.csv`).\n"
      % (friction["frames"], rows[0]["scene"], rows[-1]["scene"]))
    before = [r for r in rows if r.get("build", "this build") != "this build"]
    if before:
        A("The row *before* is commit %s's `pce-sim` on `%s` (`benchmarks/run_all --steps friction --before %s`), run "
          "right before this build's on the same scene: its Newton iterations stopped at the first direction below the "
          "tolerance, which static friction's stiff spring made small where a contact had to slide; this build's go on "
          "while the model loads a contact beyond Coulomb's bound (`docs/simulation.md` §5.2).\n"
          % (before[0]["build"], before[0]["scene"], friction.get("before") or before[0]["build"]))
    A(md_table(["scene", "build", "ms/frame", "Newton it/frame", "friction ms/frame", "friction contacts/frame",
                "sticking/frame", "ls failures", "caps", "intersecting frames"],
               [[f"`{r['scene']}`", r.get("build", "this build"), fmt(r["ms_per_frame"]), fmt(r["newton_per_frame"]),
                 fmt(r["friction_ms_per_frame"]), fmt(r["friction_contacts_per_frame"]),
                 fmt(r.get("friction_sticking_per_frame", float("nan"))), r["line_search_failures"],
                 r["iteration_caps"], r["frames_with_intersections"]] for r in rows]) + "\n")
    if before:
        a, b = before[0], rows[-1]
        A("This build's stopping rule costs %s× the time per frame of %s's (%s ms against %s ms) and %s× the Newton "
          "iterations (%s against %s); the contacts counted sticking at a frame's last evaluation go from %s to %s "
          "per frame.\n"
          % (fmt(b["ms_per_frame"] / a["ms_per_frame"]), a["build"], fmt(b["ms_per_frame"]), fmt(a["ms_per_frame"]),
             fmt(b["newton_per_frame"] / a["newton_per_frame"]), fmt(b["newton_per_frame"]),
             fmt(a["newton_per_frame"]), fmt(a.get("friction_sticking_per_frame", float("nan"))),
             fmt(b.get("friction_sticking_per_frame", float("nan")))))
    if len(rows) >= 2:
        a, b = rows[0], rows[-1]
        ms = b["ms_per_frame"] / a["ms_per_frame"] if a["ms_per_frame"] else float("nan")
        its = b["newton_per_frame"] / a["newton_per_frame"] if a["newton_per_frame"] else float("nan")
        share = b["friction_ms_per_frame"] / b["ms_per_frame"] if b["ms_per_frame"] else float("nan")
        A("With friction a frame takes %s× the time without (%s ms against %s ms) and %s× the Newton iterations "
          "(%s against %s); friction's own evaluation is %s of a frame with friction.\n"
          % (fmt(ms), fmt(b["ms_per_frame"]), fmt(a["ms_per_frame"]), fmt(its), fmt(b["newton_per_frame"]),
             fmt(a["newton_per_frame"]), f"{100 * share:.0f} %" if math.isfinite(share) else "n/a"))


def compile_time_label(f, opt):
    """A compile_time row's file as the table shows it."""
    if f == COMPILE_FLOOR:
        label = "`#include <pce/pce.hpp>` alone (the floor)"
    elif f.startswith("examples/"):
        label = f"example `{f.split('/')[1]}`"
    else:
        label = f"`{Path(f).name}`"
    return label + (f", {opt}" if opt != "-O2" else "")


def compile_time_table(rows):
    """The table's rows: one per file and optimisation, header-only and pce::precompiled side
    by side (— where that variant is not measured)."""
    order, cells = [], {}
    for r in rows:
        k = (r["file"], r["optimisation"])
        if k not in cells:
            order.append(k)
            cells[k] = {}
        cells[k][r["variant"]] = r
    out = []
    for k in order:
        line = [compile_time_label(*k)]
        for variant in ("header-only", PRECOMPILED):
            r = cells[k].get(variant)
            line += [fmt(r["seconds"]), fmt(r["cpu_seconds"]), fmt(r["peak_mib"])] if r else ["—"] * 3
        out.append(line)
    return out


def write_compile_time_section(A, ct):
    """Section 7: compile time, from step_compile_time (not measured when its results are missing)."""
    A("## 7. Compile time\n")
    if not ct or not ct.get("rows"):
        A("Not measured: the results folder has no `step_compile_time.json` "
          "(`benchmarks/run_all --steps compile_time` measures it).\n")
        return
    rows = ct["rows"]

    def sec(f, variant="header-only", opt="-O2"):
        return next((r["seconds"] for r in rows if r["file"] == f and r["variant"] == variant
                     and r["optimisation"] == opt), None)
    A("pce is header-only, so what a file costs to compile is its users' cost. `%s`, with the build's compiler "
      "(%s), for: `benchmarks/compile_time/minimal_runtime.cpp`, the smallest user file (one vertex-face pair in "
      "double: `pair_energy`, `energy_gradient`, `projected_hessian(e, Projection::analytic)`, the strategy chosen "
      "at run time, which instantiates every strategy, Eigen's 12×12 eigensolver included); "
      "`minimal_template.cpp`, the same with `projected_hessian<Projection::analytic>(e)`, the strategy chosen at "
      "compile time, which instantiates that one only; each example; and `#include <pce/pce.hpp>` with an empty "
      "`main` (the floor). *Header-only* is the plain command; *pce::precompiled* adds `-DPCE_PRECOMPILED`, which "
      "a target linking `pce::precompiled` gets: the headers then declare the heavy instantiations `extern "
      "template` (`include/pce/core/precompiled.hpp`) and the library holds them, compiled once. "
      "`sim_from_cpp` also has `-I src/sim/include -fopenmp` and no header-only row (`pce::sim` links "
      "`pce::precompiled`). Wall time is the median of %d compilation%s, in rounds over every row; CPU time is "
      "the compiler's user + system time (median), peak its largest resident memory (`compile_time.json`, "
      "`compile_time.csv`).\n"
      % (ct["command"], ct["compiler"], ct["repeats"], "s" if ct["repeats"] != 1 else ""))
    A(md_table(["file", "header-only s", "CPU s", "peak MiB", "pce::precompiled s", "CPU s", "peak MiB"],
               compile_time_table(rows)) + "\n")
    rt, tp = "benchmarks/compile_time/minimal_runtime.cpp", "benchmarks/compile_time/minimal_template.cpp"
    slow, pre, tmpl, floor = sec(rt), sec(rt, PRECOMPILED), sec(tp), sec(COMPILE_FLOOR)
    if slow and pre and tmpl:
        A("The minimal file with the strategy at run time takes %s s header-only, %s s with `pce::precompiled` "
          "and %s s with the strategy at compile time; including `pce/pce.hpp` alone takes %s s.\n"
          % (fmt(slow), fmt(pre), fmt(tmpl), fmt(floor)))
    note = (ct.get("note") or "").strip()
    A("These are one machine's timings (%s cores, %s, commit %s%s, %s), measured one after the other, never two "
      "compilations at once.%s To choose: in a file you edit often, pick the strategy at compile time "
      "(`projected_hessian<Projection::analytic>(e)`); where the strategy is a run-time choice "
      "(`projected_hessian(e, strategy)`), link `pce::precompiled` so that the file does not compile every "
      "strategy.\n"
      % (ct["cores"], ct["cpu"], ct["commit"], " with uncommitted changes" if ct["dirty"] else "", ct["date_utc"],
         f" {note}" + ("" if note.endswith(".") else ".") if note else ""))


def write_hammock_section(A, hammock):
    """Section 5: the hammock's rows from step_hammock, before and after when there is a before."""
    rows = hammock["rows"]
    before = hammock.get("before")
    A("## 5. The hammock, %s\n" % ("before and after" if before else "where a frame goes"))
    A("`pce-sim examples/scenes/%s --frames %d --no-frames --threads 1` (`analytic`, the scene's tolerance), full "
      "Newton and `--single-solve`, each run alone on the machine%s.%s Per frame: wall time (*ratio* to the first "
      "row of the same mode), Newton iterations, broad-phase queries per contact effect, CHOLMOD factorisations "
      "and symbolic analyses, CG iterations (`factor_reuse` only), the broad phase's share, the stages in ms, "
      "then iteration caps, line-search failures and frames with intersecting triangle pairs over the run "
      "(`benchmarks/results/hammock.csv`).\n"
      % (hammock["scene"], hammock["frames"],
         f"; the before rows are commit {before}'s `pce-sim` (`benchmarks/run_all --before {before}`), each "
         "mode's two runs one after the other" if before else
         "; `benchmarks/run_all --steps hammock --before REV` adds the same runs of commit REV",
         " `hammock_frictionless.json` is the shipped `hammock.json` without its friction: older `pce-sim` "
         "versions reject the `friction` key, so before and after run the same scene; what friction costs is "
         "[section 6](#6-frictions-cost-on-the-hammock)." if hammock["scene"] == "hammock_frictionless.json" else ""))
    A(md_table(["run", "mode", "ms/frame", "ratio", "Newton it", "queries", "factorisations", "analyses", "CG it",
                "broad phase"] + [STAGE_NAMES[k] + " ms" for k in compare_runs.STAGES] +
               ["caps", "ls failures", "intersecting frames"],
               [[r["run"], r["mode"], fmt(r["ms_per_frame"]), fmt(r["ratio"]), fmt(r["newton_per_frame"]),
                 fmt(r["queries_per_frame_per_effect"]), fmt(r["factorizations"]), fmt(r["analyses"]),
                 fmt(r["cg_iterations"]), f"{100 * r['broad_phase_share']:.0f} %"] +
                [fmt(r[k]) for k in compare_runs.STAGES] +
                [r["iteration_caps"], r["line_search_failures"], r["frames_with_intersections"]] for r in rows],
               align=["---", "---"] + ["---:"] * 16) + "\n")


# ---------------------------------------------------------------------------------------------
# Plots.

def plot_pair(ctx, acc, cost):
    """ns per pair against the median distance to the nearest-PSD Hessian, one panel per pair kind."""
    fig, axes = plt.subplots(1, 4, figsize=(16, 4.2), sharey=True)
    for ax, pair in zip(axes, PAIRS):
        for scalar, marker in (("double", "o"), ("float", "^")):
            for s in STRATEGIES:
                t = cost["ns"].get(f"{pair}/{s}/{scalar}")
                d = pair_summary(acc, pair, scalar, s, families=("random",))
                if t is None or d is None or not math.isfinite(d["median"]):
                    continue
                ax.scatter([t], [max(d["median"], 1e-17)], color=COLORS[s], marker=marker, s=60,
                           label=f"{s} ({scalar})")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(pair.replace("_", "-"))
        ax.set_xlabel("ns per pair (median)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("median ‖P − P*‖/‖P*‖ (random pairs)")
    h, lab = axes[0].get_legend_handles_labels()
    fig.legend(h, lab, loc="lower center", ncol=5, fontsize=8, bbox_to_anchor=(0.5, -0.08))
    fig.suptitle("Per pair: cost against distance to the true (50-digit) nearest-PSD projection; "
                 "points at 1e-17 are exact to 50 digits")
    fig.tight_layout()
    fig.savefig(ctx.images / "pair_accuracy_cost.png", dpi=90, bbox_inches="tight")
    plt.close(fig)


def plot_scenes(ctx, scenes):
    names = [n for n in scenes["plan"]]
    fig, axes = plt.subplots(1, len(names), figsize=(4.6 * len(names), 4.4), squeeze=False)
    markers = {("single", None): "s", ("newton", 0.1): "v", ("newton", 0.01): "o", ("newton", 0.001): "^"}
    for ax, name in zip(axes[0], names):
        rows = [r for r in scenes["rows"] if r["scene"] == name and r["kind"] == "config"]
        floor = [r for r in scenes["rows"] if r["scene"] == name and r["kind"] == "noise_floor"]
        for r in rows:
            if r["dev_rms"] is None:
                continue
            mk = markers.get((r["mode"], r["tolerance"]), "o")
            ax.scatter([r["ms_per_frame"]], [max(r["dev_rms"], 1e-9)], color=COLORS[r["strategy"]], marker=mk, s=55,
                       edgecolors="black" if r["failure"] else "none")
        for r in floor:
            if r["dev_rms"] is not None:
                ax.axhline(max(r["dev_rms"], 1e-9), color="gray", ls="--", lw=1)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(name)
        ax.set_xlabel("ms per frame (mean, 1 thread)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("RMS deviation of the final state from the reference (m)")
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], color=COLORS[s], marker="o", ls="", label=s) for s in STRATEGIES]
    handles += [Line2D([], [], color="black", marker=m, ls="", label=("single solve" if k[0] == "single" else f"Newton tol {k[1]:g}"))
                for k, m in markers.items()]
    handles.append(Line2D([], [], color="gray", ls="--", label="two tight runs differ by"))
    fig.legend(handles=handles, loc="lower center", ncol=10, fontsize=8, bbox_to_anchor=(0.5, -0.07))
    fig.suptitle("Per scene: time against accuracy, one point per configuration (lower left is better)")
    fig.tight_layout()
    fig.savefig(ctx.images / "scene_pareto.png", dpi=90, bbox_inches="tight")
    plt.close(fig)


def plot_broad_phase(ctx, bp):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    styles = {"fcl": "tab:blue", "bullet": "tab:orange", "brute": "tab:gray"}
    for key, ax, title in (("query_ms", axes[0], "query (tree unchanged)"), ("update_ms", axes[1], "update + query (vertices moved)")):
        for kind in styles:
            rows = sorted([r for r in bp["rows"] if r["broad_phase"] == kind and r.get(key) is not None],
                          key=lambda r: r["triangles"])
            if not rows:
                continue
            xs = [r["triangles"] for r in rows]
            ys = [r[key] for r in rows]
            k = bp["exponents"].get(kind, {}).get(key, float("nan"))
            ax.plot(xs, ys, "o-", color=styles[kind], label=f"{kind} (∝ n^{k:.2f})")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("triangles")
        ax.set_ylabel("ms (median)")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Broad phase on crumpled cloths: vertex-face + edge-edge candidates")
    fig.tight_layout()
    fig.savefig(ctx.images / "broad_phase_scaling.png", dpi=90, bbox_inches="tight")
    plt.close(fig)


def plot_threads(ctx, threads, scenes):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.0))
    rows = threads["rows"]
    keys = ["ms_per_frame"] + STAGES
    x = range(len(keys))
    for r in rows[1:]:
        axes[0].bar(x, [r["speedup_" + k] for k in keys], color="tab:blue")
    axes[0].axhline(1, color="black", lw=0.8)
    axes[0].set_xticks(list(x))
    axes[0].set_xticklabels(["frame"] + [STAGE_NAMES[k] for k in STAGES], rotation=20, fontsize=8)
    axes[0].set_ylabel(f"speed-up, {rows[-1]['threads']} threads over 1")
    axes[0].set_title(f"threads ({threads['scene']})")
    # Stage shares of a frame: Newton, analytic, scene tolerance 1e-2, one thread.
    shares = [r for r in scenes["rows"] if r["kind"] == "config" and r["strategy"] == "analytic" and r["mode"] == "newton"
              and r["tolerance"] in (None, 0.01)]
    shares = {r["scene"]: r for r in shares}
    names = list(shares)
    bottom = [0.0] * len(names)
    # Pair evaluation includes the line search's energy-only passes, which the line search's
    # time counts too, so the stages can add up to more than the frame: bars are shares of
    # the larger of the two.
    def whole(r):
        return max(r["ms_per_frame"], sum(r[k] for k in STAGES + ["other_ms"]))
    for k in STAGES + ["other_ms"]:
        vals = [shares[n][k] / whole(shares[n]) if whole(shares[n]) > 0 else 0 for n in names]
        axes[1].bar(names, vals, bottom=bottom, label=STAGE_NAMES[k])
        bottom = [b + v for b, v in zip(bottom, vals)]
    axes[1].set_ylabel("share of a frame")
    axes[1].tick_params(axis="x", labelrotation=20, labelsize=8)
    axes[1].set_title("where a frame goes (Newton, analytic, 1 thread)")
    axes[1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1, 1))
    fig.tight_layout()
    fig.savefig(ctx.images / "threads.png", dpi=90, bbox_inches="tight")
    plt.close(fig)


def plot_block_accuracy(ctx, res):
    """One Pareto plot per scene of step_block_accuracy: ms/frame against the RMS distance to the
    reference at the last measured frame, log-log; returns the files written."""
    from matplotlib.lines import Line2D
    files = []
    for s in res["scenes"]:
        last = str(max(s["at"]))
        rows = [r for r in res["rows"] if r["scene"] == s["key"] and r["status"] in ("ok", "failed")]
        subs = sorted({r["substeps"] for r in res["rows"] if r["mode"] == "block_descent"})
        cmap = plt.get_cmap("viridis")
        colour = {S: cmap(0.85 * i / max(len(subs) - 1, 1)) for i, S in enumerate(subs)}
        fig, ax = plt.subplots(figsize=(7.5, 5.2))
        front, plotted, ref_x = [], 0, None
        for r in rows:
            x, y = r.get("ms_per_frame"), r.get("rms_m", {}).get(last)
            if r["reference"]:
                ref_x = x
                continue
            if not x or y is None or not (y > 0 and math.isfinite(y) and x > 0):
                continue
            y *= 1000
            plotted += 1
            edge = "red" if r["status"] == "failed" else "black"
            if r["mode"] == "newton":
                ax.scatter([x], [y], marker="s", color="black", s=60, zorder=3)
                ax.annotate(f"Newton {r['tolerance']:g}", (x, y), textcoords="offset points", xytext=(5, -10),
                            fontsize=7)
            else:
                ax.scatter([x], [y], marker="o" if r["acceleration"] == "none" else "^", color=colour[r["substeps"]],
                           edgecolors=edge, linewidths=0.6, s=55, zorder=3)
                ax.annotate(f"{r['substeps']}×{r['sweeps']}", (x, y), textcoords="offset points", xytext=(4, 4),
                            fontsize=7)
            if r.get("pareto"):
                front.append((x, y))
        if ref_x:
            ax.axvline(ref_x, color="gray", ls="--", lw=1)
        if front:
            front.sort(key=lambda p: (p[0], -p[1]))  # monotone where two front points share an ms/frame
            ax.plot([p[0] for p in front], [p[1] for p in front], "-", color="tab:red", lw=1.2, zorder=2)
        if plotted:
            ax.set_xscale("log")
            ax.set_yscale("log")
        else:
            ax.text(0.5, 0.5, "no run with an RMS to plot", transform=ax.transAxes, ha="center")
        ax.set_xlabel("ms per frame (mean, %d thread%s)" % (res["threads"], "s" if res["threads"] != 1 else ""))
        ax.set_ylabel(f"RMS distance to the reference at frame {last} (mm)")
        ax.set_title(f"{s['key']}: block descent S×N against Newton (lower left is better)", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        handles = [Line2D([], [], color="gray", marker="o", ls="", label="block descent"),
                   Line2D([], [], color="gray", marker="^", ls="", label="block descent, Chebyshev"),
                   Line2D([], [], color="black", marker="s", ls="", label="Newton")]
        handles += [Line2D([], [], color=colour[S], marker="o", ls="", label=f"S = {S}") for S in subs]
        handles += [Line2D([], [], color="gray", ls="--", label="reference (Newton %g)" % res["settings"]["reference"]),
                    Line2D([], [], color="tab:red", ls="-", label="Pareto front")]
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1))
        fig.tight_layout()
        f = ctx.images / f"block_accuracy_{s['key']}.png"
        fig.savefig(f, dpi=90, bbox_inches="tight")
        plt.close(fig)
        files.append(f)
    return files


# ---------------------------------------------------------------------------------------------
# Summaries used by the tables and the conclusion.

def pair_summary(acc, pair, scalar, strategy, families=None, exclude=()):
    rows = [r for r in acc["rows"] if r["pair"] == pair and r["scalar"] == scalar and r["strategy"] == strategy
            and (families is None or r["family"] in families) and r["family"] not in exclude]
    if not rows:
        return None
    n = sum(r["configurations"] for r in rows)
    meds = [r["rel_dist_median"] for r in rows if r["rel_dist_median"] is not None]
    p90 = [r["rel_dist_p90"] for r in rows if r["rel_dist_p90"] is not None]
    mx = [r["rel_dist_max"] for r in rows if r["rel_dist_max"] is not None]
    ok = n - sum(r["not_ok"] for r in rows)
    return {
        "n": n, "ok": ok,
        "median": median(meds), "p90": max(p90) if p90 else float("nan"), "max": max(mx) if mx else float("nan"),
        "psd_violations": sum(r["psd_violations"] for r in rows),
        "non_finite": sum(r["non_finite"] for r in rows),
        "not_ok": sum(r["not_ok"] for r in rows),
    }


def broad_phase_exponents(bp, quick):
    """Fitted exponents of time against triangle count, from n >= 40 (smaller sizes are overhead-bound)."""
    out = {}
    for kind in sorted({r["broad_phase"] for r in bp["rows"]}):
        rows = [r for r in bp["rows"] if r["broad_phase"] == kind and (quick or r["n"] >= 40)]
        out[kind] = {k: fit_exponent([r["triangles"] for r in rows], [r.get(k) for r in rows])
                     for k in ("build_ms", "update_ms", "query_ms")}
    return out


# ---------------------------------------------------------------------------------------------
# The report.

def write_report(ctx, machine, cost, acc, bp, threads, scenes, hammock, friction, compile_time, total_s, scale=None,
                 block_acc=None):
    img = os.path.relpath(ctx.images, ctx.docs.parent)
    L = []
    A = L.append
    A("# Benchmarks: what accuracy costs in time\n")
    A("<!-- Generated by benchmarks/run_all (benchmarks/run_all.py): edit the script, not this file. -->\n")
    A("Everything on this page comes from **one run** of one command, on the machine described below:\n")
    command = "benchmarks/run_all" + (f" --before {hammock['before']}" if hammock.get("before") else "")
    A("```sh\n%-29s # ~%d min here; --quick runs a seconds-long subset (the ctest smoke test)\n```\n"
      % (command, max(1, round(total_s / 60))))
    A("It runs `pce-bench` (cost per pair), `pce-accuracy` (distance of each strategy's Hessian to the true "
      "nearest-PSD projection, computed in 50 digits), `pce-broad-phase-bench` (FCL, Bullet and brute force on "
      "crumpled cloths) and `pce-sim` (every shipped scene × strategy × mode × tolerance, and a thread count "
      "sweep, and the shipped hammock's first 120 frames alone: without friction, before and after with "
      "`--before REV`, and without and with friction), times compiling a minimal user file and the examples "
      "header-only and with `pce::precompiled`, writes "
      "JSON and CSV into `benchmarks/results/`, draws the plots below and rewrites this page. "
      "Figures are medians, and ratios are taken within this one run: the machine is a shared VM whose speed "
      "drifts by 25 % between days, so compare numbers within this page, not across runs. No timing is "
      "asserted by a test; the test suite runs `benchmarks/run_all --quick` only to keep the pipeline working, "
      "and `benchmarks/guidance_numbers.py --check` to keep the closing advice's numbers equal to the results. "
      "How `pce-bench` works and how its numbers got where they are: [`pce-bench.md`](pce-bench.md).\n")
    A("**Machine.** %s, %s cores, %s, %s, %s, build type %s (`%s`), Eigen %s, FCL %s, Bullet %s; commit %s%s; %s; "
      "total wall time %.1f min.\n" % (machine["cpu"], machine["cores"], machine["memory"], machine["os"],
                                       machine["compiler"], machine["build_type"], machine["flags"], machine["eigen"],
                                       machine["fcl"], machine["bullet"], machine["commit"],
                                       " (with uncommitted changes)" if machine["dirty"] else "",
                                       machine["date_utc"], total_s / 60))
    A(conclusion(cost, acc, bp, threads, scenes))
    A(guidance(ctx))

    # --- per pair ---
    A("## 1. Per pair: cost and accuracy side by side\n")
    A(f"![cost against accuracy per pair]({img}/pair_accuracy_cost.png)\n")
    A("**What is measured.** Cost: `%s` — ns per pair for `pair_energy` + gradient + the strategy's Hessian, "
      "median of 5 interleaved repetitions, on pools of 1024 active log-barrier pairs (`pce-bench.md`). Accuracy: "
      "`%s` — for each strategy P, the relative Frobenius distance ‖P − P*‖/‖P*‖ to P*, the nearest PSD matrix "
      "to the exact Hessian (its negative eigenvalues clamped to 0), computed with the same templates in 50 "
      "digits at the very input the scalar saw; the PSD-violation rate; the rate of non-finite results and of "
      "statuses other than `ok`. Sets: `random` (well-shaped pairs, length spread over the penalty's range), "
      "`near_contact` (L/d̂ from 1e-6 to 1e-2) and every hard family of `docs/stability.md`; lengths signed and "
      "unsigned, penalties quadratic, cubic and log barrier. Wall time of the accuracy run: %.0f s.\n"
      % (cost["command"], acc["command"], acc.get("wall_s", float("nan"))))
    quantities = ["value_gradient", "exact_hessian", "eigensystem"] + STRATEGIES
    A("Every `pce-bench` quantity, ns per pair (median); `exact_hessian` is the indefinite Hessian the "
      "strategies start from, `eigensystem` the closed-form eigenpairs:\n")
    A(md_table(["quantity"] + [f"{p.replace('_', '-')} {sc}" for p in PAIRS for sc in ("double", "float")],
               [[f"`{q}`"] + [fmt(cost["ns"].get(f"{p}/{q}/{sc}")) for p in PAIRS for sc in ("double", "float")]
                for q in quantities]) + "\n")
    A("Per pair kind, cost beside accuracy:\n")
    for pair in PAIRS:
        rows = []
        for scalar in ("double", "float"):
            tnum = cost["ns"].get(f"{pair}/numerical/{scalar}")
            for s in STRATEGIES:
                t = cost["ns"].get(f"{pair}/{s}/{scalar}")
                rnd = pair_summary(acc, pair, scalar, s, families=("random",))
                near = pair_summary(acc, pair, scalar, s, families=("near_contact",))
                hard = pair_summary(acc, pair, scalar, s, exclude=("random", "near_contact"))
                allr = pair_summary(acc, pair, scalar, s)
                if allr is None and t is None:
                    continue
                rows.append([f"`{s}`", scalar, fmt(t), fmt(t / tnum) if t and tnum else "n/a",
                             fmt(rnd["median"]) if rnd else "n/a", fmt(rnd["max"]) if rnd else "n/a",
                             fmt(near["median"]) if near else "n/a", fmt(near["max"]) if near else "n/a",
                             fmt(hard["median"]) if hard else "n/a", fmt(hard["max"]) if hard else "n/a",
                             f"{allr['psd_violations']}/{allr['ok']}" if allr else "n/a",
                             f"{allr['non_finite']}/{allr['n']}" if allr else "n/a",
                             f"{allr['not_ok']}/{allr['n']}" if allr else "n/a"])
        if not rows:
            continue
        A(f"**{pair.replace('_', '-')}**\n")
        A(md_table(["strategy", "scalar", "ns/pair", "× numerical", "random: median dist.", "max",
                    "near contact: median", "max", "hard families: median", "max", "PSD violations",
                    "non-finite", "not ok"], rows, ["---", "---"] + ["---:"] * 11) + "\n")
    A("Columns: *dist.* is ‖P − P*‖/‖P*‖ (median of the groups' medians; *max* over all configurations of the "
      "set). *PSD violations* counts ok results with λ_min(P) < −τ·max|λ(P)| (τ in `accuracy.json`'s settings), "
      "out of the ok results; *non-finite* and *not ok* count over all configurations (the hard families include "
      "degenerate inputs, whose expected status is `degenerate`). Raw rows per length, penalty and family: "
      "`benchmarks/results/accuracy.csv`.\n")

    # --- per scene ---
    A("## 2. Per scene: time against accuracy\n")
    A(f"![Pareto per scene]({img}/scene_pareto.png)\n")
    A("Each scene runs without its friction (the friction potential is the same whatever the strategy; its cost "
      "is [section 6](#6-frictions-cost-on-the-hammock)) with every Hessian strategy, in single-linearised-solve "
      "mode and with full Newton at "
      "tolerances 0.1, 0.01 (the scenes' own) and 0.001 on max|Δx|/(h·ℓ), one thread, two runs at a time on "
      "the two cores. The reference is `%s` Newton at tolerance %g with up to 300 iterations; *deviation* is the "
      "RMS (and max) over vertices of the distance between a run's final state and the reference's. The dashed "
      "line is how far a second tight run (`%s`, tolerance %g) ends from the reference: deviations below it are "
      "noise. `pce-sim` is double only (its solver, assembly and CHOLMOD are double), so the scenes have no float "
      "rows; float is compared per pair above. Shortened variants (the full scenes take 25 s to 25 min per run): %s. "
      "Command per row: `pce-sim SCENE.json --no-frames --threads 1 --hessian S [--single-solve | --tolerance T]`.\n"
      % (REFERENCE[0], REFERENCE[2], NOISE_FLOOR[0], NOISE_FLOOR[2],
         "; ".join(f"`{k}` = {v['base']} with " + ", ".join(f"{a} {b}" for a, b in v.items() if a != "base")
                   for k, v in scenes["plan"].items())))
    for name in scenes["plan"]:
        rows = [r for r in scenes["rows"] if r["scene"] == name]
        rows.sort(key=lambda r: ({"config": 0, "reference": 1, "noise_floor": 2}[r["kind"]],
                                 STRATEGIES.index(r["strategy"]), r["mode"] != "single", -(r["tolerance"] or 0)))
        A(f"**{name}** ({rows[0]['vertices']} vertices, {rows[0]['frames']} frames)\n")
        A(md_table(["strategy", "mode", "ms/frame", "Newton it/frame", "residual (median / max)", "peak MiB",
                    "LS failures", "iteration caps", "frames with intersections", "deviation RMS (m)", "max (m)"],
                   [[("**ref** " if r["kind"] == "reference" else "tight " if r["kind"] == "noise_floor" else "") + f"`{r['strategy']}`",
                     "single" if r["mode"] == "single" else f"Newton {r['tolerance']:g}",
                     fmt(r["ms_per_frame"]), fmt(r["newton_per_frame"]),
                     f"{fmt(r['residual_median'])} / {fmt(r['residual_max'])}", fmt(r["peak_mib"]),
                     r["line_search_failures"], r["iteration_caps"], r["frames_with_intersections"],
                     "—" if r["kind"] == "reference" else fmt(r["dev_rms"]),
                     "—" if r["kind"] == "reference" else fmt(r["dev_max"])] for r in rows],
                   ["---", "---"] + ["---:"] * 9) + "\n")
        failed = [r for r in rows if r["failure"]]
        for r in failed:
            A(f"- `{r['strategy']}` {r['mode']} {r['tolerance']}: failed after {r['frames']} frames: {r['failure']}\n")
    if scenes.get("headline"):
        rows = [r for r in scenes["rows"] if r["scene"] == "hammock"]
        A("**hammock at full resolution** (%d vertices, the first %d frames: the first sheet falls and lands; "
          "scene tolerance 0.01, one thread; no reference run, too long)\n" % (rows[0]["vertices"], rows[0]["frames"]))
        ana = next((r for r in rows if r["strategy"] == "analytic"), None)
        A(md_table(["strategy", "ms/frame", "× analytic", "Newton it/frame", "pair evaluation ms/frame",
                    "linear solve ms/frame", "peak MiB", "LS failures", "iteration caps", "frames with intersections"],
                   [[f"`{r['strategy']}`", fmt(r["ms_per_frame"]),
                     fmt(r["ms_per_frame"] / ana["ms_per_frame"]) if ana else "n/a", fmt(r["newton_per_frame"]),
                     fmt(r["pair_ms"]), fmt(r["solve_ms"]), fmt(r["peak_mib"]), r["line_search_failures"],
                     r["iteration_caps"], r["frames_with_intersections"]]
                    for r in sorted(rows, key=lambda r: STRATEGIES.index(r["strategy"]))]) + "\n")

    # --- broad phase ---
    A("## 3. Broad phase: FCL, Bullet and brute force\n")
    A(f"![broad-phase scaling]({img}/broad_phase_scaling.png)\n")
    s = bp.get("settings", {})
    A("`%s`: crumpled cloths of n×n quads (`pce::sim::crumpled_grid`), vertex-face and edge-edge candidates at "
      "the distance in the settings below; *build* is the first query of a fresh broad phase, *update* moves "
      "every vertex by up to 0.05 spacing and queries again (trees refitted), *query* repeats a query with "
      "nothing moved (the broad phases have no 'unchanged' shortcut, so it refits too). Each time is one "
      "vertex-face plus one edge-edge call. "
      "Medians over repetitions. Every broad phase returns the same candidates (checked by the benchmark at "
      "every size, and by `tests/sim/test_broad_phase.cpp`). Brute force is quadratic in the primitive count and stops "
      "at the size where a call would take longer than its limit. Settings: `%s`.\n" % (bp["command"], json.dumps(s)))
    rows = sorted(bp["rows"], key=lambda r: (r["n"], r["broad_phase"]))
    A(md_table(["n", "triangles", "broad phase", "build ms", "update ms", "query ms", "vertex-face", "edge-edge"],
               [[r["n"], r["triangles"], r["broad_phase"], fmt(r.get("build_ms")), fmt(r.get("update_ms")),
                 fmt(r.get("query_ms")), r["vertex_face"], r["edge_edge"]] for r in rows]) + "\n")
    A("Fitted exponents k of time ∝ triangles^k (least squares on log–log, n ≥ 40):\n")
    A(md_table(["broad phase", "build", "update", "query"],
               [[k, fmt(v["build_ms"]), fmt(v["update_ms"]), fmt(v["query_ms"])] for k, v in bp["exponents"].items()]) + "\n")

    # --- threads ---
    A("## 4. Threads, and where a frame goes\n")
    A(f"![threads and stage shares]({img}/threads.png)\n")
    tr = threads["rows"]
    A("`pce-sim` on `%s` (%s), `analytic`, Newton, `--threads 1` and `--threads %d` (this machine has %s cores, so "
      "that is the sweep it allows), one run at a time with nothing else running: "
      "`pce-sim benchmarks/results/scenes/threads_%s.json --no-frames --hessian analytic --threads T`. Pair "
      "evaluation runs in an OpenMP loop and the contact effects' broad-phase covers run side by side; the "
      "scatter of the pair blocks into the sparse matrix is serial (so results are identical bit for bit "
      "whatever the thread count), and so are CHOLMOD's factorisation (OpenBLAS serial, see "
      "`docs/simulation.md`) and each broad-phase query.\n" % (threads["scene"], ", ".join(f"{a} {b}" for a, b in threads["changes"].items()),
                                    tr[-1]["threads"], machine["cores"], threads["scene"]))
    A(md_table(["threads", "ms/frame", "Newton it/frame"] + [STAGE_NAMES[k] + " ms" for k in STAGES] +
               ["speed-up: frame", "pair evaluation", "assembly"],
               [[r["threads"], fmt(r["ms_per_frame"]), fmt(r["newton_per_frame"])] + [fmt(r[k]) for k in STAGES] +
                [fmt(r["speedup_ms_per_frame"]), fmt(r["speedup_pair_ms"]), fmt(r["speedup_assembly_ms"])] for r in tr]) + "\n")
    shares = [r for r in scenes["rows"] if r["kind"] == "config" and r["strategy"] == "analytic"
              and r["mode"] == "newton" and r["tolerance"] in (None, 0.01)]
    A("Share of a frame per stage (Newton, `analytic`, the scene's tolerance, one thread). *Pair evaluation* "
      "includes the line search's energy-only passes, which *line search* counts too, so a row can add up to "
      "a little more than 100 % (the plot divides by the larger of the sum and the frame); *assembly* is the "
      "pattern, the inertia term and the serial scatter of the pair blocks into the sparse matrix.\n")
    A(md_table(["scene", "ms/frame"] + [STAGE_NAMES[k] for k in STAGES + ["other_ms"]],
               [[r["scene"], fmt(r["ms_per_frame"])] + [f"{100 * r[k] / r['ms_per_frame']:.0f} %" if r["ms_per_frame"] else "n/a"
                                                       for k in STAGES + ["other_ms"]] for r in shares]) + "\n")
    write_hammock_section(A, hammock)
    write_friction_section(A, friction)
    write_compile_time_section(A, compile_time)
    write_scale_section(A, scale)
    write_block_accuracy_section(A, block_acc, img)
    A("## Files\n")
    A("`benchmarks/results/`: `machine.json`, `pce_bench.json`/`.csv`, `accuracy.json`/`.csv`, "
      "`broad_phase.json`/`.csv`, `threads.csv`, `scenes.csv`, `hammock.csv`, `friction.csv`, "
      "`compile_time.json`/`.csv`, `scale_ladder.json`/`.csv`/`.md`, `block_accuracy.json`/`.md`, `step_*.json` (each step's numbers as this page "
      "used them; `run_all --steps scenes` reruns one step and reads the others from there), and the scene "
      "variants in `scenes/`. The simulations' own outputs go to `runs/` (not kept in git).\n")
    ctx.docs.parent.mkdir(parents=True, exist_ok=True)
    ctx.docs.write_text("\n".join(L))


def conclusion(cost, acc, bp, threads, scenes):
    """The short "what accuracy costs" section, numbers from this run."""
    ns = cost["ns"]

    def ratio(pair, a, b, scalar="double"):
        x, y = ns.get(f"{pair}/{a}/{scalar}"), ns.get(f"{pair}/{b}/{scalar}")
        return x / y if x and y else float("nan")

    def dist(pair, s, fam=("random",), scalar="double", key="median"):
        d = pair_summary(acc, pair, scalar, s, families=fam)
        return d[key] if d else float("nan")

    def scene_row(name, s, mode="newton", tol=0.01):
        for r in scenes["rows"]:
            if r["scene"] == name and r["strategy"] == s and r["mode"] == mode and r["kind"] == "config" and \
                    (r["tolerance"] == tol or (tol == 0.01 and r["tolerance"] is None)):
                return r
        return None

    L = ["## What accuracy costs\n"]
    vf = "vertex_face"
    L.append(
        "- **Per pair, `analytic` is the cheap PSD Hessian and close to the true projection.** Vertex-face, "
        f"double: `analytic` costs {fmt(ratio(vf, 'analytic', 'exact_hessian'))}× the exact (indefinite) Hessian "
        f"and 1/{fmt(1 / ratio(vf, 'analytic', 'numerical'))} of `numerical`; on random pairs its median distance "
        f"to the nearest PSD matrix is {fmt(dist(vf, 'analytic'))} (max {fmt(dist(vf, 'analytic', key='max'))}), "
        f"near contact {fmt(dist(vf, 'analytic', ('near_contact',)))}.")
    L.append(
        f"- **`exact` buys the true projection for {fmt(ratio(vf, 'exact', 'analytic'))}× `analytic`** "
        f"(1/{fmt(1 / ratio(vf, 'exact', 'numerical'))} of `numerical`): median distance "
        f"{fmt(dist(vf, 'exact'))} in double against `numerical`'s {fmt(dist(vf, 'numerical'))}.")
    L.append(
        f"- **`gauss_newton` is the cheapest ({fmt(ratio(vf, 'gauss_newton', 'analytic'))}× `analytic`) and the "
        f"least faithful**: it drops the length's curvature, median distance {fmt(dist(vf, 'gauss_newton'))}.")
    L.append(
        f"- **float** costs {fmt(ns.get(vf + '/analytic/float', math.nan) / ns.get(vf + '/analytic/double', math.nan))}× "
        f"double for `analytic`; its median distance is {fmt(dist(vf, 'analytic', scalar='float'))} "
        f"(`exact` in float: {fmt(dist(vf, 'exact', scalar='float'))}).")
    # Per scene: the strategies at the scene's own tolerance.
    for name in [n for n in ("hammock", "hammock_coarse", "drape", "strands", "twist")
                 if any(r["scene"] == n for r in scenes["rows"])]:
        parts = []
        for s in STRATEGIES:
            r = scene_row(name, s)
            if r:
                parts.append(f"`{s}` {fmt(r['ms_per_frame'])} ms/{fmt(r['newton_per_frame'])} it")
        single = scene_row(name, "analytic", "single", None)
        L.append(f"- **{name}** (Newton, tolerance 0.01, per frame): " + ", ".join(parts) +
                 (f"; single solve `analytic` {fmt(single['ms_per_frame'])} ms, deviation {fmt(single['dev_rms'])} m RMS"
                  if single and single.get("dev_rms") is not None else "") + ".")
    ex = bp["exponents"]
    L.append("- **Broad phase**: time ∝ triangles^k with k (query) = " +
             ", ".join(f"{k} {fmt(v['query_ms'])}" for k, v in ex.items()) + ".")
    tr = threads["rows"]
    if len(tr) > 1:
        L.append(f"- **Threads**: {tr[-1]['threads']} threads speed pair evaluation up {fmt(tr[-1]['speedup_pair_ms'])}×, "
                 f"assembly {fmt(tr[-1]['speedup_assembly_ms'])}×, a whole frame {fmt(tr[-1]['speedup_ms_per_frame'])}×.")
    return "\n".join(L) + "\n"


def guidance(ctx):
    """benchmarks/guidance.md with its numbers from this run's results folder (markers removed).
    When the results folder is benchmarks/results, guidance.md itself is rewritten too."""
    guide = ROOT / "benchmarks" / "guidance.md"
    page = guide.read_text()
    values, failed = guidance_numbers.compute(ctx.results)
    new = guidance_numbers.render(page, values)
    if ctx.results == (ROOT / "benchmarks" / "results").resolve() and new != page:
        guide.write_text(new)
        log(f"rewrote the numbers of {guide}")
    for text in failed:
        log(f"WARNING: the results contradict benchmarks/guidance.md: {text} (rewrite the advice)")
    return guidance_numbers.guidance_numbers_in(new) + "\n"


# ---------------------------------------------------------------------------------------------

def self_test():
    """Checks the pieces that turn raw outputs into numbers (run by --self-test)."""
    assert abs(fit_exponent([10, 100, 1000], [3e-3 * n ** 1.5 for n in (10, 100, 1000)]) - 1.5) < 1e-12
    assert abs(fit_exponent([1, 2, 4, 8], [5, 5, 5, 5])) < 1e-12
    rms, mx = deviation([(0, 0, 0), (1, 1, 1)], [(0, 0, 3), (1, 1, 1)])
    assert abs(rms - math.sqrt(4.5)) < 1e-12 and abs(mx - 3) < 1e-12
    assert median([3, float("nan"), 1, 2]) == 2
    assert fmt(1234.5) == "1 234" and fmt(0.5) == "0.5" and fmt(1e-5) == "1.0e-05"
    try:
        deviation([(0, 0, 0)], [])
    except ValueError:
        pass
    else:
        raise AssertionError("deviation accepted different vertex counts")
    fr = friction_per_frame([{"counters": {"vertex_face_friction_ms": 1.0, "edge_edge_friction_ms": 2.0,
                                           "obstacle_friction_contacts": 4.0}},
                             {"counters": {"edge_edge_friction_ms": 3.0, "edge_edge_friction_contacts": None}},
                             {"counters": {}}])
    assert fr == {"friction_ms_per_frame": 2.0, "friction_contacts_per_frame": 4 / 3,
                  "friction_sticking_per_frame": 0.0}, fr
    # compile_time: Eigen's include folder from an installed Eigen3Config.cmake, and the table.
    with tempfile.TemporaryDirectory() as tmp:
        cfg, inc = Path(tmp) / "share" / "eigen3" / "cmake", Path(tmp) / "include" / "eigen3"
        cfg.mkdir(parents=True)
        (inc / "Eigen").mkdir(parents=True)
        (inc / "Eigen" / "Core").write_text("")
        (cfg / "Eigen3Config.cmake").write_text('set (EIGEN3_INCLUDE_DIR  "${PACKAGE_PREFIX_DIR}/include/eigen3")\n')
        assert eigen_include(cfg) == inc.resolve(), eigen_include(cfg)
    ct = [{"file": "benchmarks/compile_time/minimal_runtime.cpp", "variant": v, "optimisation": o, "seconds": t,
           "cpu_seconds": t, "peak_mib": 100.0}
          for v, o, t in (("header-only", "-O2", 27.0), ("header-only", "-O0", 9.0), (PRECOMPILED, "-O2", 2.0))]
    assert compile_time_table(ct) == [["`minimal_runtime.cpp`", "27", "27", "100", "2", "2", "100"],
                                      ["`minimal_runtime.cpp`, -O0", "9", "9", "100", "—", "—", "—"]], \
        compile_time_table(ct)
    missing = [j[0] for j in compile_jobs(False) if j[0] != COMPILE_FLOOR and not (ROOT / j[0]).is_file()]
    assert not missing, f"compile_time: files not found: {missing}"
    assert set(map(str, compile_jobs(True))) <= set(map(str, compile_jobs(False)))
    # scale: level choice, mode options for a pce-sim with and without --mode, the exponent fit.
    assert scale_ladder.level_for_vertices(8000) == ("8k", 90) and scale_ladder.level_for_vertices(1e5) == ("128k", 360)
    assert scale_ladder.mode_arguments("--mode --iterations", "block_descent", 20) == [
        "--mode", "block_descent", "--iterations", "20"]
    assert scale_ladder.mode_arguments("--single-solve", "newton", None) == []
    assert abs(scale_ladder.fit_exponent([2116, 8281, 32761], [2116 ** 1.3, 8281 ** 1.3, 32761 ** 1.3]) - 1.3) < 1e-12
    # scale: the variant grammar, its labels, tags and scenes; the window; the plans.
    v = scale_ladder.parse_variant("newton/amg+mu0")
    assert v == {"mode": "newton", "iterations": None, "linear": "amg", "linear_tolerance": None, "mu0": True}, v
    assert scale_ladder.variant_label(v) == "newton/amg+mu0" and scale_ladder.variant_tag(v) == "newton_amg_mu0"
    v = scale_ladder.parse_variant("block_descent:20/pcg@1e-6")
    assert (v["iterations"], v["linear"], v["linear_tolerance"], v["mu0"]) == (20, "pcg", 1e-6, False), v
    assert scale_ladder.variant_label(v) == "block_descent:20/pcg@1e-06"
    assert scale_ladder.parse_mode("block_descent:20") == ("block_descent", 20)
    assert scale_ladder.variant_label(scale_ladder.parse_variant("newton+mu0")) == "newton+mu0"
    for bad in ("newton:0", "newton/", "newton/amg@2", "newton+mu1", "Newton", "newton/amg/pcg"):
        try:
            scale_ladder.parse_variant(bad)
        except ValueError:
            pass
        else:
            raise AssertionError(f"parse_variant accepted {bad!r}")
    sc = scale_ladder.make_scene("2k", 45, 3, linear="amg", linear_tolerance=1e-6, mu0=True)
    assert sc["solver"]["linear_solver"] == "amg" and sc["solver"]["linear_tolerance"] == 1e-6
    assert not any("friction" in e for e in sc["effects"]), sc["effects"]
    sc = scale_ladder.make_scene("2k", 45, 3)
    assert "linear_solver" not in sc["solver"] and sum("friction" in e for e in sc["effects"]) == 3
    assert scale_ladder.parse_window("5-12") == (5, 12) and scale_ladder.parse_window(None) is None
    for bad in ("0-3", "5-4", "5", "a-b"):
        try:
            scale_ladder.parse_window(bad)
        except ValueError:
            pass
        else:
            raise AssertionError(f"parse_window accepted {bad!r}")
    recs = [{"frame": i, "wall_ms": 10.0 * i, "newton_iterations": i, "counters": {"factorizations": 2 * i}}
            for i in range(1, 6)]
    w = scale_ladder.summarise_run(recs, {}, (2, 3))
    assert w["ms_per_frame"] == 25.0 and w["iterations_per_frame"] == 2.5 and w["factorizations_per_frame"] == 5
    assert w["frames_done"] == 5 and w["frames_averaged"] == 2 and w["linear_iterations_per_frame"] != \
        w["linear_iterations_per_frame"]  # nan: no cg_iterations counter
    assert scale_ladder.summarise_run(recs, {})["ms_per_frame"] == 30.0
    full = scale_ladder.expand(scale_ladder.plan_groups("full", cores=2))
    labels = {(lv, scale_ladder.variant_label(v), t) for lv, _, _, _, v, t in full}
    assert ("128k", "newton/direct", 2) in labels and ("128k", "newton/direct+mu0", 1) in labels
    assert ("8k", "newton/amg", 2) in labels and ("32k", "newton/amg", 1) not in labels
    assert ("32k", "newton/direct+mu0", 1) in labels and ("32k", "newton/direct+mu0", 2) not in labels
    assert all(f == 12 and win == (5, 12) for lv, _, f, win, v, _ in full if v["mode"] == "newton")
    assert [lv for lv, *_ in full] == sorted((lv for lv, *_ in full), key=["8k", "32k", "128k"].index)
    quick = [scale_ladder.variant_label(v) for *_, v, _ in scale_ladder.expand(scale_ladder.plan_groups("quick"))]
    assert any("/" in q for q in quick) and any(q.endswith("+mu0") for q in quick), quick
    self_test_block_accuracy()
    print("run_all self-test: ok")


def self_test_block_accuracy():
    """block_accuracy: specs and labels, the grid and its cap, the plans, the Pareto front, the
    measurements of fake runs, the table, the section and the plot (run by --self-test)."""
    ba = block_accuracy
    # Specs: parse_config and config_spec are inverses; bad specs are refused.
    for spec in ("newton@0.0001", "newton@0.01", "bd:1x5", "bd:2x10+chebyshev", "bd:10x20"):
        assert ba.config_spec(ba.parse_config(spec)) == spec, spec
    c = ba.parse_config("bd:5×20+chebyshev")
    assert (c["mode"], c["substeps"], c["sweeps"], c["acceleration"]) == ("block_descent", 5, 20, "chebyshev"), c
    assert ba.parse_config("bd:2x10+none") == ba.parse_config("bd:2x10")
    assert ba.config_label(c) == "block descent 5×20 Chebyshev" and ba.config_tag(c) == "bd_s5_n20_chebyshev"
    assert ba.config_label(ba.newton_config(1e-4, reference=True)) == "Newton 0.0001 (reference)"
    assert ba.parse_config("newton@1e-4")["tolerance"] == 1e-4
    for bad in ("bd:0x5", "bd:2x0", "bd:2x", "bd:2x5+aitken", "bd:2*5", "newton@", "newton@-1", "newton@1,2",
                "block_descent:20", "bd:2x5chebyshev"):
        try:
            ba.parse_config(bad)
        except ValueError:
            pass
        else:
            raise AssertionError(f"parse_config accepted {bad!r}")
    assert ba.parse_int_list("1, 2,5,2", "--substeps") == [1, 2, 5]
    for bad in ("0", "1,,2", "a", "-1", "1.5"):
        try:
            ba.parse_int_list(bad, "--sweeps")
        except ValueError:
            pass
        else:
            raise AssertionError(f"parse_int_list accepted {bad!r}")
    try:
        ba.parse_accelerations("none,aitken")
    except ValueError:
        pass
    else:
        raise AssertionError("parse_accelerations accepted aitken")
    # The grid: accelerations outermost, then S, then N; S*N above the cap skipped, at the cap run.
    run, skipped = ba.expand_grid([1, 2, 5, 10], [5, 10, 20], ["none", "chebyshev"], 100)
    assert [ba.config_spec(x) for x in skipped] == ["bd:10x20", "bd:10x20+chebyshev"], skipped
    assert len(run) == 22 and ba.config_spec(run[0]) == "bd:1x5" and ba.config_spec(run[-1]) == "bd:10x10+chebyshev"
    assert "bd:5x20" in {ba.config_spec(x) for x in run}  # 100 sweeps: at the cap, run
    assert len(ba.expand_grid([1, 2], [5], ["none"], 0)[0]) == 2  # 0: no cap
    full, skipped = ba.plan_configs(ba.PLANS["full"])
    assert [ba.config_spec(x) for x in full[:2]] == ["newton@0.0001", "newton@0.01"] and full[0]["reference"]
    assert len(full) == 2 + 4 * 3 * 2 - 2 and [ba.config_spec(x) for x in skipped] == ["bd:10x20", "bd:10x20+chebyshev"]
    assert ba.parse_scene_caps("hammock=20,ladder:8k=5") == {"hammock": 20, "ladder:8k": 5}
    for bad in ("hammock", "hammock=0", "=3", "hammock=x"):
        try:
            ba.parse_scene_caps(bad)
        except ValueError:
            pass
        else:
            raise AssertionError(f"parse_scene_caps accepted {bad!r}")
    quick, _ = ba.plan_configs(ba.PLANS["quick"])
    assert [ba.config_spec(x) for x in quick[2:]] == ["bd:1x5", "bd:2x5", "bd:1x5+chebyshev", "bd:2x5+chebyshev"]
    explicit, skipped = ba.plan_configs(dict(ba.PLANS["full"], configs=["bd:50x20", "bd:2x10"]))
    assert [ba.config_spec(x) for x in explicit[2:]] == ["bd:50x20", "bd:2x10"] and not skipped  # no cap on --configs
    try:
        ba.plan_configs(dict(ba.PLANS["full"], configs=["newton@0.1"]))
    except ValueError:
        pass
    else:
        raise AssertionError("plan_configs accepted a Newton spec in --configs")
    # Scenes: frames, measured frames, the output interval that writes them.
    s = ba.resolve_scene("hammock")
    assert (s["key"], s["frames"], s["at"]) == ("hammock", 60, [30, 60])
    assert ba.scene_writes({"output_every": 5}, 60, [30, 60]) and not ba.scene_writes({"output_every": 7}, 60, [30])
    assert ba.scene_writes({"output_every": 1000000}, 12, [12]) and ba.output_every_for([30, 60]) == 30
    s = ba.resolve_scene("ladder:2k", 3, [2, 3])
    assert (s["key"], s["n"], s["frames"], s["at"]) == ("ladder_2k", 45, 3, [2, 3])
    assert ba.resolve_scene("ladder:8k", 5)["at"] == [5]
    for bad in (("ladder:3k", None, None), ("hammock", None, [61]), ("drape", None, None)):
        try:
            ba.resolve_scene(*bad)
        except ValueError:
            pass
        else:
            raise AssertionError(f"resolve_scene accepted {bad}")
    # pce-sim's options; a pce-sim without --substeps/--acceleration runs S = 1, none only.
    assert ba.config_arguments(ba.parse_config("bd:2x10+chebyshev"), None) == [
        "--mode", "block_descent", "--iterations", "10", "--substeps", "2", "--acceleration", "chebyshev"]
    assert ba.config_arguments(ba.newton_config(1e-4), "--mode --tolerance") == ["--mode", "newton", "--tolerance",
                                                                                  "0.0001"]
    old_help = "--mode TEXT  --iterations INT  --tolerance FLOAT"
    assert ba.config_arguments(ba.parse_config("bd:1x5"), old_help) == ["--mode", "block_descent", "--iterations", "5"]
    for spec in ("bd:2x5", "bd:1x5+chebyshev"):
        try:
            ba.config_arguments(ba.parse_config(spec), old_help)
        except ValueError:
            pass
        else:
            raise AssertionError(f"config_arguments selected {spec} on a pce-sim without the option")
    # The Pareto front: strictly lower in both; a tie is not dominated; no numbers, no point.
    nan = float("nan")
    assert ba.pareto_flags([(100, 0.0), (10, 5.0), (20, 6.0), (20, 1.0), (50, 2.0), (5, None), (1, nan), (10, 5.0)]) \
        == [True, True, False, True, False, False, False, True]
    assert ba.pareto_flags([(3, 3), (1, 1), (2, 2)]) == [False, True, False]
    assert ba.summarise([{"wall_ms": 10.0, "newton_iterations": 0, "sweeps": 20, "substeps": 2,
                          "intersecting_triangle_pairs": 0},
                         {"wall_ms": 30.0, "newton_iterations": 0, "sweeps": 10, "substeps": 2,
                          "intersecting_triangle_pairs": 3}]) == {
        "frames_done": 2, "ms_per_frame": 20.0, "iterations_per_frame": 15.0, "substeps_reported": 2,
        "max_intersecting_pairs": 3}
    # Fake runs: the RMS, the lowest point, its relative error and the flags, then the table,
    # the section and the plot.
    with tempfile.TemporaryDirectory() as tmp:
        scene = {"key": "fake", "spec": "fake.json", "kind": "file", "file_run": "fake.json", "frames": 2,
                 "at": [1, 2]}
        cfgs = [ba.newton_config(1e-4, True), ba.newton_config(0.01), ba.parse_config("bd:1x5"),
                ba.parse_config("bd:2x5+chebyshev"), ba.parse_config("bd:1x20")]
        shifts, ms = [0.0, 0.001, 0.1, 0.01, 0.2], [100.0, 50.0, 10.0, 20.0, 60.0]
        rows = []
        for c, dz, t in zip(cfgs, shifts, ms):
            d = Path(tmp) / ba.config_tag(c)
            d.mkdir()
            for f in (1, 2):
                (d / f"frame_{f:04d}.obj").write_text(f"v 0 0 {-1 - dz}\nv 1 0 {-0.5 - dz}\nf 1 2 1\n")
            rows.append({"scene": "fake", "spec": ba.config_spec(c), "label": ba.config_label(c), **c, "dir": str(d),
                         "status": "ok", "reason": None, "frames_done": 2, "ms_per_frame": t,
                         "iterations_per_frame": 5.0, "max_intersecting_pairs": 0})
        rows.append({"scene": "fake", "spec": "bd:5x5", "label": "block descent 5×5", **ba.parse_config("bd:5x5"),
                     "status": "not run", "reason": "this pce-sim has no --substeps", "dir": None})
        ba.measure(rows, scene)
        assert rows[0]["rms_m"] == {"1": 0.0, "2": 0.0} and abs(rows[2]["rms_m"]["2"] - 0.1) < 1e-12, rows[2]
        assert abs(rows[2]["lowest_z_m"] + 1.1) < 1e-12 and abs(rows[2]["lowest_z_rel_error"] - 0.1) < 1e-12
        assert [r["pareto"] for r in rows] == [True, True, True, True, False, False], [r["pareto"] for r in rows]
        res = {"scenes": [scene], "rows": rows, "settings": dict(ba.PLANS["quick"]), "skipped": ["bd:10x20"],
               "threads": 1, "commit": "abc1234", "date_utc": "2000-01-01 00:00 UTC", "cores": 2, "plan": "quick",
               "complete": True}
        header, table = ba.table_rows(res, scene)
        assert header[6:8] == ["RMS to ref., frame 1 (mm)", "RMS to ref., frame 2 (mm)"] and len(table) == 6
        assert table[2][6:] == ["100", "100", "-1 100", "0.1", "0", "**yes**"], table[2]
        assert table[4][-1] == "" and table[5][0] == "block descent 5×5 (not run)"
        md = ba.markdown(res)
        assert "this pce-sim has no --substeps" in md and "`bd:10x20`" in md
        L = []
        write_block_accuracy_section(L.append, res, "images/benchmarks")
        page = "\n".join(L)
        assert page.startswith(BLOCK_ACCURACY_HEADING) and "--plan quick" in page and "run_all --steps block_accuracy" \
            " --quick" in page and "images/benchmarks/block_accuracy_fake.png" in page and "abc1234" in page, page
        L = []
        write_block_accuracy_section(L.append, None, "images/benchmarks")
        assert "Not measured" in L[1]

        class Images:
            images = Path(tmp)
        files = plot_block_accuracy(Images, res)
        assert files == [Path(tmp) / "block_accuracy_fake.png"] and files[0].stat().st_size > 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="a seconds-long subset of every step (smoke test)")
    ap.add_argument("--build", default=None, help="CMake build folder with the executables, used as it is (default: "
                                                 "build/ if it has every executable the steps need, else run_all "
                                                 "configures and builds them in build-benchmarks/)")
    ap.add_argument("--results", default=None, help="results folder (default benchmarks/results, or "
                                                   "build/run_all_quick with --quick)")
    ap.add_argument("--docs", default=None, help="the page to write (default docs/benchmarks.md; with --quick, "
                                                "RESULTS/benchmarks.md)")
    ap.add_argument("--jobs", type=int, default=2, help="scene runs at a time (each uses one thread)")
    ap.add_argument("--steps", default="all", help="comma-separated steps to run (%s), 'all' or 'none' (only the "
                                                   "plots and the page); the others' last results are read from the "
                                                   "results folder" % ", ".join(ALL_STEPS))
    ap.add_argument("--before", default=None, metavar="REV",
                    help="step 'hammock': also run commit REV's pce-sim (built in build-before/), before/after")
    ap.add_argument("--note", default=None, metavar="TEXT",
                    help="step 'compile_time': a line on this run's conditions (say, the machine was busy), kept "
                         "in compile_time.json and shown on the page")
    ap.add_argument("--self-test", action="store_true", help="check the number-crunching helpers and exit")
    args = ap.parse_args()
    if args.self_test:
        self_test()
        return 0
    steps = ALL_STEPS if args.steps == "all" else [] if args.steps == "none" else args.steps.split(",")
    unknown = [x for x in steps if x not in ALL_STEPS]
    if unknown:
        raise ValueError(f"--steps: unknown step(s) {', '.join(unknown)} (steps: {', '.join(ALL_STEPS)})")
    needs = {"pair_cost": "pce-bench", "accuracy": "pce-accuracy", "broad_phase": "pce-broad-phase-bench",
             "threads": "pce-sim", "scenes": "pce-sim", "hammock": "pce-sim", "friction": "pce-sim",
             "scale": "pce-sim", "block_accuracy": "pce-sim"}
    # compile_time needs no executable: the build folder's CMakeCache.txt (its compiler and Eigen).
    if args.build is None:
        args.build = str(default_build([needs[x] for x in steps if x in needs], args.jobs))
    if args.results is None:
        args.results = str(Path(args.build) / "run_all_quick") if args.quick else str(ROOT / "benchmarks" / "results")
    if args.docs is None:
        args.docs = str(Path(args.results) / "benchmarks.md") if args.quick else str(ROOT / "docs" / "benchmarks.md")
    ctx = Context(args)
    ctx.results.mkdir(parents=True, exist_ok=True)
    ctx.images.mkdir(parents=True, exist_ok=True)
    for x in steps:
        if x in needs:
            ctx.exe(needs[x])  # fail before running anything
    t0 = time.monotonic()
    log(f"results in {ctx.results}, page {ctx.docs}{' (quick)' if ctx.quick else ''}; steps: {', '.join(steps)}")
    # The machine and commit the measurements ran on: rewritten only when something is measured
    # at run time (compile_time's own JSON records its compiler, machine and commit).
    if any(x != "compile_time" for x in steps) or not (ctx.results / "machine.json").exists():
        machine = step_machine(ctx)
    else:
        machine = json.loads((ctx.results / "machine.json").read_text())
    data = {}

    def done(name, value, started):
        value["wall_s"] = time.monotonic() - started
        data[name] = value
        # accuracy.json already holds the accuracy rows; the step file keeps the rest.
        kept = {k: v for k, v in value.items() if not (name == "accuracy" and k == "rows")}
        (ctx.results / f"step_{name}.json").write_text(json.dumps(kept, indent=1, default=str))

    if "pair_cost" in steps:
        log("pce-bench (alone on the machine)")
        t = time.monotonic()
        done("pair_cost", step_pair_cost(ctx), t)
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        t = time.monotonic()
        fa = pool.submit(step_accuracy, ctx) if "accuracy" in steps else None
        if fa:
            log("pce-accuracy" + (", with pce-broad-phase-bench on the other core" if "broad_phase" in steps else ""))
        if "broad_phase" in steps:
            bp = step_broad_phase(ctx)
            bp["exponents"] = broad_phase_exponents(bp, ctx.quick)
            done("broad_phase", bp, t)
        if fa:
            done("accuracy", fa.result(), t)
    if "threads" in steps:
        log("threads (one run at a time)")
        t = time.monotonic()
        done("threads", step_threads(ctx), t)
    if "scenes" in steps:
        log(f"scenes ({ctx.jobs} runs at a time)")
        t = time.monotonic()
        scenes = step_scenes(ctx)
        for r in scenes["rows"]:
            r.pop("final_obj", None)
        done("scenes", scenes, t)
    if "hammock" in steps:
        log("hammock before/after (one run at a time)" if ctx.before else "hammock (one run at a time)")
        t = time.monotonic()
        done("hammock", step_hammock(ctx), t)
    if "friction" in steps:
        log("friction: the hammock without and with friction (one run at a time)")
        t = time.monotonic()
        done("friction", step_friction(ctx), t)
    if "compile_time" in steps:
        log("compile time (one compilation at a time)")
        t = time.monotonic()
        done("compile_time", step_compile_time(ctx), t)
    if "scale" in steps:
        log("scale ladder (one run at a time)")
        t = time.monotonic()
        done("scale", step_scale(ctx), t)
    if "block_accuracy" in steps:
        log("block descent's accuracy against time (one run at a time)")
        t = time.monotonic()
        done("block_accuracy", step_block_accuracy(ctx), t)
    for name in ALL_STEPS:  # steps not run now: their last results
        if name not in data:
            f = ctx.results / f"step_{name}.json"
            if not f.exists():
                if name in OPTIONAL_STEPS:  # the page says it was not measured
                    log(f"WARNING: {f} is missing: the page reports step '{name}' as not measured")
                    data[name] = None
                    continue
                raise RuntimeError(f"{f} is missing: run step '{name}' first")
            data[name] = json.loads(f.read_text())
            if name == "accuracy":
                data[name]["rows"] = json.loads((ctx.results / "accuracy.json").read_text())["rows"]
    cost, acc, bp, threads, scenes, hammock, friction, compile_time, scale, block_acc = (data[k] for k in ALL_STEPS)
    total = time.monotonic() - t0
    # The page reports the time the whole pipeline takes: the steps' own times (accuracy and
    # broad phase run side by side, so the longer of the two counts).
    run_total = (data["pair_cost"].get("wall_s", 0) + max(acc.get("wall_s", 0), bp.get("wall_s", 0)) +
                 threads.get("wall_s", 0) + scenes.get("wall_s", 0) + hammock.get("wall_s", 0) +
                 (friction or {}).get("wall_s", 0) + (compile_time or {}).get("wall_s", 0) +
                 (scale or {}).get("wall_s", 0) + (block_acc or {}).get("wall_s", 0))
    log("plots and page")
    plot_pair(ctx, acc, cost)
    plot_scenes(ctx, scenes)
    plot_broad_phase(ctx, bp)
    plot_threads(ctx, threads, scenes)
    block_plots = plot_block_accuracy(ctx, block_acc) if block_acc and block_acc.get("rows") else []
    write_report(ctx, machine, cost, acc, bp, threads, scenes, hammock, friction, compile_time, run_total, scale,
                 block_acc)
    missing = [p for p in [ctx.docs] + [ctx.images / f for f in ("pair_accuracy_cost.png", "scene_pareto.png",
                                                                   "broad_phase_scaling.png", "threads.png")]
               + block_plots if not p.exists() or p.stat().st_size == 0]
    if missing:
        raise RuntimeError("missing outputs: " + ", ".join(map(str, missing)))
    page = ctx.docs.read_text()
    absent = [h for h in ("## What accuracy costs", "## 1. Per pair", "## 2. Per scene", "## 3. Broad phase",
                          "## 4. Threads", "## 5. The hammock", "## 6. Friction's cost on the hammock",
                          "## 7. Compile time", "## 8. Scale ladder", BLOCK_ACCURACY_HEADING)
              if h not in page]
    if absent:
        raise RuntimeError(f"{ctx.docs}: sections missing: {', '.join(absent)}")
    failures = [r for r in scenes["rows"] if r["exit_code"] not in (0,)]
    if failures and ctx.quick:
        raise RuntimeError("scene runs failed: " + "; ".join(f"{r['tag']}: {r['failure']}" for r in failures))
    log(f"done in {total / 60:.1f} min: {ctx.docs}" + (f"; {len(failures)} scene runs ended early (reported)" if failures else ""))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (RuntimeError, ValueError, OSError, KeyError, json.JSONDecodeError) as e:
        print(f"run_all: {e}", file=sys.stderr)
        sys.exit(1)
