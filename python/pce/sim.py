# SPDX-License-Identifier: MIT
"""The simulator from Python: load a scene file or a scene built as a dict (meshes from NumPy
arrays), step it, read its state, move its pins' targets and its obstacles between steps, or
run it and write what ``pce-sim`` writes (docs/python.md, docs/simulation.md).

Scene errors raise :class:`SceneError` with the message ``pce-sim`` prints (after its
``pce-sim:`` prefix); a frame that fails raises :class:`SimulationError`.
"""

from __future__ import annotations

import json
import math
import numbers
import os
from typing import List, Optional, Tuple

import numpy as np

from . import _pce

__all__ = ["load", "from_dict", "scene_json", "Simulation", "SceneError", "SimulationError", "keep_freed_memory"]

#: An invalid scene or mesh file, or a start state the scene does not allow (a ValueError).
SceneError = _pce.SceneError
#: A frame failed (non-finite state, failed solve; a RuntimeError): the frames before it are kept.
SimulationError = _pce.SimulationError
#: glibc keeps freed memory for reuse, as ``pce-sim`` makes it do (process-wide, so opt in):
#: faster linear solves on large scenes, at the price of keeping the peak heap.
keep_freed_memory = _pce.keep_freed_memory

# The accepted names, from the compiled module's tables (pce::sim::kContactHessians, kBroadPhaseNames).
_HESSIANS = tuple(_pce._contact_hessians())
_BROAD_PHASES = tuple(_pce._broad_phases())
_MODES = tuple(_pce._solver_modes())
_ACCELERATIONS = tuple(_pce._accelerations())


def _numbers(name, value, shape):
    """``value`` as a float64 array of ``shape``: TypeError unless numbers, ValueError for another shape."""
    a = np.asarray(value)
    if a.dtype.kind not in "fiu":
        raise TypeError(f"{name}: expected numbers, got {value!r}")
    if a.shape != shape:
        raise ValueError(f"{name}: expected shape {shape}, got shape {a.shape}")
    return a.astype(np.float64)


def _optional_int(name, value, low, high):
    """None, or `value` as an int: TypeError if it is not an integer, ValueError if it is not in [low, high]."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}: expected an integer in [{low}, {high}], got {value!r}")
    if not low <= value <= high:
        raise ValueError(f"{name}: expected an integer in [{low}, {high}], got {value!r}")
    return int(value)


def load(
    scene,
    *,
    frames: Optional[int] = None,
    hessian: Optional[str] = None,
    broad_phase: Optional[str] = None,
    threads: Optional[int] = None,
    single_solve: Optional[bool] = None,
    tolerance: Optional[float] = None,
    mode: Optional[str] = None,
    iterations: Optional[int] = None,
    substeps: Optional[int] = None,
    acceleration: Optional[str] = None,
) -> "Simulation":
    """Loads a scene file (JSON, docs/simulation.md §2) at frame 0.

    The keyword arguments override the scene as ``pce-sim``'s options do: ``frames``
    (``--frames``), ``hessian`` (``--hessian``: every contact effect's strategy),
    ``broad_phase`` (``--broad-phase``: "fcl", "bullet", "brute"), ``threads`` (``--threads``,
    0: all), ``single_solve`` (``--single-solve``), ``tolerance`` (``--tolerance``),
    ``mode`` (``--mode``: "newton", "single_solve", "block_descent"; wins over
    ``single_solve``), ``iterations`` (``--iterations``: block descent's sweeps per step),
    ``substeps`` (``--substeps``: time steps per frame, 1 to 1000), ``acceleration``
    (``--acceleration``: block descent's, "none" or "chebyshev").

    Raises :class:`SceneError` (the message ``pce-sim`` prints) for an invalid scene, and
    for a start state with intersecting meshes unless the scene allows it.
    """
    if not isinstance(scene, (str, os.PathLike)):
        raise TypeError(f"scene: expected a path, got {scene!r}")
    options = _overrides(frames, hessian, broad_phase, threads, single_solve, tolerance, mode, iterations, substeps,
                         acceleration)
    return Simulation(_pce._load(os.fspath(scene), *options))


def from_dict(
    scene,
    *,
    base=".",
    frames: Optional[int] = None,
    hessian: Optional[str] = None,
    broad_phase: Optional[str] = None,
    threads: Optional[int] = None,
    single_solve: Optional[bool] = None,
    tolerance: Optional[float] = None,
    mode: Optional[str] = None,
    iterations: Optional[int] = None,
    substeps: Optional[int] = None,
    acceleration: Optional[str] = None,
) -> "Simulation":
    """Loads a scene given as a dict (the scene format of docs/simulation.md §2) at frame 0.

    A mesh may be written inline with NumPy arrays (or nested lists): ``vertices`` (n, 3)
    numbers, and ``triangles`` (m, 3), ``segments`` (k, 2) or ``tetrahedra`` (t, 4) integer
    vertex indices from 0; any other value may be a NumPy array or scalar too. The dict is
    written as JSON text (:func:`scene_json`; every float exactly, as Python's ``repr``) and
    loaded by the same loader as :func:`load`: a scene file holding that text runs the same,
    bit for bit. Its errors name the file ``<dict>``; relative mesh ``file`` paths start
    from ``base``. The keyword overrides are :func:`load`'s.

    Raises TypeError or ValueError (naming the mesh and the field) for an array of the wrong
    kind or shape or a number that is not finite, before loading; then :class:`SceneError`
    as :func:`load` does.
    """
    if not isinstance(base, (str, os.PathLike)):
        raise TypeError(f"base: expected a directory path, got {base!r}")
    options = _overrides(frames, hessian, broad_phase, threads, single_solve, tolerance, mode, iterations, substeps,
                         acceleration)
    text = scene_json(scene)
    return Simulation(_pce._load_text(text, "<dict>", os.fsdecode(os.fspath(base)), *options))


# The inline mesh fields: (columns, NumPy kinds accepted, what an element is).
_MESH_ARRAYS = {
    "vertices": (3, "fiu", "numbers"),
    "triangles": (3, "iu", "integer vertex indices"),
    "segments": (2, "iu", "integer vertex indices"),
    "tetrahedra": (4, "iu", "integer vertex indices"),
}


def scene_json(scene) -> str:
    """The JSON text :func:`from_dict` loads for ``scene`` (a dict in the scene format): NumPy
    arrays as nested lists, NumPy scalars as numbers, floats written exactly (``repr``).
    Written to a file, it is a scene ``pce-sim`` runs (and resumes: the checkpoints of a run
    from :func:`from_dict` are fingerprinted with this text).

    Raises TypeError for something JSON cannot hold, a mesh array of the wrong dtype (a
    ``vertices`` array of numbers, index arrays of integers), ValueError for a mesh array of
    the wrong shape or a number that is not finite; each names the field
    (``meshes[1].triangles (mesh 'strand'): ...``).
    """
    if not isinstance(scene, dict):
        raise TypeError(f"scene: expected a dict, got {type(scene).__name__}")
    meshes = scene.get("meshes")
    checked = {}
    if isinstance(meshes, (list, tuple)):
        for i, mesh in enumerate(meshes):
            if not isinstance(mesh, dict):
                continue  # the loader names it
            name = mesh.get("name")
            where = f" (mesh {name!r})" if isinstance(name, str) else ""
            for key, (columns, kinds, what) in _MESH_ARRAYS.items():
                value = mesh.get(key)
                if isinstance(value, np.ndarray):
                    checked[id(value)] = _mesh_array(f"meshes[{i}].{key}", where, value, columns, kinds, what)
    return json.dumps(_plain(scene, "scene", checked), allow_nan=False)


def _mesh_array(field, where, a, columns, kinds, what):
    """Array ``a`` of mesh field ``field`` (``where`` names the mesh) as nested lists: TypeError
    unless its dtype is one of ``kinds``, ValueError unless its shape is (n, columns) and every
    value is finite."""
    if a.dtype.kind not in kinds:
        raise TypeError(f"{field}{where}: expected an array of {what}, got dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] != columns:
        raise ValueError(f"{field}{where}: expected an array of shape (n, {columns}), got shape {a.shape}")
    if a.dtype.kind == "f":
        bad = np.argwhere(~np.isfinite(a))
        if len(bad):
            r, c = bad[0]
            raise ValueError(f"{field}[{r}][{c}]{where}: expected a finite number, got {float(a[r, c])!r}")
    return a.tolist()


def _plain(value, path, checked):
    """``value`` as what ``json.dumps`` writes: NumPy arrays as lists, NumPy scalars as
    Python numbers; TypeError for anything else JSON cannot hold, ValueError for a float
    that is not finite, naming its path."""
    if isinstance(value, dict):
        out = {}
        for key, item in value.items():
            if not isinstance(key, str):
                raise TypeError(f"{path}: expected string keys, got {key!r}")
            out[key] = _plain(item, f"{key}" if path == "scene" else f"{path}.{key}", checked)
        return out
    if isinstance(value, np.ndarray):
        if id(value) in checked:
            return checked[id(value)]
        if value.dtype.kind not in "biuf":
            raise TypeError(f"{path}: expected an array of numbers, got dtype {value.dtype}")
        return _plain(value.tolist(), path, checked)
    if isinstance(value, (list, tuple)):
        return [_plain(item, f"{path}[{k}]", checked) for k, item in enumerate(value)]
    if isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, (str, bool, int)):
        return value
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{path}: expected a finite number, got {value!r}")
        return value
    raise TypeError(
        f"{path}: expected JSON data (dict, list, str, number, bool, None) or a NumPy array, got {type(value).__name__}"
    )


def _overrides(frames, hessian, broad_phase, threads, single_solve, tolerance, mode, iterations, substeps,
               acceleration):
    """The keyword overrides of :func:`load`, checked, in the order ``_pce._load`` takes them."""
    frames = _optional_int("frames", frames, 1, 10_000_000)
    threads = _optional_int("threads", threads, 0, 1024)
    for name, value in (("hessian", hessian), ("broad_phase", broad_phase)):
        if value is not None and not isinstance(value, str):
            raise TypeError(f"{name}: expected a string, got {value!r}")
    if hessian is not None and hessian not in _HESSIANS:
        raise ValueError(f"hessian: expected one of {', '.join(_HESSIANS)}, got {hessian!r}")
    if broad_phase is not None and broad_phase not in _BROAD_PHASES:
        raise ValueError(f"broad_phase: expected one of {', '.join(_BROAD_PHASES)}, got {broad_phase!r}")
    iterations = _optional_int("iterations", iterations, 1, 100_000)
    substeps = _optional_int("substeps", substeps, 1, 1000)
    if mode is not None and not isinstance(mode, str):
        raise TypeError(f"mode: expected a string, got {mode!r}")
    if mode is not None and mode not in _MODES:
        raise ValueError(f"mode: expected one of {', '.join(_MODES)}, got {mode!r}")
    if acceleration is not None and not isinstance(acceleration, str):
        raise TypeError(f"acceleration: expected a string, got {acceleration!r}")
    if acceleration is not None and acceleration not in _ACCELERATIONS:
        raise ValueError(f"acceleration: expected one of {', '.join(_ACCELERATIONS)}, got {acceleration!r}")
    if single_solve is not None and not isinstance(single_solve, bool):
        raise TypeError(f"single_solve: expected True or False, got {single_solve!r}")
    if tolerance is not None:
        if isinstance(tolerance, bool) or not isinstance(tolerance, numbers.Real):
            raise TypeError(f"tolerance: expected a number > 0, got {tolerance!r}")
        if not 0 < tolerance < float("inf"):
            raise ValueError(f"tolerance: expected a finite number > 0, got {tolerance!r}")
        tolerance = float(tolerance)
    return frames, hessian, broad_phase, threads, single_solve, tolerance, mode, iterations, substeps, acceleration


class Simulation:
    """A loaded scene. Made by :func:`load`."""

    def __init__(self, loaded):
        self._s = loaded
        self._stats: Optional[dict] = None
        self._stats_text = ""

    @property
    def positions(self) -> np.ndarray:
        """(V, 3) float64: every deformable vertex's position now. A new copy each time it is
        read: it does not change when the simulation steps, and writing to it does not move
        the simulation."""
        return self._s.positions()

    @property
    def velocities(self) -> np.ndarray:
        """(V, 3) float64: the vertices' velocities now, (x − x_prev)/dt of the last step
        (zero before the first); a copy, as ``positions``."""
        return self._s.velocities()

    # --- control between steps -------------------------------------------------------

    def pin_vertices(self, group: int, *, entry: int = 0) -> np.ndarray:
        """(k,) int: the vertices (rows of :attr:`positions`) of pin group ``group`` (an index
        of the ``groups`` of the scene's ``entry``-th ``pins`` entry), in the group's order."""
        return np.array(self._s.pin_vertices(*self._pin_group(group, entry)), dtype=np.int64)

    def pin_targets(self, group: int, *, entry: int = 0) -> np.ndarray:
        """(k, 3) float64: pin group ``group``'s targets, one row per vertex of
        :meth:`pin_vertices`: those set by :meth:`set_pin_targets`, else the last step's (its
        rest positions or its motion's; the rest positions before the first step). A copy."""
        return self._s.pin_targets(*self._pin_group(group, entry))

    def set_pin_targets(self, group: int, targets, *, entry: int = 0) -> None:
        """From the next step on, pin group ``group`` pulls its vertices to ``targets`` ((k, 3)
        numbers, one row per vertex of :meth:`pin_vertices`) at the end of every step instead
        of to its rest positions or its motion, until set again; ``targets=None`` gives the
        group its rest positions or motion back. A released group stays released. Not in a
        checkpoint.

        Raises TypeError for targets that are not numbers, ValueError for another shape, a
        coordinate that is not finite or beyond ±1e6 m, or a group or entry that is none.
        """
        entry, group = self._pin_group(group, entry)
        if targets is not None:
            targets = np.asarray(targets)
            if targets.dtype.kind not in "fiu":
                raise TypeError(f"targets: expected an array of numbers, got dtype {targets.dtype}")
            count = len(self._s.pin_vertices(entry, group))
            if targets.shape != (count, 3):
                raise ValueError(
                    f"targets: expected shape ({count}, 3), one row per vertex of pin group {group}, "
                    f"got shape {targets.shape}"
                )
            targets = np.ascontiguousarray(targets, dtype=np.float64)
        self._s.set_pin_targets(entry, group, targets)

    @property
    def obstacles(self) -> List[str]:
        """The scene's obstacle names, in scene order."""
        return list(self._s.obstacle_names())

    def obstacle_pose(self, name: str) -> Tuple[np.ndarray, np.ndarray]:
        """Obstacle ``name``'s pose now, ``(translation, rotation)``: its centre (3,) and its
        rotation matrix (3, 3), x_world = rotation @ x_local + translation."""
        if not isinstance(name, str):
            raise TypeError(f"name: expected an obstacle name, got {name!r}")
        translation, rotation = self._s.obstacle_pose(name)
        return np.array(translation), np.array(rotation).reshape(3, 3)

    def set_obstacle_pose(self, name: str, translation=None, rotation=None) -> None:
        """From the next step on, obstacle ``name`` is at this pose (its motion replaced, until
        set again): ``translation`` its centre (3 numbers), ``rotation`` a rotation matrix
        (3, 3) or ``{"axis": [x, y, z], "degrees": d}`` as in a scene; a part not given stays
        as it is now (:meth:`obstacle_pose`). Every ``obstacle_contact`` entry with the
        obstacle pushes out of it there at the end of the next step, its friction sees the
        surface move there from where it is now, and output draws it there. Not in a
        checkpoint.

        Raises TypeError for arguments of the wrong kind, ValueError for an unknown name, a
        translation that is not finite or beyond ±1e6 m, or a rotation that is not one.
        """
        if not isinstance(name, str):
            raise TypeError(f"name: expected an obstacle name, got {name!r}")
        if translation is not None:
            translation = _numbers("translation", translation, (3,))
        axis = degrees = None
        if isinstance(rotation, dict):
            if set(rotation) != {"axis", "degrees"}:
                raise ValueError(f"rotation: expected {{'axis': [x, y, z], 'degrees': d}}, got keys {sorted(rotation)}")
            axis = _numbers("rotation axis", rotation["axis"], (3,))
            degrees = rotation["degrees"]
            if isinstance(degrees, bool) or not isinstance(degrees, numbers.Real):
                raise TypeError(f"rotation degrees: expected a number, got {degrees!r}")
            degrees, rotation = float(degrees), None
        elif rotation is not None:
            rotation = _numbers("rotation", rotation, (3, 3)).ravel().tolist()
        self._s.set_obstacle_pose(
            name,
            None if translation is None else translation.tolist(),
            rotation,
            None if axis is None else axis.tolist(),
            degrees,
        )

    def _pin_group(self, group, entry):
        """(entry, group) checked: TypeError unless integers, ValueError unless they name a group."""
        entry = _optional_int("entry", entry, 0, 1_000_000)
        if entry is None:
            raise TypeError("entry: expected an integer, got None")
        count = self._s.pins_entries()
        if entry >= count:
            raise ValueError(f"entry: expected the index of one of the scene's {count} pins entries, got {entry}")
        groups = self._s.pin_group_count(entry)
        if isinstance(group, bool) or not isinstance(group, numbers.Integral):
            raise TypeError(f"group: expected an integer in [0, {groups}), got {group!r}")
        if not 0 <= group < groups:
            raise ValueError(f"group: expected a pin group index in [0, {groups}), got {group}")
        return entry, int(group)

    @property
    def frame(self) -> int:
        """Frames done (0 after loading)."""
        return self._s.frame

    @property
    def frames(self) -> int:
        """The frames the scene asks for (``frames``, or the override)."""
        return self._s.frames

    @property
    def time(self) -> float:
        """Simulated time, s."""
        return self._s.time

    @property
    def dt(self) -> float:
        """The time step, s."""
        return self._s.dt

    @property
    def stats(self) -> Optional[dict]:
        """The last frame's record, as ``pce-sim`` writes it to ``stats.jsonl`` (None before
        the first step)."""
        text = self._s.last_record
        if text != self._stats_text:
            self._stats, self._stats_text = json.loads(text), text
        return self._stats

    @property
    def warnings(self) -> List[str]:
        """The start state's warnings, one line each (``pce-sim`` prints them)."""
        return list(self._s.warnings)

    def step(self) -> dict:
        """Simulates one frame (the GIL is released meanwhile); returns its record (:attr:`stats`).

        Raises :class:`SimulationError` if the frame fails; the state is then the last finite one.
        """
        self._s.step()
        return self.stats

    def run(
        self,
        frames: Optional[int] = None,
        out=None,
        *,
        write_frames: bool = True,
        checkpoint_every: int = 0,
        video=None,
        usd=None,
    ):
        """Steps ``frames`` more frames (default: up to the scene's :attr:`frames`); with
        ``out``, writes into that directory what ``pce-sim --out DIR`` writes: the current
        frame and every ``output_every``-th frame as ``frame_NNNN.obj`` (not with
        ``write_frames=False``), ``stats.jsonl`` as frames end, and at the end
        ``last_frame.png``, ``stats.json`` and ``summary.json`` (also after a failed frame,
        which is then re-raised, and after Ctrl-C, which also writes a checkpoint as
        ``pce-sim`` does on SIGINT), plus a checkpoint every ``checkpoint_every`` frames.
        With ``video`` (a .mp4, .m4v, .mov or .mkv path; needs ``out`` and ffmpeg) and ``usd``
        (a .usda or .usd path; needs ``out``), also the movie and the USD cache of the frames
        this call writes (``pce-sim``'s ``--video`` and ``--usd``), when it ends.

        Returns the records of the frames run.
        """
        if frames is None:
            frames = max(self.frames - self.frame, 0)
        frames = _optional_int("frames", frames, 0, 10_000_000)
        checkpoint_every = _optional_int("checkpoint_every", checkpoint_every, 0, 10_000_000)
        if not isinstance(write_frames, bool):
            raise TypeError(f"write_frames: expected True or False, got {write_frames!r}")
        files = {}
        for name, value in (("video", video), ("usd", usd)):
            if value is None:
                continue
            if not isinstance(value, (str, os.PathLike)):
                raise TypeError(f"{name}: expected a file path, got {value!r}")
            if out is None:
                raise ValueError(f"{name}: needs out= (the run's output directory)")
            files[name] = os.fsdecode(os.fspath(value))
            _pce._check_output(name, files[name])
        records = []
        if out is None:
            for _ in range(frames):
                records.append(self.step())
            return records
        if not isinstance(out, (str, os.PathLike)):
            raise TypeError(f"out: expected a directory path, got {out!r}")
        self._s.open(os.fspath(out), write_frames, checkpoint_every, files.get("video", ""), files.get("usd", ""))
        try:
            for _ in range(frames):
                records.append(self.step())
        except SimulationError as e:
            self._s.close(str(e), None)
            raise
        except KeyboardInterrupt:
            self._s.close("", "SIGINT")
            raise
        except BaseException:
            self._s.close("", None)
            raise
        self._s.close("", None)
        return records

    def __repr__(self) -> str:
        return f"<pce.sim.Simulation {self._s.file!r} at frame {self.frame} of {self.frames}>"
