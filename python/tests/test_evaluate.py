# SPDX-License-Identifier: MIT
"""pce.evaluate: bit for bit what pce-probe prints (the single-pair C++ API) for every kind,
length, penalty, projection and dtype, on random and hard pairs; statuses and NaN rows;
every bad argument raises ValueError / TypeError naming it."""

import itertools
import json
import subprocess

import numpy as np
import pytest

import pce

PENALTIES = {
    "quadratic": (pce.Quadratic(k=10.0, eps=0.4), {"type": "quadratic", "stiffness": 10.0, "eps": 0.4}),
    "cubic": (pce.Cubic(k=10.0, eps=0.4, delta=1e-3), {"type": "cubic", "stiffness": 10.0, "eps": 0.4, "delta": 1e-3}),
    "log_barrier": (pce.LogBarrier(k=10.0, dhat=0.4), {"type": "log_barrier", "stiffness": 10.0, "dhat": 0.4}),
}
# (kind, length, side): the plane kinds with both lengths and sides, the point kinds unsigned.
CASES = [
    (kind, length, side)
    for kind in ("vertex_face", "edge_edge")
    for length, side in (("unsigned", 1), ("signed", 1), ("signed", -1))
] + [("point_edge", "unsigned", 1), ("point_point", "unsigned", 1)]
DTYPES = (np.float64, np.float32)


def pairs(kind, dtype, n=10, seed=1):
    """n - 3 random pairs in a small cube (most within the penalties' reach) and three hard
    rows: two equal points (degenerate: zero-area triangle, zero-length edge, distance 0;
    for edge-edge the edges touch), every point in the plane z = 0 (l = 0 exactly: the log
    barrier is out of its domain; point-edge: on one line, degenerate), a coordinate of
    1e30 (beyond the accepted magnitude in float)."""
    dofs = pce.KINDS[kind][1]
    rng = np.random.default_rng(seed)
    X = rng.uniform(-0.3, 0.3, size=(n, dofs))
    first = 0 if dofs == 6 else 3
    X[0, first + 3 : first + 6] = X[0, first : first + 3]
    if dofs == 12:
        X[1, 2::3] = 0.0  # every point at z = 0: l = 0 exactly
    elif kind == "point_edge":
        X[1, 1::3] = X[1, 2::3] = 0.0  # every point on the x axis: distance 0
    X[2, 4] = 1e30
    return X.astype(dtype)


def probe_requests(kind, X, length, side, penalty, projection, closest=False):
    scalar = "double" if X.dtype == np.float64 else "float"
    for row in X:
        yield {
            "pair": kind,
            "length": length,
            "side": side,
            "penalty": penalty,
            "projection": projection,
            "scalar": scalar,
            "closest_feature": closest,
            "x": [float(v) for v in row],
        }


def run_probe(probe, requests):
    text = "".join(json.dumps(r) + "\n" for r in requests)
    out = subprocess.run([str(probe)], input=text, capture_output=True, text=True, check=True).stdout
    return [json.loads(line) for line in out.splitlines()]


def bits(a, dtype):
    a = np.asarray(a, dtype=dtype)
    return a.view(np.uint64 if dtype == np.float64 else np.uint32)


def assert_row_equal(r, i, response, dofs, dtype, where):
    assert pce.Status(r.status[i]).name == response["status"], where
    if response["status"] != "ok":
        for name in pce.OUTPUTS:
            assert np.all(np.isnan(getattr(r, name)[i])), (where, name)
        return
    np.testing.assert_array_equal(bits(r.length[i], dtype), bits(response["length"], dtype), err_msg=where)
    np.testing.assert_array_equal(bits(r.value[i], dtype), bits(response["value"], dtype), err_msg=where)
    np.testing.assert_array_equal(bits(r.gradient[i], dtype), bits(response["gradient"], dtype), err_msg=where)
    np.testing.assert_array_equal(
        bits(r.hessian[i].ravel(), dtype), bits(response["hessian"], dtype), err_msg=where
    )
    np.testing.assert_array_equal(
        bits(r.projected[i].ravel(), dtype), bits(response["projected_hessian"], dtype), err_msg=where
    )
    eig = response["eigenvalues"]
    np.testing.assert_array_equal(bits(r.eigenvalues[i][: len(eig)], dtype), bits(eig, dtype), err_msg=where)
    assert np.all(np.isnan(r.eigenvalues[i][len(eig) :])), where


def test_every_kind_length_penalty_projection_and_dtype_equals_pce_probe(probe):
    batches, requests = [], []
    for (kind, length, side), (pname, (penalty, spec)), projection, dtype in itertools.product(
        CASES, PENALTIES.items(), pce.PROJECTIONS, DTYPES
    ):
        X = pairs(kind, dtype)
        r = pce.evaluate(kind, X, length=length, side=side, penalty=penalty, projection=projection)
        batches.append((kind, length, side, pname, projection, dtype, X, r))
        requests.extend(probe_requests(kind, X, length, side, spec, projection))
    responses = iter(run_probe(probe, requests))
    statuses = set()
    for kind, length, side, pname, projection, dtype, X, r in batches:
        assert r.value.dtype == dtype and r.projected.dtype == dtype
        for i in range(len(X)):
            where = f"{kind} {length} side={side} {pname} {projection} {np.dtype(dtype).name} row {i}"
            response = next(responses)
            assert_row_equal(r, i, response, pce.KINDS[kind][1], dtype, where)
            statuses.add(response["status"])
    # The comparison saw real results and every status but overflow.
    assert {"ok", "degenerate", "invalid_input", "out_of_domain"} <= statuses


def test_closest_features_equal_pce_probe(probe):
    batches, requests = [], []
    for kind, (pname, (penalty, spec)), projection, dtype in itertools.product(
        ("vertex_face", "edge_edge"), PENALTIES.items(), pce.PROJECTIONS, DTYPES
    ):
        X = pairs(kind, dtype, n=24, seed=5)
        r = pce.evaluate(kind, X, penalty=penalty, projection=projection, closest_feature=True)
        batches.append((kind, pname, projection, dtype, X, r))
        requests.extend(probe_requests(kind, X, "unsigned", 1, spec, projection, closest=True))
    responses = iter(run_probe(probe, requests))
    features = set()
    for kind, pname, projection, dtype, X, r in batches:
        for i in range(len(X)):
            response = next(responses)
            where = f"closest {kind} {pname} {projection} {np.dtype(dtype).name} row {i}"
            assert_row_equal(r, i, response, 12, dtype, where)
            assert r.feature[i] == response.get("feature", ""), where
            if response["status"] == "ok":
                features.add(response["feature"])
    assert features == set(pce.FEATURES)


def test_statuses_and_nan_rows():
    X = pairs("vertex_face", np.float64)
    X[3, 7] = np.nan
    r = pce.evaluate("vertex_face", X, penalty=pce.LogBarrier(1.0, 0.4))
    assert r.status[0] == pce.Status.degenerate
    assert r.status[1] == pce.Status.out_of_domain
    assert r.status[3] == pce.Status.invalid_input
    assert r.ok.sum() == np.count_nonzero(r.status == 0) and r.ok[4:].all()
    for name in pce.OUTPUTS:
        assert np.all(np.isnan(getattr(r, name)[~r.ok]))
        assert np.all(np.isfinite(getattr(r, name)[r.ok]))
    # A stiffness that is finite in double but not in float: the penalty overflows.
    r32 = pce.evaluate("point_point", pairs("point_point", np.float32)[3:], penalty=pce.Quadratic(1e300, 1.0))
    assert np.all(r32.status == pce.Status.overflow)
    assert np.all(np.isnan(r32.value))


def test_threads_and_output_subsets_change_nothing():
    X = pairs("edge_edge", np.float64, n=1001, seed=9)
    full = pce.evaluate("edge_edge", X, penalty=pce.Cubic(3.0, 0.3, 1e-4), projection="exact")
    threaded = pce.evaluate("edge_edge", X, penalty=pce.Cubic(3.0, 0.3, 1e-4), projection="exact", threads=3)
    some = pce.evaluate(
        "edge_edge", X, penalty=pce.Cubic(3.0, 0.3, 1e-4), projection="exact", outputs=("value", "projected")
    )
    np.testing.assert_array_equal(full.status, threaded.status)
    for name in pce.OUTPUTS:
        np.testing.assert_array_equal(getattr(full, name), getattr(threaded, name))
    assert some.gradient is None and some.hessian is None and some.length is None and some.eigenvalues is None
    np.testing.assert_array_equal(some.value, full.value)
    np.testing.assert_array_equal(some.projected, full.projected)
    assert pce.evaluate("edge_edge", X, penalty=pce.Cubic(3.0, 0.3), threads=0).ok.any()


def test_conversions_of_X():
    X = pairs("point_edge", np.float64)
    base = pce.evaluate("point_edge", X, penalty=pce.Quadratic(1.0, 0.5))
    wide = np.zeros((X.shape[0], 18))
    wide[:, ::2] = X  # a strided (non-contiguous) view
    strided = pce.evaluate("point_edge", wide[:, ::2], penalty=pce.Quadratic(1.0, 0.5))
    np.testing.assert_array_equal(strided.value, base.value)
    listed = pce.evaluate("point_edge", X.tolist(), penalty=pce.Quadratic(1.0, 0.5))
    np.testing.assert_array_equal(listed.value, base.value)
    ints = pce.evaluate("point_point", np.arange(12).reshape(2, 6), penalty=pce.Quadratic(1.0, 10.0))
    assert ints.value.dtype == np.float64 and ints.ok.all()
    halves = pce.evaluate("point_point", np.arange(12, dtype=np.float16).reshape(2, 6), penalty=pce.Quadratic(1.0, 10.0))
    np.testing.assert_array_equal(halves.value, ints.value)
    empty = pce.evaluate("vertex_face", np.empty((0, 12), np.float32), penalty=pce.Quadratic(1.0, 1.0))
    assert len(empty) == 0 and empty.hessian.shape == (0, 12, 12) and empty.value.dtype == np.float32


GOOD = dict(kind="vertex_face", X=np.zeros((2, 12)), penalty=pce.Quadratic(1.0, 0.1))


@pytest.mark.parametrize(
    "change, error, name",
    [
        ({"kind": "vertex_edge"}, ValueError, "kind"),
        ({"kind": 3}, ValueError, "kind"),
        ({"X": np.zeros((2, 9))}, ValueError, "X"),
        ({"X": np.zeros(12)}, ValueError, "X"),
        ({"X": np.zeros((2, 12, 1))}, ValueError, "X"),
        ({"X": np.zeros((2, 12), np.complex128)}, TypeError, "X"),
        ({"X": [["a"] * 12]}, TypeError, "X"),
        ({"X": None}, TypeError, "X"),
        ({"length": "signd"}, ValueError, "length"),
        ({"kind": "point_point", "X": np.zeros((2, 6)), "length": "signed"}, ValueError, "length"),
        ({"side": 0}, ValueError, "side"),
        ({"side": True}, ValueError, "side"),
        ({"penalty": {"type": "quadratic"}}, TypeError, "penalty"),
        ({"projection": "psd"}, ValueError, "projection"),
        ({"closest_feature": 1}, TypeError, "closest_feature"),
        ({"closest_feature": True, "length": "signed"}, ValueError, "closest_feature"),
        ({"kind": "point_edge", "X": np.zeros((2, 9)), "closest_feature": True}, ValueError, "closest_feature"),
        ({"outputs": ("value", "grad")}, ValueError, "outputs"),
        ({"outputs": 3}, TypeError, "outputs"),
        ({"threads": -1}, ValueError, "threads"),
        ({"threads": 1.5}, TypeError, "threads"),
        ({"threads": 1025}, ValueError, "threads"),
        ({"X": np.zeros((2, 12), bool)}, TypeError, "X"),
        ({"X": np.zeros((2, 12)).astype(str)}, TypeError, "X"),
        ({"X": np.zeros((2, 12), np.longdouble)}, TypeError, "X"),
        ({"X": np.zeros((2, 12), object)}, TypeError, "X"),
    ],
)
def test_bad_arguments_raise_naming_the_argument(change, error, name):
    args = dict(GOOD)
    args.update(change)
    kind, X = args.pop("kind"), args.pop("X")
    with pytest.raises(error, match=rf"^{name}\b"):
        pce.evaluate(kind, X, **args)


@pytest.mark.parametrize(
    "make, error, name",
    [
        (lambda: pce.Quadratic(k=-1.0, eps=0.1), ValueError, "Quadratic.k"),
        (lambda: pce.Quadratic(k=1.0, eps=float("nan")), ValueError, "Quadratic.eps"),
        (lambda: pce.Quadratic(k="1", eps=0.1), TypeError, "Quadratic.k"),
        (lambda: pce.Cubic(k=1.0, eps=0.1, delta=-1e-3), ValueError, "Cubic.delta"),
        (lambda: pce.Cubic(k=float("inf"), eps=0.1), ValueError, "Cubic.k"),
        (lambda: pce.LogBarrier(k=1.0, dhat=0.0), ValueError, "LogBarrier.dhat"),
        (lambda: pce.LogBarrier(k=-2.0, dhat=1.0), ValueError, "LogBarrier.k"),
    ],
)
def test_bad_penalty_parameters_raise_naming_the_field(make, error, name):
    with pytest.raises(error, match=rf"^{name}\b"):
        make()


def test_the_compiled_entry_point_checks_sizes_itself():
    """The private entry point re-checks what pce.evaluate checked, so a wrong call cannot
    write outside an array."""
    X = np.zeros((4, 12))
    small = np.empty(3)
    with pytest.raises(ValueError, match="value"):
        pce._pce._evaluate(0, X, False, 1, 0, 1.0, 0.1, 0.0, 1, False, 1, None, None, small, None, None, None, None, None)
    with pytest.raises(TypeError, match="value"):
        pce._pce._evaluate(
            0, X, False, 1, 0, 1.0, 0.1, 0.0, 1, False, 1, None, None, np.empty(4, np.float32), None, None, None, None,
            None,
        )
    with pytest.raises(ValueError, match="X"):
        pce._pce._evaluate(0, np.zeros((4, 9)), False, 1, 0, 1.0, 0.1, 0.0, 1, False, 1, *[None] * 8)


def test_version():
    assert pce.__version__.count(".") == 2


def test_out_reuses_the_arrays_of_an_earlier_result():
    X = pairs("vertex_face", np.float64, n=50, seed=3)
    Y = pairs("vertex_face", np.float64, n=50, seed=4)
    first = pce.evaluate("vertex_face", X, penalty=pce.Quadratic(5.0, 0.3), projection="exact")
    arrays = {name: getattr(first, name) for name in pce.OUTPUTS}
    again = pce.evaluate("vertex_face", Y, penalty=pce.Quadratic(5.0, 0.3), projection="exact", out=first)
    fresh = pce.evaluate("vertex_face", Y, penalty=pce.Quadratic(5.0, 0.3), projection="exact")
    for name in pce.OUTPUTS:
        assert getattr(again, name) is arrays[name]  # written in place
        np.testing.assert_array_equal(getattr(again, name), getattr(fresh, name))
    np.testing.assert_array_equal(again.status, fresh.status)
    lean = pce.evaluate("vertex_face", X, penalty=pce.Quadratic(5.0, 0.3), outputs=("value",), out=first)
    assert lean.value is arrays["value"] and lean.hessian is None
    with pytest.raises(ValueError, match=r"^out: its length"):
        pce.evaluate("vertex_face", X, penalty=pce.Quadratic(5.0, 0.3), out=lean)
    with pytest.raises(ValueError, match=r"^out: its value"):
        pce.evaluate("vertex_face", X[:10], penalty=pce.Quadratic(5.0, 0.3), outputs=("value",), out=first)
    with pytest.raises(ValueError, match=r"^out: its length must be a writable float32"):
        pce.evaluate("vertex_face", X.astype(np.float32), penalty=pce.Quadratic(5.0, 0.3), out=first)
    with pytest.raises(TypeError, match=r"^out"):
        pce.evaluate("vertex_face", X, penalty=pce.Quadratic(5.0, 0.3), out={"value": np.empty(50)})
