# SPDX-License-Identifier: MIT
"""pce.sim.from_dict and control between steps: a scene built as a dict with meshes from NumPy
arrays runs bit for bit as the same scene written as a JSON file (positions, velocities, the
OBJ frames); bad arrays raise naming the mesh and the field, bad elements the loader's error;
positions and velocities are copies, the velocities (x - x_prev)/dt; a pin group's target set
each frame is followed, an obstacle put each frame pushes a sheet, and the bad arguments of
both raise naming the argument."""

import json
import subprocess

import numpy as np
import pytest

import pce


def grid(nx, ny, width, height, jitter=0.0, seed=1):
    """A rectangle in z = 0 centred at the origin: (nx+1)(ny+1) vertices, 2 nx ny triangles,
    the vertices moved by up to `jitter` in z (full-precision floats)."""
    xs, ys = np.linspace(-width / 2, width / 2, nx + 1), np.linspace(-height / 2, height / 2, ny + 1)
    x, y = np.meshgrid(xs, ys)
    z = np.random.default_rng(seed).uniform(-jitter, jitter, x.shape)
    vertices = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    triangles = []
    for j in range(ny):
        for i in range(nx):
            a, b, c, d = j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i
            triangles += [[a, b, c], [a, c, d]]
    return vertices, np.array(triangles, dtype=np.int32)


def strand(segments, length, origin):
    """A straight strand hanging from `origin` along -z with a slight helix."""
    t = np.arange(segments + 1) / segments
    vertices = np.stack([origin[0] + 0.01 * np.sin(7 * t), origin[1] + 0.01 * np.cos(7 * t), origin[2] - length * t], 1)
    return vertices, np.stack([np.arange(segments), np.arange(1, segments + 1)], axis=1)


def two_mesh_scene(frames):
    """A cloth and a strand from NumPy arrays, with pins, a ball and contact."""
    cloth_v, cloth_t = grid(6, 5, 0.6, 0.5, jitter=1e-3)
    hair_v, hair_s = strand(8, 0.3, (0.5, 0.0, 0.2))
    return {
        "description": "from NumPy arrays",
        "dt": 0.01,
        "frames": frames,
        "meshes": [
            {"name": "cloth", "vertices": cloth_v, "triangles": cloth_t, "density": 0.2},
            {"name": "hair", "vertices": hair_v.astype(np.float32), "segments": hair_s.astype(np.uint16)},
        ],
        "obstacles": [
            {"name": "ball", "shape": "sphere", "radius": np.float64(0.1), "position": np.array([0, 0, -0.2])}
        ],
        "effects": [
            {"type": "gravity"},
            {"type": "stretching", "stiffness": 50},
            {"type": "bending", "stiffness": 1e-4},
            {"type": "strand_stretching", "stiffness": 10},
            {"type": "strand_bending", "stiffness": 1e-5},
            {"type": "pins", "groups": [{"mesh": "cloth", "vertices": [0, 6]}, {"mesh": "hair", "vertices": [0]}]},
            {"type": "obstacle_contact", "penalty": {"type": "quadratic", "stiffness": 1e4, "distance": 0.01}},
        ],
    }


def as_json_lists(scene):
    """The same scene with every array as lists (what a scene file written by hand holds)."""
    if isinstance(scene, dict):
        return {k: as_json_lists(v) for k, v in scene.items()}
    if isinstance(scene, list):
        return [as_json_lists(v) for v in scene]
    if isinstance(scene, (np.ndarray, np.generic)):
        return scene.tolist()
    return scene


def test_from_dict_runs_bit_for_bit_as_the_same_scene_file(tmp_path):
    frames = 12
    scene = two_mesh_scene(frames)
    path = tmp_path / "scene.json"
    with open(path, "w") as f:
        json.dump(as_json_lists(scene), f)
    a, b = pce.sim.from_dict(scene), pce.sim.load(path)
    assert a.frames == frames and repr(a).startswith("<pce.sim.Simulation '<dict>'")
    assert np.array_equal(a.positions, b.positions)
    assert a.positions[: len(scene["meshes"][0]["vertices"])].tolist() == scene["meshes"][0]["vertices"].tolist()
    for _ in range(frames):
        a.step()
        b.step()
        assert np.array_equal(a.positions, b.positions) and np.array_equal(a.velocities, b.velocities)
    moved = np.abs(a.positions - pce.sim.from_dict(scene).positions).max()
    assert moved > 1e-3  # it did fall
    # The same through run(out=...): the OBJ frames are the same bytes.
    c, d = pce.sim.from_dict(scene, frames=3), pce.sim.load(path, frames=3)
    c.run(out=tmp_path / "dict")
    d.run(out=tmp_path / "file")
    names = sorted(p.name for p in (tmp_path / "dict").glob("frame_*.obj"))
    assert names == sorted(p.name for p in (tmp_path / "file").glob("frame_*.obj")) and len(names) == 4
    for n in names:
        assert (tmp_path / "dict" / n).read_bytes() == (tmp_path / "file" / n).read_bytes(), n
    assert json.load(open(tmp_path / "dict" / "summary.json"))["scene"] == "<dict>"


def test_scene_json_writes_floats_exactly():
    v = np.array([[0.1, 1 / 3, np.nextafter(1.0, 2.0)], [1e-300, -2.5e-7, np.pi]])
    text = pce.sim.scene_json({"meshes": [{"name": "m", "vertices": v, "segments": np.array([[0, 1]])}]})
    assert np.array_equal(np.array(json.loads(text)["meshes"][0]["vertices"]), v)


def test_pce_sim_resumes_a_from_dict_run_from_the_scene_json_file(pce_sim, tmp_path):
    """A from_dict run's checkpoints are fingerprinted with scene_json's text: pce-sim resumes
    them from a file holding that text and ends where from_dict's uninterrupted run ends."""
    scene = two_mesh_scene(4)
    path = tmp_path / "scene.json"
    path.write_text(pce.sim.scene_json(scene))
    straight = pce.sim.from_dict(scene, threads=1)
    straight.run(out=tmp_path / "straight")
    pce.sim.from_dict(scene, threads=1).run(frames=2, out=tmp_path / "resumed", checkpoint_every=2)
    subprocess.run([str(pce_sim), str(path), "--threads", "1", "--resume", str(tmp_path / "resumed")], check=True,
                   capture_output=True)  # fmt: skip
    last = (tmp_path / "resumed" / "frame_0004.obj").read_bytes()
    assert last == (tmp_path / "straight" / "frame_0004.obj").read_bytes()


def test_from_dict_reads_mesh_files_from_base(tmp_path):
    (tmp_path / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    scene = {"dt": 0.01, "frames": 1, "meshes": [{"name": "m", "file": "tri.obj"}], "effects": [{"type": "gravity"}]}
    assert pce.sim.from_dict(scene, base=tmp_path).positions.shape == (3, 3)
    with pytest.raises(pce.sim.SceneError, match=r"^<dict>: meshes\[0\]\.file: mesh file not found"):
        pce.sim.from_dict(scene, base=tmp_path / "elsewhere")
    with pytest.raises(TypeError, match="base: expected a directory path"):
        pce.sim.from_dict(scene, base=3)
    with pytest.raises(ValueError, match="mode: expected one of"):
        pce.sim.from_dict(scene, mode="fast")


def cloth_scene(**mesh):
    v, t = grid(3, 2, 0.3, 0.2)
    m = {"name": "cloth", "vertices": v, "triangles": t}
    m.update(mesh)
    return {"dt": 0.01, "frames": 1, "meshes": [m], "effects": [{"type": "gravity"}]}


@pytest.mark.parametrize(
    "mesh, error, message",
    [
        ({"triangles": np.zeros((2, 3))}, TypeError,
         "meshes[0].triangles (mesh 'cloth'): expected an array of integer vertex indices, got dtype float64"),
        ({"vertices": np.zeros((4, 2))}, ValueError,
         "meshes[0].vertices (mesh 'cloth'): expected an array of shape (n, 3), got shape (4, 2)"),
        ({"vertices": np.array([["a", "b", "c"]])}, TypeError, "meshes[0].vertices (mesh 'cloth'): expected an array of numbers"),
        ({"vertices": np.array([[0, 0, 0], [0, np.nan, 0]])}, ValueError,
         "meshes[0].vertices[1][1] (mesh 'cloth'): expected a finite number, got nan"),
        ({"segments": np.arange(6)}, ValueError, "meshes[0].segments (mesh 'cloth'): expected an array of shape (n, 2)"),
        ({"tetrahedra": np.array([[0, 1, 2, 3]], dtype=bool)}, TypeError, "meshes[0].tetrahedra (mesh 'cloth'): expected"),
        ({"vertices": [[0, 0, 0], [1, 0, float("inf")]]}, ValueError, "meshes[0].vertices[1][2]: expected a finite number, got inf"),
        ({"density": {1, 2}}, TypeError, "meshes[0].density: expected JSON data"),
        ({"triangles": np.array([[0, 1, 2], [0, 1, 12]])}, pce.sim.SceneError,
         "<dict>: meshes[0].triangles[1][2]: expected a vertex index in [0, 12), got 12"),
        ({"triangles": np.array([[0, 1, 1]])}, pce.sim.SceneError,
         "<dict>: meshes[0].triangles[0]: the triangle uses vertex 1 twice"),
        ({"vertices": np.full((12, 3), 2e6)}, pce.sim.SceneError, "<dict>: meshes[0].vertices[0][0]: expected a number in"),
    ],
)  # fmt: skip
def test_from_dict_errors_name_the_mesh_and_the_field(mesh, error, message):
    with pytest.raises(error) as e:
        pce.sim.from_dict(cloth_scene(**mesh))
    assert str(e.value).startswith(message), str(e.value)


def test_from_dict_refuses_what_json_cannot_hold():
    with pytest.raises(TypeError, match="scene: expected a dict"):
        pce.sim.from_dict([1, 2])
    with pytest.raises(TypeError, match="scene: expected string keys"):
        pce.sim.from_dict({1: 2})
    scene = cloth_scene()
    scene["obstacles"] = [{"name": "b", "shape": "sphere", "radius": 0.1, "position": [0, 0, float("nan")]}]
    with pytest.raises(ValueError, match=r"^obstacles\[0\]\.position\[2\]: expected a finite number, got nan"):
        pce.sim.from_dict(scene)


def test_positions_and_velocities_are_copies_and_velocities_the_last_step_over_dt():
    s = pce.sim.from_dict(cloth_scene(), frames=3)
    for _ in range(3):
        x_prev = s.positions
        s.step()
        x, v = s.positions, s.velocities
        assert np.array_equal(v, (x - x_prev) / s.dt)
        assert x.flags.writeable and v.flags.writeable
        v[:] = 0.0
        x[:] = 0.0
        assert not np.array_equal(s.velocities, v) and not np.array_equal(s.positions, x)
    assert s.positions is not s.positions


def pinned_sheet(frames, stiffness):
    v, t = grid(8, 8, 0.4, 0.4)
    return {
        "dt": 0.01,
        "frames": frames,
        "meshes": [{"name": "sheet", "vertices": v, "triangles": t, "density": 0.1}],
        "effects": [
            {"type": "gravity"},
            {"type": "stretching", "stiffness": 20},
            {"type": "bending", "stiffness": 1e-4},
            {"type": "damping", "coefficient": 1},
            {
                "type": "pins",
                "stiffness": stiffness,
                "groups": [{"vertices": [0]}, {"vertices": [8, 80], "release_frame": 2}],
            },
        ],
    }


def test_a_sheet_pinned_at_a_corner_follows_the_target_python_moves_each_frame():
    k, frames = 1e5, 40
    s = pce.sim.from_dict(pinned_sheet(frames, k))
    corner = s.pin_vertices(0)
    assert corner.tolist() == [0] and s.pin_vertices(1).tolist() == [8, 80]
    rest = s.positions[0].copy()
    np.testing.assert_array_equal(s.pin_targets(0), [rest])
    # Held flat by three corners for the first step, the sheet then swings down from corner 0,
    # a pendulum released from the horizontal: its pivot pulls at most 3 m g (2.57 m g here).
    mass = 0.1 * 0.4 * 0.4
    tolerance = 3 * mass * 9.81 / k
    for f in range(1, frames + 1):
        target = rest + [0.005 * f, 0.0, 0.01 * f]  # 0.5 m/s along x, 1 m/s up
        s.set_pin_targets(0, [target])
        np.testing.assert_array_equal(s.pin_targets(0), [target])
        s.step()
        off = np.linalg.norm(s.positions[0] - target)
        assert off < tolerance, f"frame {f}: {off} m from the target (tolerance {tolerance})"
    assert s.positions[0][2] > 0.39  # it went 0.4 m up with the corner
    # Cleared: the group's rest position again, from the next step on.
    s.set_pin_targets(0, None)
    s.step()
    np.testing.assert_array_equal(s.pin_targets(0), [rest])


def test_bad_pin_target_arguments():
    s = pce.sim.from_dict(pinned_sheet(1, 1e4))
    with pytest.raises(ValueError, match=r"targets: expected shape \(2, 3\), one row per vertex of pin group 1"):
        s.set_pin_targets(1, [[0, 0, 0]])
    with pytest.raises(TypeError, match="targets: expected an array of numbers"):
        s.set_pin_targets(0, [["a", "b", "c"]])
    with pytest.raises(ValueError, match=r"targets\[0\]: expected"):
        s.set_pin_targets(0, [[0, 0, np.inf]])
    with pytest.raises(ValueError, match=r"targets\[1\]: expected"):
        s.set_pin_targets(1, [[0, 0, 0], [0, 2e6, 0]])
    with pytest.raises(ValueError, match=r"group: expected a pin group index in \[0, 2\), got 2"):
        s.set_pin_targets(2, [[0, 0, 0]])
    with pytest.raises(TypeError, match="group: expected an integer"):
        s.pin_targets(1.0)
    with pytest.raises(ValueError, match="entry: expected the index of one of the scene's 1 pins entries, got 1"):
        s.pin_vertices(0, entry=1)
    np.testing.assert_array_equal(s.pin_targets(1), s.positions[[8, 80]])  # nothing was set


def ball_and_sheet(frames):
    v, t = grid(12, 12, 0.6, 0.6)
    return {
        "dt": 0.01,
        "frames": frames,
        "meshes": [{"name": "sheet", "vertices": v, "triangles": t}],
        "obstacles": [{"name": "ball", "shape": "sphere", "radius": 0.1, "position": [0, 0, -0.3]}],
        "effects": [
            {"type": "stretching", "stiffness": 100},
            {"type": "bending", "stiffness": 1e-4},
            {"type": "damping", "coefficient": 2},
            {"type": "pins", "stiffness": 1e4, "groups": [
                {"box": {"min": [-1, -1, -1], "max": [-0.29, 1, 1]}}, {"box": {"min": [0.29, -1, -1], "max": [1, 1, 1]}}]},
            {"type": "obstacle_contact", "penalty": {"type": "quadratic", "stiffness": 1e4, "distance": 0.005}},
        ],
    }  # fmt: skip


def test_an_obstacle_python_moves_into_a_sheet_pushes_it():
    frames = 40
    s = pce.sim.from_dict(ball_and_sheet(frames))
    assert s.obstacles == ["ball"]
    centre = int(np.argmin(np.linalg.norm(s.positions, axis=1)))
    contacts = 0
    z = -0.3
    for f in range(1, frames + 1):
        before, z = z, -0.3 + min(0.01 * f, 0.25)  # rises 1 cm a frame, then holds with its top at z = 0.05
        s.set_obstacle_pose("ball", translation=[0, 0, z])
        assert s.obstacle_pose("ball")[0].tolist() == [0, 0, before]  # from the next step on
        contacts += s.step()["counters"].get("obstacle_contacts", 0)
        translation, rotation = s.obstacle_pose("ball")
        assert translation.tolist() == [0, 0, z] and rotation.tolist() == np.eye(3).tolist()
    assert contacts > 0
    assert s.positions[centre][2] > 0.045  # pushed up onto the ball's top, 5 cm above the rest plane
    # A rotation as a scene's axis and degrees, or as a matrix; the translation kept.
    s.set_obstacle_pose("ball", rotation={"axis": [0, 0, 1], "degrees": 90})
    s.step()
    translation, rotation = s.obstacle_pose("ball")
    assert translation.tolist() == [0, 0, z]
    np.testing.assert_allclose(rotation, [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)
    s.set_obstacle_pose("ball", rotation=np.eye(3))
    s.step()
    assert s.obstacle_pose("ball")[1].tolist() == np.eye(3).tolist()


def test_bad_obstacle_pose_arguments():
    s = pce.sim.from_dict(ball_and_sheet(1))
    with pytest.raises(ValueError, match=r"name: no obstacle named 'wall' \(the obstacles: 'ball'\)"):
        s.set_obstacle_pose("wall", translation=[0, 0, 0])
    with pytest.raises(ValueError, match="name: no obstacle named 'wall'"):
        s.obstacle_pose("wall")
    with pytest.raises(ValueError, match=r"translation: expected shape \(3,\)"):
        s.set_obstacle_pose("ball", translation=[0, 0])
    with pytest.raises(ValueError, match="translation: "):
        s.set_obstacle_pose("ball", translation=[0, 0, 2e6])
    with pytest.raises(ValueError, match=r"rotation: expected a rotation matrix \(orthonormal, determinant 1\)"):
        s.set_obstacle_pose("ball", rotation=-np.eye(3))
    with pytest.raises(ValueError, match="rotation: expected a finite, non-zero axis"):
        s.set_obstacle_pose("ball", rotation={"axis": [0, 0, 0], "degrees": 10})
    with pytest.raises(ValueError, match="rotation: expected"):
        s.set_obstacle_pose("ball", rotation={"axis": [0, 0, 1]})
    with pytest.raises(TypeError, match="rotation: expected numbers"):
        s.set_obstacle_pose("ball", rotation="up")
    with pytest.raises(TypeError, match="name: expected an obstacle name"):
        s.set_obstacle_pose(0)
    assert s.obstacle_pose("ball")[0].tolist() == [0, 0, -0.3]
    s.step()
    assert s.obstacle_pose("ball")[0].tolist() == [0, 0, -0.3]  # none of them was kept
