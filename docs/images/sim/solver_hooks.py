#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Draws docs/images/sim/solver_hooks.png, the picture of docs/simulation.md §5.6: who calls
what among `Simulation`, the two step solvers, the interfaces they ask for and the effects
that implement them (src/sim/solver/*.cpp, src/sim/include/pce/sim/*.hpp).

    python3 docs/images/sim/solver_hooks.py [--out docs/images/sim/solver_hooks.png]

Needs matplotlib. The picture is drawn by hand from the code: when an interface, a hook or
an effect changes, change the lists below and draw it again.
"""

import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyBboxPatch  # noqa: E402

MONO = "DejaVu Sans Mono"
# Fill and edge colour per role: the callers and the interfaces only they ask for share one.
SIM = ("#fff2cc", "#7f6000")
NEWTON = ("#d6e6f5", "#1f5f99")
BLOCK = ("#fce5cd", "#b45f06")
BOTH = ("#e8dcf3", "#674ea7")
CHECKPOINT = ("#d9ead3", "#38761d")
EFFECT = ("#eeeeee", "#444444")
SHARED = ("#f7f7f7", "#888888")
CHIP = {"Effect": EFFECT, "NewtonHooks": NEWTON, "Requery": BOTH, "BlockDescentHooks": BLOCK,
        "AccelerationField": BLOCK, "CarriedState": CHECKPOINT}


def box(ax, x0, y0, x1, y1, colours, title, lines=(), note=None, title_size=10.5, size=9.0, header=None):
    """A rounded box from (x0, y0) to (x1, y1): a bold title, its header (small, grey), monospace
    lines, an italic note."""
    fill, edge = colours
    ax.add_patch(FancyBboxPatch((x0, y0), x1 - x0, y1 - y0, boxstyle="round,pad=0.3,rounding_size=1.0",
                                facecolor=fill, edgecolor=edge, linewidth=1.4))
    cx = (x0 + x1) / 2
    y = y1 - 2.2
    ax.text(cx, y, title, ha="center", va="center", fontsize=title_size, fontweight="bold", color="#222222")
    if header:
        y -= 2.0
        ax.text(cx, y, header, ha="center", va="center", fontsize=7.6, family=MONO, color="#666666")
        y -= 0.4
    for line in lines:
        y -= 2.3
        ax.text(cx, y, line, ha="center", va="center", fontsize=size, family=MONO, color="#222222")
    if note:
        ax.text(cx, y0 + 1.4, note, ha="center", va="center", fontsize=8.2, style="italic", color="#555555")


def arrow(ax, start, end, colour, rad=0.0, label=None, label_at=None, style="-|>", dashed=False):
    """An arrow from `start` to `end` (a call, or with `dashed` an implementation)."""
    ax.annotate("", xy=end, xytext=start,
                arrowprops=dict(arrowstyle=style, color=colour, linewidth=1.5, shrinkA=0, shrinkB=0,
                                linestyle="--" if dashed else "-", connectionstyle=f"arc3,rad={rad}",
                                mutation_scale=13))
    if label:
        ax.text(*label_at, label, ha="center", va="center", fontsize=8.2, color=colour,
                bbox=dict(facecolor="white", edgecolor="none", pad=0.6))


def chips(ax, x0, y, names):
    """Small boxes naming the interfaces an effect implements, from x0 to the right."""
    x = x0
    for name in names:
        width = 1.05 * len(name) + 1.6
        fill, edge = CHIP[name]
        ax.add_patch(FancyBboxPatch((x, y - 1.0), width, 2.0, boxstyle="round,pad=0.15,rounding_size=0.5",
                                    facecolor=fill, edgecolor=edge, linewidth=1.0))
        ax.text(x + width / 2, y, name, ha="center", va="center", fontsize=7.6, family=MONO, color="#222222")
        x += width + 0.8


def draw(out):
    fig = plt.figure(figsize=(12.0, 8.8))
    ax = fig.add_axes([0, 0, 1, 1])
    ax.set_xlim(0, 120)
    ax.set_ylim(0, 88)
    ax.axis("off")

    # The simulation and the callers.
    box(ax, 1, 76, 119, 86, SIM, "Simulation   (pce/sim/simulation.hpp, solver/simulation.cpp)",
        ["model · x, v · effects (scene order) · obstacles · solver settings",
         "step(): check → begin (every effect's begin_step) → the mode's solver → the accepted state → report"])
    box(ax, 6, 55, 40, 69, NEWTON, "Newton   (solver/newton.cpp)",
        ["modes newton, single_solve", "LinearState, iterate buffers"])
    box(ax, 42.5, 57, 59.5, 67, SHARED, "solver/step.hpp", ["Inertia · Step", "StepSolver"],
        note="shared by both", title_size=9.5, size=8.6)
    box(ax, 62, 55, 96, 69, BLOCK, "BlockDescent  (solver/block_descent.cpp)",
        ["mode block_descent", "colouring, bounds, sweeps"], title_size=10)
    box(ax, 99, 55, 119, 69, CHECKPOINT, "checkpoint", ["output/checkpoint.cpp", "writes, reads each", "effect's state"],
        note="no solver", size=8.4)

    # The interfaces, each in its own header.
    box(ax, 6, 29.5, 29, 47.5, NEWTON, "NewtonHooks",
        ["begin_iteration", "cover_step", "begin_line_search", "end_line_search", "end_solve · frozen_friction"],
        size=8.6, header="newton_hooks.hpp")
    box(ax, 35, 29.5, 53, 47.5, BOTH, "Requery", ["still_valid", "refresh"], note="both solvers", size=8.6,
        header="requery.hpp")
    box(ax, 57, 29.5, 80, 47.5, BLOCK, "BlockDescentHooks", ["limit_moves", "safe_step", "vertex_bounds", "begin_sweep"],
        size=8.6, header="block_descent_hooks.hpp")
    box(ax, 84, 29.5, 97, 47.5, BLOCK, "AccelerationField", ["add_acceleration"], note="gravity", title_size=9.5,
        size=8.6, header="(same header)")
    box(ax, 100, 29.5, 119, 47.5, CHECKPOINT, "CarriedState", ["save_state", "load_state"], size=8.6,
        header="carried_state.hpp")
    box(ax, 1, 19, 119, 26, EFFECT, "Effect   (pce/sim/effect.hpp): what every solver asks of every effect",
        ["begin_step · declare · evaluate · evaluate_local · report"])

    # Calls.
    arrow(ax, (23, 76), (23, 69), NEWTON[1])
    arrow(ax, (79, 76), (79, 69), BLOCK[1])
    ax.text(51, 72.5, "StepSolver::solve(step): one solver object per mode, kept between steps", ha="center", va="center",
            fontsize=8.4, color="#444444")
    arrow(ax, (3.2, 76), (3.2, 26), SIM[1])
    ax.text(4.3, 51, "begin_step · evaluate at the accepted state · report", rotation=90, ha="center",
            va="center", fontsize=8.0, color=SIM[1])
    arrow(ax, (17.5, 55), (17.5, 47.5), NEWTON[1])
    arrow(ax, (32, 55), (32, 26), NEWTON[1])
    arrow(ax, (36, 55), (41, 47.5), NEWTON[1])
    arrow(ax, (66, 55), (48, 47.5), BLOCK[1])
    arrow(ax, (70, 55), (70, 47.5), BLOCK[1])
    arrow(ax, (82, 55), (82, 26), BLOCK[1])
    arrow(ax, (89, 55), (90.5, 47.5), BLOCK[1])
    arrow(ax, (109, 55), (109, 47.5), CHECKPOINT[1])

    # The effects, with the interfaces each implements.
    box(ax, 1, 4, 46, 14.5, EFFECT, "the elastic terms, pins, damping",
        ["stretching · bending · strand_stretching", "strand_bending · pins · damping · volume_elasticity"],
        title_size=9.5, size=8.4)
    chips(ax, 20, 5.5, ["Effect"])
    box(ax, 49, 4, 70, 14.5, EFFECT, "gravity", [], title_size=9.5)
    chips(ax, 50.0, 9.6, ["Effect"])
    chips(ax, 50.0, 6.4, ["AccelerationField"])
    box(ax, 73, 4, 119, 14.5, EFFECT, "ContactEffect   (contact_effect.hpp)",
        ["self_vertex_face · self_edge_edge · obstacle_contact"], title_size=9.5, size=8.4)
    chips(ax, 74.5, 7.9, ["Effect", "NewtonHooks", "Requery"])
    chips(ax, 74.5, 5.3, ["BlockDescentHooks", "CarriedState"])
    for x in (23.5, 59.5, 96):
        arrow(ax, (x, 14.5), (x, 19), "#777777", dashed=True)
    ax.text(60, 1.2, "calls: solid arrows, coloured by the caller (each solver finds the effects that implement "
            "its interfaces by dynamic_cast, once per step); dashed: implements", ha="center", va="center",
            fontsize=8.2, style="italic", color="#555555")

    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    fig.savefig(out, dpi=110)
    print(out)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(here, "solver_hooks.png"), help="the PNG to write")
    draw(parser.parse_args().out)


if __name__ == "__main__":
    main()
