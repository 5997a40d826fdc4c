#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Two cloths of different materials built from NumPy arrays, one lifted by a hand that
Python moves between frames.

The scene of examples/scenes/lift_two_cloths.json, written as a dict whose meshes are NumPy
arrays (pce.sim.from_dict): a soft "silk" and a stiff "canvas" on a table, a material per
mesh, friction per pair of meshes. Instead of keyframes, Python moves the canvas's pinned
corner before every step (set_pin_targets), along a path it computes, and reads the
positions back.

    python3 examples/python/lift_from_arrays.py [--frames 80]

Needs the pce package (docs/python.md).
"""

import argparse

import numpy as np

import pce.sim


def grid(width, height, nx, ny, centre):
    """A width × height rectangle of nx × ny quads, each split along one diagonal, centred at
    `centre` in a plane z = const: vertex (i, j) is row j (nx + 1) + i."""
    x, y = np.meshgrid(np.linspace(-width / 2, width / 2, nx + 1), np.linspace(-height / 2, height / 2, ny + 1))
    vertices = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1) + centre
    i = np.arange(ny * (nx + 1)).reshape(ny, nx + 1)[:, :nx].ravel()  # each quad's lower left corner
    triangles = np.concatenate([np.stack([i, i + 1, i + nx + 2], 1), np.stack([i, i + nx + 2, i + nx + 1], 1)])
    return vertices, triangles


def hand(t):
    """Where the hand holds the corner at time t, from its rest position: still until 0.25 s,
    up 0.35 m by 1 s, across by 2 s, easing in and out of each leg (smoothstep)."""
    legs = [(0.25, [0, 0, 0]), (1.0, [0.05, 0.05, 0.35]), (2.0, [-0.35, 0.25, 0.3])]
    if t <= legs[0][0]:
        return np.zeros(3)
    for (t0, d0), (t1, d1) in zip(legs, legs[1:]):
        if t <= t1:
            u = (t - t0) / (t1 - t0)
            w = u * u * (3 - 2 * u)
            return np.array(d0) + w * (np.array(d1) - np.array(d0))
    return np.array(legs[-1][1], dtype=float)


def scene(frames):
    silk_v, silk_t = grid(0.6, 0.3, 24, 12, [0, 0, 0.006])
    canvas_v, canvas_t = grid(0.4, 0.4, 16, 16, [0.1, 0.05, 0.016])
    penalty = {"type": "quadratic", "stiffness": 300.0, "distance": 0.005}
    return {
        "dt": 0.025,
        "frames": frames,
        "output_every": 2,
        "view_direction": [-0.5, -1.6, -0.7],
        "meshes": [
            {"name": "silk", "vertices": silk_v, "triangles": silk_t, "density": 0.05},
            {"name": "canvas", "vertices": canvas_v, "triangles": canvas_t, "density": 0.3},
        ],
        "obstacles": [{"name": "table", "shape": "box", "half_extents": [0.5, 0.5, 0.05], "position": [0, 0, -0.05]}],
        "effects": [
            {"type": "gravity"},
            {"type": "stretching", "meshes": ["silk"], "stiffness": 15.0},
            {"type": "stretching", "meshes": ["canvas"], "stiffness": 300.0},
            {"type": "bending", "meshes": ["silk"], "stiffness": 2e-6},
            {"type": "bending", "meshes": ["canvas"], "stiffness": 2e-4},
            {"type": "damping", "coefficient": 0.5},
            {"type": "pins", "stiffness": 1e4, "groups": [{"mesh": "canvas", "vertices": [288]}]},
            {"type": "self_vertex_face", "meshes": [["silk", "canvas"]], "closest_features": True,
             "penalty": penalty, "friction": {"coefficient": 0.8}},
            {"type": "self_vertex_face", "meshes": [["silk", "silk"], ["canvas", "canvas"]],
             "closest_features": True, "penalty": penalty},
            {"type": "self_edge_edge", "closest_features": True, "penalty": penalty},
            {"type": "obstacle_contact", "meshes": ["silk"], "penalty": penalty, "friction": {"coefficient": 0.1}},
            {"type": "obstacle_contact", "meshes": ["canvas"], "penalty": penalty, "friction": {"coefficient": 0.3}},
        ],
    }  # fmt: skip


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--frames", type=int, default=80)
    args = ap.parse_args()
    s = pce.sim.from_dict(scene(args.frames))
    corner = s.pin_targets(0)[0]  # the corner's rest position
    silk = slice(0, 25 * 13)  # the silk's vertices come first
    silk_start = s.positions[silk].mean(axis=0)
    for _ in range(args.frames):
        target = corner + hand(s.time + s.dt)  # where the hand is at the end of the step
        s.set_pin_targets(0, [target])
        s.step()
    x = s.positions
    print(f"frame {s.frame}: corner {np.linalg.norm(x[25 * 13 + 288] - target) * 1e3:.2f} mm from the hand, "
          f"silk dragged {np.linalg.norm(x[silk].mean(axis=0) - silk_start):.3f} m")  # fmt: skip


if __name__ == "__main__":
    main()
