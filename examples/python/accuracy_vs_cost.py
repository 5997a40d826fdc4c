#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""What each PSD strategy costs and how far it lands from the numerical projection.

Draws N random vertex-face pairs whose log barrier is active (k = 1, dhat = 1e-2; the
vertex at a signed distance L in (0.05, 0.95) dhat above a random, well-shaped triangle),
evaluates them with pce.evaluate once per projection, and prints and plots, per
projection, the time per pair (best of 3) against the median over pairs of
||P - P_numerical||_F / ||P_numerical||_F.

    python3 examples/python/accuracy_vs_cost.py [--pairs 100000] [--threads 1] [--seed 1]
                                                [--out docs/images/python/accuracy_vs_cost.png]

Needs the pce package (docs/python.md) and matplotlib.
"""

import argparse
import os
import time

import numpy as np

import pce

PROJECTIONS = ("analytic", "exact", "gauss_newton", "abs", "numerical")
DHAT = 1e-2
FLOOR = 1e-17  # where a median distance is exactly 0 (numerical against itself)


def random_pairs(n, rng):
    """(n, 12) vertex-face pairs (p, t0, t1, t2): a triangle in [-1, 1]^3 whose quality
    4√3·area / (sum of squared edges) is at least 0.5 (1 for an equilateral one), and p at a
    signed distance L uniform in (0.05, 0.95)·DHAT along its normal, above a point inside it."""
    triangles = np.empty((0, 3, 3))
    while len(triangles) < n:
        t = rng.uniform(-1.0, 1.0, size=(2 * n, 3, 3))
        e1, e2, e3 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0], t[:, 2] - t[:, 1]
        area = 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)
        edges = (e1**2).sum(1) + (e2**2).sum(1) + (e3**2).sum(1)
        quality = 4.0 * np.sqrt(3.0) * area / edges
        triangles = np.concatenate([triangles, t[quality >= 0.5]])
    t = triangles[:n]
    normal = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    b = rng.dirichlet(np.ones(3), size=n)  # barycentric coordinates of the foot point
    foot = np.einsum("ni,nij->nj", b, t)
    L = rng.uniform(0.05, 0.95, size=n) * DHAT
    p = foot + L[:, None] * normal
    return np.concatenate([p, t.reshape(n, 9)], axis=1)


def label_points(fig, ax, points, size=10):
    """Names each point, trying offsets around it until the label's box overlaps no point
    and no label placed before it (points are close when costs are alike)."""
    scale = 72.0 / fig.dpi  # display pixels to points
    xy = {name: ax.transData.transform(p) * scale for name, p in points.items()}
    taken = [(x - 4, y - 4, x + 4, y + 4) for x, y in xy.values()]
    (left, bottom), (right, top) = ax.bbox.get_points() * scale
    for name, (x, y) in xy.items():
        w, h = 0.62 * size * len(name), 1.1 * size
        offsets = ((6, 4), (6, -4 - h), (-6 - w, 4), (-6 - w, -4 - h), (6, 16), (6, -16 - h), (6, 28), (6, -28 - h))
        for dx, dy in offsets:
            box = (x + dx, y + dy, x + dx + w, y + dy + h)
            inside = left <= box[0] and box[2] <= right and bottom <= box[1] and box[3] <= top
            if inside and not any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3] for b in taken):
                break
        taken.append(box)
        ax.annotate(name, points[name], textcoords="offset points", xytext=(dx, dy), fontsize=size,
                    arrowprops=dict(arrowstyle="-", color="0.6", lw=0.6) if abs(dy) > 12 else None)  # fmt: skip


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pairs", type=int, default=100000, help="number of pairs (default 100000)")
    parser.add_argument("--out", default="docs/images/python/accuracy_vs_cost.png", help="the PNG to write")
    parser.add_argument("--threads", type=int, default=1, help="threads for pce.evaluate (0: one per CPU)")
    parser.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    args = parser.parse_args()
    if args.pairs < 1 or args.threads < 0:
        parser.error("--pairs must be >= 1 and --threads >= 0")

    X = random_pairs(args.pairs, np.random.default_rng(args.seed))
    penalty = pce.LogBarrier(1.0, DHAT)

    # numerical first: the reference every other projection is measured against.
    cost, distance, reference, ref_norm = {}, {}, None, None
    for projection in ("numerical",) + tuple(p for p in PROJECTIONS if p != "numerical"):
        best = float("inf")
        for _ in range(3):
            start = time.perf_counter()
            r = pce.evaluate(
                "vertex_face", X, length="signed", penalty=penalty, projection=projection,
                outputs=("value", "gradient", "projected"), threads=args.threads,
            )  # fmt: skip
            best = min(best, time.perf_counter() - start)
        if not r.ok.all():
            raise SystemExit(f"{projection}: {np.count_nonzero(~r.ok)} pairs are not ok")
        cost[projection] = best / len(X) * 1e9
        if reference is None:
            reference, ref_norm = r.projected, np.linalg.norm(r.projected, axis=(1, 2))
        diff = np.linalg.norm(r.projected - reference, axis=(1, 2))
        with np.errstate(divide="ignore", invalid="ignore"):  # a zero reference: 0 if P is 0 too, else inf
            relative = np.where(ref_norm > 0, diff / ref_norm, np.where(diff > 0, np.inf, 0.0))
        distance[projection] = float(np.median(relative))

    print(f"{len(X)} vertex-face pairs, signed length, log barrier k = 1, dhat = {DHAT:g}, "
          f"threads={args.threads}; outputs value, gradient, projected")  # fmt: skip
    print(f"{'projection':<14}{'ns per pair':>13}{'vs analytic':>13}{'median distance to numerical':>31}")
    for projection in PROJECTIONS:
        print(
            f"{projection:<14}{cost[projection]:>13.1f}{cost[projection] / cost['analytic']:>12.2f}x"
            f"{distance[projection]:>31.3e}"
        )

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    points = {p: (cost[p], max(distance[p], FLOOR)) for p in PROJECTIONS}
    for projection, (x, y) in points.items():
        exact_zero = distance[projection] == 0
        ax.plot(x, y, "o", color="tab:grey" if exact_zero else "tab:blue",
                label=f"exactly 0, drawn at {FLOOR:g}" if exact_zero else None)  # fmt: skip
    ax.set_yscale("log")
    ax.set_xlim(0, 1.2 * max(cost.values()))
    ax.set_ylim(FLOOR / 10, 100 * max(max(distance.values()), FLOOR))
    ax.set_xlabel("ns per pair (value, gradient, projected Hessian; best of 3)")
    ax.set_ylabel("median ||P - P_numerical||_F / ||P_numerical||_F")
    title = f"{len(X)} active log-barrier vertex-face pairs (dhat = {DHAT:g}), threads={args.threads}"
    ax.set_title(title, fontsize=10)
    if any(v == 0 for v in distance.values()):
        ax.legend(loc="upper right", fontsize=8)
    ax.grid(True, which="major", alpha=0.3)
    fig.tight_layout()
    label_points(fig, ax, points)
    parent = os.path.dirname(args.out)
    if parent:
        os.makedirs(parent, exist_ok=True)
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
