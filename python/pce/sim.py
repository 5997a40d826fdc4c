# SPDX-License-Identifier: MIT
"""The simulator from Python: load a scene file, step it, read its state, or run it and
write what ``pce-sim`` writes (docs/python.md, docs/simulation.md).

Scene errors raise :class:`SceneError` with the message ``pce-sim`` prints (after its
``pce-sim:`` prefix); a frame that fails raises :class:`SimulationError`.
"""

from __future__ import annotations

import json
import numbers
import os
from typing import List, Optional

import numpy as np

from . import _pce

__all__ = ["load", "Simulation", "SceneError", "SimulationError", "keep_freed_memory"]

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
) -> "Simulation":
    """Loads a scene file (JSON, docs/simulation.md §2) at frame 0.

    The keyword arguments override the scene as ``pce-sim``'s options do: ``frames``
    (``--frames``), ``hessian`` (``--hessian``: every contact effect's strategy),
    ``broad_phase`` (``--broad-phase``: "fcl", "bullet", "brute"), ``threads`` (``--threads``,
    0: all), ``single_solve`` (``--single-solve``), ``tolerance`` (``--tolerance``),
    ``mode`` (``--mode``: "newton", "single_solve", "block_descent"; wins over
    ``single_solve``), ``iterations`` (``--iterations``: block descent's sweeps per step).

    Raises :class:`SceneError` (the message ``pce-sim`` prints) for an invalid scene, and
    for a start state with intersecting meshes unless the scene allows it.
    """
    if not isinstance(scene, (str, os.PathLike)):
        raise TypeError(f"scene: expected a path, got {scene!r}")
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
    if mode is not None and not isinstance(mode, str):
        raise TypeError(f"mode: expected a string, got {mode!r}")
    if mode is not None and mode not in _MODES:
        raise ValueError(f"mode: expected one of {', '.join(_MODES)}, got {mode!r}")
    if single_solve is not None and not isinstance(single_solve, bool):
        raise TypeError(f"single_solve: expected True or False, got {single_solve!r}")
    if tolerance is not None:
        if isinstance(tolerance, bool) or not isinstance(tolerance, numbers.Real):
            raise TypeError(f"tolerance: expected a number > 0, got {tolerance!r}")
        if not 0 < tolerance < float("inf"):
            raise ValueError(f"tolerance: expected a finite number > 0, got {tolerance!r}")
        tolerance = float(tolerance)
    return Simulation(
        _pce._load(os.fspath(scene), frames, hessian, broad_phase, threads, single_solve, tolerance, mode, iterations)
    )


class Simulation:
    """A loaded scene. Made by :func:`load`."""

    def __init__(self, loaded):
        self._s = loaded
        self._stats: Optional[dict] = None
        self._stats_text = ""

    @property
    def positions(self) -> np.ndarray:
        """(V, 3) float64: every deformable vertex's position now. A copy: it does not change
        when the simulation steps, and writing to it does not move the simulation."""
        return self._s.positions()

    @property
    def velocities(self) -> np.ndarray:
        """(V, 3) float64: the vertices' velocities now (a copy, as ``positions``)."""
        return self._s.velocities()

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
