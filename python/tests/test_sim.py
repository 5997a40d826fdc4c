# SPDX-License-Identifier: MIT
"""pce.sim: a run from Python writes what pce-sim writes and ends bit for bit where it ends;
stepping, the state's copies, the records; scene errors carry pce-sim's message; bad
arguments raise naming the argument. run(usd=...) writes a USD cache whose points are the
OBJ frames (read with pxr), run(video=...) a movie of one frame per output frame."""

import json
import shutil
import subprocess

import numpy as np
import pytest

import pce

TIMINGS = {"wall_ms", "broad_phase_ms", "pair_ms", "assembly_ms", "solve_ms", "line_search_ms", "effects"}


def without_timings(record):
    """A stats record without its wall-clock fields (the counters' *_ms entries included)."""
    r = {k: v for k, v in record.items() if k not in TIMINGS}
    r["counters"] = {k: v for k, v in record["counters"].items() if not k.endswith("_ms")}
    return r


def obj_vertices(path):
    return np.array([[float(t) for t in line.split()[1:4]] for line in open(path) if line.startswith("v ")])


@pytest.mark.parametrize("scene, frames", [("drape", 4), ("strands", 3), ("twist", 5)])
def test_a_run_from_python_ends_bit_for_bit_where_pce_sim_ends(pce_sim, scenes, tmp_path, scene, frames):
    path = str(scenes / f"{scene}.json")
    cpp, py = tmp_path / "pce-sim", tmp_path / "python"
    subprocess.run(
        [str(pce_sim), path, "--frames", str(frames), "--threads", "1", "--out", str(cpp)],
        check=True, capture_output=True,
    )  # fmt: skip
    s = pce.sim.load(path, frames=frames, threads=1)
    records = s.run(out=py)
    assert s.frame == frames and len(records) == frames and s.stats == records[-1]
    assert sorted(p.name for p in cpp.iterdir()) == sorted(p.name for p in py.iterdir())
    for f in cpp.iterdir():
        if f.suffix in (".obj", ".png"):
            assert f.read_bytes() == (py / f.name).read_bytes(), f.name
    a, b = (json.load(open(d / "stats.json")) for d in (cpp, py))
    assert [without_timings(r) for r in a] == [without_timings(r) for r in b]
    assert [without_timings(json.loads(line)) for line in open(py / "stats.jsonl")] == [without_timings(r) for r in b]
    assert [without_timings(r) for r in records] == [without_timings(r) for r in b]
    sa, sb = (json.load(open(d / "summary.json")) for d in (cpp, py))
    for k in ("total_s", "peak_memory_mib", "mean_ms_per_frame"):
        sa.pop(k), sb.pop(k)
    assert sa == sb
    last = sorted(py.glob("frame_*.obj"))[-1]
    np.testing.assert_array_equal(s.positions, obj_vertices(last))


def test_step_state_and_copies(scenes):
    s = pce.sim.load(scenes / "twist.json", frames=3)
    assert (s.frame, s.frames, s.stats) == (0, 3, None)
    x0 = s.positions
    assert x0.shape == (s.positions.shape[0], 3) and x0.dtype == np.float64
    np.testing.assert_array_equal(s.velocities, 0 * x0)
    x0[:] = 7.0  # a copy: the simulation does not move
    assert not np.any(s.positions == 7.0)
    record = s.step()
    assert record["frame"] == 1 and s.frame == 1 and record is s.stats
    assert record["newton_iterations"] >= 1 and "counters" in record and "intersecting_triangle_pairs" in record
    assert s.time == pytest.approx(s.dt)
    assert np.any(s.positions != pce.sim.load(scenes / "twist.json").positions)
    assert s.run() and s.frame == 3 and s.run() == []  # up to the scene's frames, then nothing
    assert len(s.run(frames=2)) == 2 and s.frame == 5
    assert "twist.json" in repr(s)


def scene_error_of_pce_sim(pce_sim, path):
    r = subprocess.run([str(pce_sim), str(path), "--frames", "1"], capture_output=True, text=True)
    assert r.returncode == 2
    line = r.stderr.strip().splitlines()[-1]
    assert line.startswith("pce-sim: ")
    return line[len("pce-sim: ") :]


def bad_scenes(scenes, tmp_path):
    drape = json.load(open(scenes / "drape.json"))
    yield tmp_path / "missing.json"
    text = tmp_path / "text.json"
    text.write_text("{ not json")
    yield text
    negative = json.loads(json.dumps(drape))
    negative["dt"] = -1
    p = tmp_path / "negative_dt.json"
    p.write_text(json.dumps(negative))
    yield p
    unknown = json.loads(json.dumps(drape))
    unknown["effects"].append({"type": "magnetism"})
    p = tmp_path / "unknown_effect.json"
    p.write_text(json.dumps(unknown))
    yield p
    overlap = json.loads(json.dumps(drape))
    overlap["meshes"].append(json.loads(json.dumps(overlap["meshes"][0])))
    misspelt = json.loads(json.dumps(overlap))
    misspelt["meshes"][-1].setdefault("transform", {})["rotation_deg"] = [0, 0, 30]
    p = tmp_path / "misspelt.json"
    p.write_text(json.dumps(misspelt))
    yield p
    # The copy turned upright about its own centre crosses the sheet: the start state is refused.
    overlap["meshes"][-1]["name"] = "upright"
    transform = overlap["meshes"][-1].setdefault("transform", {})
    transform["rotation"] = {"axis": [1, 0, 0], "degrees": 90}
    p = tmp_path / "crossing.json"
    p.write_text(json.dumps(overlap))
    yield p


def test_scene_errors_carry_pce_sims_message(pce_sim, scenes, tmp_path):
    for path in bad_scenes(scenes, tmp_path):
        expected = scene_error_of_pce_sim(pce_sim, path)
        with pytest.raises(pce.sim.SceneError) as e:
            pce.sim.load(path)
        assert str(e.value) == expected, path.name
        assert isinstance(e.value, ValueError)


@pytest.mark.parametrize(
    "kwargs, error, name",
    [
        ({"frames": 0}, ValueError, "frames"),
        ({"frames": 2.5}, TypeError, "frames"),
        ({"frames": "3"}, TypeError, "frames"),
        ({"hessian": 1}, TypeError, "hessian"),
        ({"hessian": "none"}, ValueError, "hessian"),
        ({"broad_phase": "octree"}, ValueError, "broad_phase"),
        ({"threads": -1}, ValueError, "threads"),
        ({"single_solve": 1}, TypeError, "single_solve"),
        ({"tolerance": 0.0}, ValueError, "tolerance"),
        ({"tolerance": float("nan")}, ValueError, "tolerance"),
        ({"tolerance": "1e-3"}, TypeError, "tolerance"),
        ({"mode": 1}, TypeError, "mode"),
        ({"mode": "vbd"}, ValueError, "mode"),
        ({"mode": "block_descent", "iterations": 0}, ValueError, "iterations"),
        ({"substeps": 0}, ValueError, "substeps"),
        ({"substeps": 2.5}, TypeError, "substeps"),
        ({"mode": "block_descent", "acceleration": "momentum"}, ValueError, "acceleration"),
        ({"mode": "block_descent", "acceleration": 1}, TypeError, "acceleration"),
    ],
)
def test_bad_load_arguments(scenes, kwargs, error, name):
    with pytest.raises(error, match=rf"^{name}\b"):
        pce.sim.load(scenes / "twist.json", **kwargs)


def test_bad_run_arguments(scenes, tmp_path):
    s = pce.sim.load(scenes / "twist.json", frames=2)
    with pytest.raises(ValueError, match="^frames"):
        s.run(frames=-1)
    with pytest.raises(TypeError, match="^out"):
        s.run(out=3)
    with pytest.raises(ValueError, match="^checkpoint_every"):
        s.run(out=tmp_path, checkpoint_every=-2)
    with pytest.raises(TypeError, match="^write_frames"):
        s.run(out=tmp_path, write_frames="no")
    with pytest.raises(TypeError, match="^scene"):
        pce.sim.load(None)
    assert s.frame == 0 and not any(tmp_path.iterdir())  # nothing ran, nothing written


def test_pce_sim_resumes_a_run_python_checkpointed(pce_sim, scenes, tmp_path):
    """The fingerprint of a Python run's checkpoints is pce-sim's (single_solve=False is no
    override): pce-sim --resume goes on from it and ends where an uninterrupted run ends."""
    path = str(scenes / "twist.json")
    straight, resumed = tmp_path / "straight", tmp_path / "resumed"
    subprocess.run([str(pce_sim), path, "--frames", "4", "--threads", "1", "--out", str(straight)], check=True,
                   capture_output=True)  # fmt: skip
    s = pce.sim.load(path, frames=4, threads=1, single_solve=False)
    s.run(frames=2, out=resumed, checkpoint_every=2)
    assert (resumed / "checkpoint_0002.pcecp").is_file()
    subprocess.run([str(pce_sim), path, "--frames", "4", "--threads", "1", "--resume", str(resumed)], check=True,
                   capture_output=True)  # fmt: skip
    assert (resumed / "frame_0004.obj").read_bytes() == (straight / "frame_0004.obj").read_bytes()


def test_iterations_need_block_descent(scenes):
    with pytest.raises(pce.sim.SceneError, match=r"solver\.iterations: a number of sweeps .* needs the block_descent"):
        pce.sim.load(scenes / "twist.json", iterations=5)  # a Newton scene


def test_block_descent_is_pce_sims(pce_sim, scenes, tmp_path):
    """mode= and iterations= are pce-sim's --mode and --iterations: the same frames, bit for bit, each of the
    mode's default 5 substeps."""
    path = str(scenes / "twist.json")
    cli, py = tmp_path / "cli", tmp_path / "py"
    subprocess.run([str(pce_sim), path, "--frames", "3", "--threads", "1", "--mode", "block_descent", "--iterations",
                    "4", "--out", str(cli)], check=True, capture_output=True)  # fmt: skip
    s = pce.sim.load(path, frames=3, threads=1, mode="block_descent", iterations=4)
    s.run(out=py)
    assert (py / "frame_0003.obj").read_bytes() == (cli / "frame_0003.obj").read_bytes()
    assert s.stats["stop"] == "sweeps" and s.stats["substeps"] == 5 and s.stats["newton_iterations"] == 0
    assert s.stats["sweeps"] == 5 * 4


def test_substeps_and_acceleration_are_pce_sims(pce_sim, scenes, tmp_path):
    """substeps= and acceleration= are pce-sim's --substeps and --acceleration: the same frames, bit for bit."""
    path = str(scenes / "twist.json")
    cli, py = tmp_path / "cli", tmp_path / "py"
    subprocess.run([str(pce_sim), path, "--frames", "2", "--threads", "1", "--mode", "block_descent", "--iterations",
                    "3", "--substeps", "2", "--acceleration", "chebyshev", "--out", str(cli)], check=True,
                   capture_output=True)  # fmt: skip
    s = pce.sim.load(path, frames=2, threads=1, mode="block_descent", iterations=3, substeps=2,
                     acceleration="chebyshev")  # fmt: skip
    s.run(out=py)
    assert (py / "frame_0002.obj").read_bytes() == (cli / "frame_0002.obj").read_bytes()
    assert s.stats["substeps"] == 2 and s.stats["sweeps"] == 6
    assert [r["substep"] for r in s.stats["sweep_records"]] == [0, 0, 0, 1, 1, 1]
    assert all("energy" in r for r in s.stats["sweep_records"])


def small_scene(tmp_path):
    """A cloth and two strands falling, a box sliding below them: dt 0.01 s, 5 frames, every
    second frame written (frames 0, 2, 4 and 5)."""
    scene = {
        "dt": 0.01,
        "frames": 5,
        "output_every": 2,
        "meshes": [
            {"name": "cloth", "generator": {"type": "grid", "width": 0.5, "height": 0.5, "nx": 6, "ny": 6}},
            {
                "name": "hair",
                "generator": {"type": "strands", "count": 2, "segments": 4, "length": 0.3, "spacing": 0.2},
                "transform": {"translation": [1, 0, 0.5]},
            },
        ],
        "obstacles": [
            {
                "name": "slider",
                "shape": "box",
                "half_extents": [0.2, 0.2, 0.05],
                "position": [0, 0, -0.3],
                "motion": {"velocity": [0.5, 0, 0]},
            }
        ],
        "effects": [
            {"type": "gravity"},
            {"type": "stretching", "stiffness": 20},
            {"type": "strand_stretching", "stiffness": 20},
        ],
    }
    path = tmp_path / "small.json"
    path.write_text(json.dumps(scene))
    return path


def obj_elements(path, kind):
    """The 0-based vertex indices of an OBJ's `f` (kind "f") or `l` (kind "l") lines."""
    return [[int(t) - 1 for t in line.split()[1:]] for line in open(path) if line.startswith(kind + " ")]


def test_usd_cache_points_are_the_obj_frames(tmp_path):
    Usd = pytest.importorskip("pxr.Usd", reason="usd-core is not installed (the test extra installs it)")
    from pxr import UsdGeom

    s = pce.sim.load(small_scene(tmp_path))
    out = tmp_path / "out"
    s.run(out=out, usd=out / "cache.usda")
    stage = Usd.Stage.Open(str(out / "cache.usda"))
    assert stage.GetTimeCodesPerSecond() == 1 / s.dt == 100
    assert (stage.GetStartTimeCode(), stage.GetEndTimeCode()) == (0, 5)
    assert UsdGeom.GetStageUpAxis(stage) == "Z" and UsdGeom.GetStageMetersPerUnit(stage) == 1
    assert stage.GetDefaultPrim().GetPath() == "/World"
    cloth, hair = UsdGeom.Mesh.Get(stage, "/World/cloth"), UsdGeom.BasisCurves.Get(stage, "/World/hair")
    assert cloth and hair
    frames = sorted(int(p.stem[len("frame_") :]) for p in out.glob("frame_*.obj"))
    assert frames == [0, 2, 4, 5]
    assert cloth.GetPointsAttr().GetTimeSamples() == frames == hair.GetPointsAttr().GetTimeSamples()
    n_cloth = len(cloth.GetPointsAttr().Get(0))
    # Topology once: the OBJ's triangles and strands.
    triangles, segments = obj_elements(out / "frame_0000.obj", "f"), obj_elements(out / "frame_0000.obj", "l")
    assert list(cloth.GetFaceVertexCountsAttr().Get()) == [3] * len(triangles)
    assert list(cloth.GetFaceVertexIndicesAttr().Get()) == [i for t in triangles for i in t]
    assert hair.GetTypeAttr().Get() == "linear"
    assert list(hair.GetCurveVertexCountsAttr().Get()) == [5, 5]
    assert [[a - n_cloth, b - n_cloth] for a, b in segments] == [[k, k + 1] for k in (0, 1, 2, 3, 5, 6, 7, 8)]
    # Points: each time code's are the OBJ frame's vertices rounded to float, exactly.
    for f in frames:
        x = obj_vertices(out / f"frame_{f:04d}.obj").astype(np.float32)
        np.testing.assert_array_equal(np.array(cloth.GetPointsAttr().Get(f), dtype=np.float32), x[:n_cloth])
        np.testing.assert_array_equal(np.array(hair.GetPointsAttr().Get(f), dtype=np.float32), x[n_cloth:])
    # The sliding box: its transform sampled at the same time codes, 0.5 m/s along x.
    box = UsdGeom.Xformable(stage.GetPrimAtPath("/World/obstacles/slider"))
    assert stage.GetPrimAtPath("/World/obstacles/slider/shape").GetTypeName() == "Cube"
    assert box.GetXformOpOrderAttr().Get() == ["xformOp:transform"]
    for f in frames:
        assert box.ComputeLocalToWorldTransform(f).ExtractTranslation()[0] == pytest.approx(0.5 * f * s.dt, abs=1e-12)
    assert not (out / "pce-sim-frames.tmp").exists()


def test_video_has_one_frame_per_output_frame(tmp_path):
    if not (shutil.which("ffmpeg") and shutil.which("ffprobe")):
        pytest.skip("ffmpeg or ffprobe is not installed (Debian: apt-get install ffmpeg)")
    s = pce.sim.load(small_scene(tmp_path))
    movie = tmp_path / "movie.mp4"
    s.run(out=tmp_path / "out", write_frames=False, video=movie)
    probe = subprocess.run(
        ["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
         "stream=nb_read_frames,r_frame_rate,codec_name,pix_fmt", "-of", "json", str(movie)],
        check=True, capture_output=True, text=True,
    )  # fmt: skip
    stream = json.loads(probe.stdout)["streams"][0]
    # Frames 0, 2, 4 and 5 (write_frames=False writes only the last OBJ, the movie has them all).
    assert stream["nb_read_frames"] == "4" and stream["r_frame_rate"] == "50/1"
    assert (stream["codec_name"], stream["pix_fmt"]) == ("h264", "yuv420p")


def test_bad_video_and_usd_arguments(tmp_path, monkeypatch):
    s = pce.sim.load(small_scene(tmp_path))
    out = tmp_path / "out"
    (tmp_path / "file").write_text("x")
    with pytest.raises(TypeError, match="^video: expected a file path"):
        s.run(out=out, video=3)
    with pytest.raises(TypeError, match="^usd: expected a file path"):
        s.run(out=out, usd=b"cache.usda")
    with pytest.raises(ValueError, match=r"^usd: needs out="):
        s.run(usd=tmp_path / "cache.usda")
    with pytest.raises(ValueError, match=r"^video: .*: is a directory$"):
        s.run(out=out, video=tmp_path)
    with pytest.raises(ValueError, match=r"^usd: .*cache\.txt: expected a file name ending in \.usda or \.usd$"):
        s.run(out=out, usd=tmp_path / "cache.txt")
    with pytest.raises(ValueError, match=r"^usd: .*: .*file is not a directory$"):
        s.run(out=out, usd=tmp_path / "file" / "cache.usda")
    empty = tmp_path / "empty"
    empty.mkdir()
    monkeypatch.setenv("PATH", str(empty))
    with pytest.raises(RuntimeError, match=r"^video: ffmpeg not found on PATH; .*apt-get install ffmpeg"):
        s.run(out=out, video=tmp_path / "movie.mp4")
    assert s.frame == 0 and not out.exists()  # nothing ran, nothing written
