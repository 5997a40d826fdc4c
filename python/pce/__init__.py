# SPDX-License-Identifier: MIT
"""pce: penalty-based collision energies with closed-form eigensystems.

Batched pair evaluation on NumPy arrays (:func:`evaluate`) and the simulator
(:mod:`pce.sim`). The mathematics follows Shi & Kim, "A Unified Analysis of
Penalty-Based Collision Energies" (PACMCGIT 6(3), 2023). Documentation: docs/python.md.
"""

from __future__ import annotations

import enum
import math
import numbers
import os
from dataclasses import dataclass
from typing import Iterable, Optional, Union

import numpy as np

from . import _pce

__version__: str = _pce.__version__

#: glibc serves every block from its heap and keeps freed memory for reuse (process-wide,
#: so opt in; ``pce-sim`` does it first thing). New output arrays then reuse the memory of
#: freed ones instead of fresh pages the kernel must fault in and zero, which for large
#: batches costs more than the evaluation (docs/python.md, "Speed"). Returns whether it took.
keep_freed_memory = _pce.keep_freed_memory

__all__ = [
    "Status",
    "Quadratic",
    "Cubic",
    "LogBarrier",
    "Result",
    "evaluate",
    "KINDS",
    "PROJECTIONS",
    "OUTPUTS",
    "FEATURES",
    "keep_freed_memory",
    "sim",
    "__version__",
]


class Status(enum.IntEnum):
    """A pair's status, as the C++ ``pce::Status`` (and ``pce-probe``) name it."""

    ok = 0
    invalid_input = 1  #: a coordinate is NaN, Inf or beyond the accepted magnitude
    degenerate = 2  #: no frame: zero-area triangle, parallel edges; distance 0 for point kinds
    out_of_domain = 3  #: the penalty is undefined at this length (log barrier at L <= 0)
    overflow = 4  #: a result is not representable in the dtype


def _parameter(owner: str, name: str, value, check, expected: str) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{owner}.{name}: expected a real number, got {value!r}")
    v = float(value)
    if not math.isfinite(v) or not check(v):
        raise ValueError(f"{owner}.{name}: expected {expected}, got {value!r}")
    return v


@dataclass(frozen=True)
class Quadratic:
    """ψ(L) = k (L − eps)² for L < eps, else 0 (``pce::QuadraticPenalty``)."""

    k: float
    eps: float

    def __post_init__(self):
        object.__setattr__(self, "k", _parameter("Quadratic", "k", self.k, lambda v: v >= 0, "a finite k >= 0"))
        object.__setattr__(self, "eps", _parameter("Quadratic", "eps", self.eps, lambda v: True, "a finite eps"))


@dataclass(frozen=True)
class Cubic:
    """ψ(L) = k d² √(d² + δ), d = L − eps, for L < eps, else 0 (``pce::CubicPenalty``)."""

    k: float
    eps: float
    delta: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "k", _parameter("Cubic", "k", self.k, lambda v: v >= 0, "a finite k >= 0"))
        object.__setattr__(self, "eps", _parameter("Cubic", "eps", self.eps, lambda v: True, "a finite eps"))
        object.__setattr__(
            self, "delta", _parameter("Cubic", "delta", self.delta, lambda v: v >= 0, "a finite delta >= 0")
        )


@dataclass(frozen=True)
class LogBarrier:
    """ψ(L) = −k (L − dhat)² ln(L / dhat) for 0 < L < dhat, else 0; undefined at L <= 0
    (``pce::LogBarrierPenalty``)."""

    k: float
    dhat: float

    def __post_init__(self):
        object.__setattr__(self, "k", _parameter("LogBarrier", "k", self.k, lambda v: v >= 0, "a finite k >= 0"))
        object.__setattr__(
            self, "dhat", _parameter("LogBarrier", "dhat", self.dhat, lambda v: v > 0, "a finite dhat > 0")
        )


Penalty = Union[Quadratic, Cubic, LogBarrier]

#: Pair kinds: name -> (code, coordinates per pair, frame-space eigenvalues per pair).
KINDS = {"vertex_face": (0, 12, 9), "edge_edge": (1, 12, 9), "point_edge": (2, 9, 6), "point_point": (3, 6, 3)}
#: PSD strategies: name -> code, in ``pce::kProjectionNames``' order (the compiled module's table).
PROJECTIONS = dict(_pce._projections())
#: The float outputs `evaluate` can compute (all by default).
OUTPUTS = ("length", "value", "gradient", "hessian", "projected", "eigenvalues")
#: Closest features, in ``pce::Feature``'s order.
FEATURES = ("point_plane", "line_line", "point_edge", "point_point")
_PENALTIES = {Quadratic: 0, Cubic: 1, LogBarrier: 2}
_MAX_THREADS = 1024


def _cpus() -> int:
    """The CPUs this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


class Result:
    """The outputs of :func:`evaluate`; an output that was not asked for is ``None``.

    Attributes:
        status: (N,) int32, :class:`Status` values.
        length: (N,) the length L.
        value: (N,) the energy ψ(L).
        gradient: (N, D) ∇E.
        hessian: (N, D, D) the exact ∇²E.
        projected: (N, D, D) the PSD matrix of the projection ("none": the exact Hessian).
        eigenvalues: (N, F) frame-space eigenvalues, ascending (closest features: the
            evaluated kind's 9, 6 or 3, then NaN).
        feature: (N,) str, closest features only: the kind evaluated ("" where not ok).

    Rows whose status is not ok hold NaN in every float output.
    """

    __slots__ = ("status", "length", "value", "gradient", "hessian", "projected", "eigenvalues", "feature")

    def __init__(self, **arrays):
        for name in self.__slots__:
            setattr(self, name, arrays.get(name))

    @property
    def ok(self) -> np.ndarray:
        """(N,) bool: the rows whose status is ok."""
        return self.status == Status.ok

    def __len__(self) -> int:
        return len(self.status)

    def __repr__(self) -> str:
        n = len(self.status)
        counts = ", ".join(f"{s.name}={int(np.count_nonzero(self.status == s))}" for s in Status if np.any(self.status == s))
        return f"<pce.Result of {n} pairs: {counts or 'empty'}>"


def _coordinates(X, dofs: int, kind: str) -> np.ndarray:
    """X as a C-contiguous float32 or float64 array of shape (N, dofs): float32 and float64
    kept, integers and float16 converted to float64; anything else is a TypeError."""
    if X is None or isinstance(X, (str, bytes)):
        raise TypeError(f"X: expected an (N, {dofs}) array of coordinates, got {X!r}")
    try:
        a = np.asarray(X)
    except (TypeError, ValueError) as e:
        raise TypeError(f"X: expected an (N, {dofs}) array of real numbers ({e})") from None
    if a.dtype not in (np.float32, np.float64):
        if a.dtype.kind in "iu" or a.dtype == np.float16:
            a = a.astype(np.float64)
        elif a.dtype.kind == "f":
            raise TypeError(f"X: {a.dtype} would be rounded; convert it to float64 or float32 first")
        else:
            raise TypeError(f"X: expected real numbers (float64, float32 or integers), got dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] != dofs:
        raise ValueError(f"X: expected shape (N, {dofs}) for {kind}, got {a.shape}")
    return np.ascontiguousarray(a)


def _reused(out, name: str, shape, dtype) -> np.ndarray:
    """`out`'s array `name`, checked to be a writable C-contiguous `shape` array of `dtype`."""
    if not isinstance(out, Result):
        raise TypeError(f"out: expected a pce.Result of an earlier call, got {type(out).__name__}")
    a = getattr(out, name)
    if (
        not isinstance(a, np.ndarray)
        or a.shape != shape
        or a.dtype != dtype
        or not a.flags.c_contiguous
        or not a.flags.writeable
    ):
        got = "None" if a is None else f"{a.dtype} {a.shape}"
        raise ValueError(f"out: its {name} must be a writable {np.dtype(dtype)} array of shape {shape}, got {got}")
    return a


def evaluate(
    kind: str,
    X,
    *,
    penalty: Penalty,
    length: str = "unsigned",
    side: int = 1,
    projection: str = "analytic",
    closest_feature: bool = False,
    outputs: Optional[Iterable[str]] = None,
    threads: int = 1,
    out: Optional[Result] = None,
) -> Result:
    """Evaluates N pairs at once: energy, gradient, exact and PSD Hessians, eigenvalues.

    Args:
        kind: "vertex_face" (p, t0, t1, t2), "edge_edge" (ea0, ea1, eb0, eb1): X is (N, 12);
            "point_edge" (p, e0, e1): (N, 9); "point_point" (p, q): (N, 6).
        X: coordinates, float64 or float32 (kept); integers and float16 are converted to
            float64; bool, complex, long double, strings and objects are a TypeError.
        penalty: :class:`Quadratic`, :class:`Cubic` or :class:`LogBarrier`.
        length: "unsigned" (the distance to the plane or line) or "signed" (plane kinds only).
        side: +1 or -1, the outside of a signed length.
        projection: "analytic", "exact", "numerical", "gauss_newton", "abs" or "none".
        closest_feature: evaluate the distance between the primitives by whichever kind holds
            the closest points (vertex_face / edge_edge, unsigned length); sets ``feature``.
        outputs: which of :data:`OUTPUTS` to compute (default: all); fewer is faster.
        threads: threads for the rows, at most 1024 (0: one per CPU this process may use);
            results do not depend on it.
        out: a :class:`Result` of an earlier call with the same N, dtype and outputs: its
            arrays are written again and returned in a new Result (no allocation, no fresh
            pages to fault in: what a solver that evaluates every iteration wants).

    Returns:
        A :class:`Result`; outputs have the dtype of X.

    Raises:
        ValueError / TypeError naming the argument for a bad argument.
    """
    if not isinstance(kind, str) or kind not in KINDS:
        raise ValueError(f"kind: expected one of {', '.join(KINDS)}, got {kind!r}")
    code, dofs, frame_dofs = KINDS[kind]
    x = _coordinates(X, dofs, kind)
    if length not in ("signed", "unsigned"):
        raise ValueError(f"length: expected 'signed' or 'unsigned', got {length!r}")
    signed = length == "signed"
    if signed and dofs != 12:
        raise ValueError(f"length: 'signed' is for vertex_face and edge_edge; {kind} has the unsigned length only")
    if isinstance(side, bool) or side not in (1, -1):
        raise ValueError(f"side: expected 1 or -1, got {side!r}")
    if type(penalty) not in _PENALTIES:
        raise TypeError(f"penalty: expected pce.Quadratic, pce.Cubic or pce.LogBarrier, got {penalty!r}")
    if not isinstance(projection, str) or projection not in PROJECTIONS:
        raise ValueError(f"projection: expected one of {', '.join(PROJECTIONS)}, got {projection!r}")
    if not isinstance(closest_feature, (bool, np.bool_)):
        raise TypeError(f"closest_feature: expected True or False, got {closest_feature!r}")
    if closest_feature and (dofs != 12 or signed):
        raise ValueError("closest_feature: needs kind vertex_face or edge_edge and length 'unsigned'")
    if outputs is None:
        wanted = set(OUTPUTS)
    else:
        if isinstance(outputs, str):
            outputs = (outputs,)
        try:
            wanted = set(outputs)
        except TypeError:
            raise TypeError(f"outputs: expected names from {OUTPUTS}, got {outputs!r}") from None
        unknown = wanted.difference(OUTPUTS)
        if unknown:
            raise ValueError(f"outputs: unknown {sorted(unknown)}; expected a subset of {OUTPUTS}")
    if isinstance(threads, bool) or not isinstance(threads, numbers.Integral):
        raise TypeError(f"threads: expected an integer in [0, {_MAX_THREADS}], got {threads!r}")
    if not 0 <= threads <= _MAX_THREADS:
        raise ValueError(f"threads: expected an integer in [0, {_MAX_THREADS}], got {threads!r}")
    threads = int(threads) or _cpus()

    n = x.shape[0]
    eig_width = 9 if closest_feature else frame_dofs
    shapes = {
        "length": (n,),
        "value": (n,),
        "gradient": (n, dofs),
        "hessian": (n, dofs, dofs),
        "projected": (n, dofs, dofs),
        "eigenvalues": (n, eig_width),
    }
    if out is None:
        arrays = {name: np.empty(shape, dtype=x.dtype) if name in wanted else None for name, shape in shapes.items()}
        status = np.empty(n, dtype=np.int32)
    else:
        arrays = {name: _reused(out, name, shape, x.dtype) if name in wanted else None for name, shape in shapes.items()}
        status = _reused(out, "status", (n,), np.dtype(np.int32))
    feature = np.zeros(n, dtype=np.int32) if closest_feature else None
    p = penalty
    params = {Quadratic: lambda: (p.k, p.eps, 0.0), Cubic: lambda: (p.k, p.eps, p.delta), LogBarrier: lambda: (p.k, p.dhat, 0.0)}
    a, b, c = params[type(p)]()
    _pce._evaluate(
        code, x, signed, int(side), _PENALTIES[type(p)], a, b, c, PROJECTIONS[projection], bool(closest_feature),
        threads, status, arrays["length"], arrays["value"], arrays["gradient"], arrays["hessian"],
        arrays["projected"], arrays["eigenvalues"], feature,
    )  # fmt: skip
    if feature is not None:
        names = np.array(FEATURES + ("",))
        feature = names[np.where(status == Status.ok, feature, len(FEATURES))]
    return Result(status=status, feature=feature, **arrays)


from . import sim  # noqa: E402  (the simulator; imports _pce too)
