#!/usr/bin/env python3
"""Checks that pce::sim's includes run down its layers, never up.

    tests/tidy/include_layers.py SRC_SIM_DIR

pce::sim is built in layers, each using only its own and those below (docs/conventions.md,
"Layers of pce::sim"). Every public header of include/pce/sim belongs to one layer
(PUBLIC below), every source folder to one (FOLDERS). A file may include a pce::sim header
(public, or a source folder's) only of its own layer or a lower one, and a public header's
implementation (NAME.cpp or NAME_cgal.cpp) lives in a folder of the header's layer. Prints
every include that runs up and every misplaced implementation, and exits 1 if there is one,
or a header or folder the tables do not place.
"""
import os
import re
import sys

LAYERS = ["base", "mesh", "geometry", "assembly", "effects", "solver", "scene", "output", "run", "app"]

# Public headers (include/pce/sim/NAME.hpp) by layer.
PUBLIC = {
    "base": ["input_error", "counters", "instrumentation"],
    "mesh": ["mesh", "obj", "tet_io", "generators", "model"],
    "geometry": ["obstacle", "fcl_distance", "broad_phase", "candidates", "intersections"],
    "assembly": ["block_hessian"],
    "effects": ["effect", "contact_effect", "effects", "newton_hooks", "block_descent_hooks", "requery", "carried_state"],
    "solver": ["simulation", "start_state", "allocator"],
    "scene": ["scene"],
    "output": ["render", "frames", "checkpoint", "recording", "movie", "usd"],
    "run": ["run"],
}

# Source folders (src/sim/FOLDER) by layer.
FOLDERS = {
    "util": "base",
    "mesh": "mesh",
    "obstacles": "geometry",
    "broad_phase": "geometry",
    "geometry": "geometry",
    "assembly": "assembly",
    "effects": "effects",
    "solver": "solver",
    "scene": "scene",
    "output": "output",
    "run": "run",
    "app": "app",
}

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def layer_of_public(name):
    for layer, names in PUBLIC.items():
        if name in names:
            return layer
    return None


def main(root):
    problems = []
    rank = {name: i for i, name in enumerate(LAYERS)}
    for dirpath, _, files in os.walk(root):
        for f in sorted(files):
            if not f.endswith((".hpp", ".cpp")):
                continue
            path = os.path.join(dirpath, f)
            rel = os.path.relpath(path, root)
            parts = rel.split(os.sep)
            if parts[0] == "include":
                own = layer_of_public(os.path.splitext(f)[0])
                if own is None:
                    problems.append(f"{rel}: a public header no layer holds (add it to PUBLIC)")
                    continue
            elif parts[0] in FOLDERS:
                own = FOLDERS[parts[0]]
            else:
                if len(parts) > 1:
                    problems.append(f"{rel}: a folder no layer holds (add it to FOLDERS)")
                continue
            with open(path, encoding="utf-8") as fh:
                for number, line in enumerate(fh, 1):
                    m = INCLUDE.match(line)
                    if not m:
                        continue
                    target = m.group(2)
                    if m.group(1) == "<":
                        if not target.startswith("pce/sim/"):
                            continue
                        theirs = layer_of_public(os.path.splitext(os.path.basename(target))[0])
                        if theirs is None:
                            problems.append(f"{rel}:{number}: includes {target}, which no layer holds")
                            continue
                    else:
                        first = target.split("/")[0]
                        if "/" in target and first in FOLDERS:
                            theirs = FOLDERS[first]
                        else:  # relative to the including file's folder
                            theirs = own
                    if rank[theirs] > rank[own]:
                        problems.append(f"{rel}:{number}: {own} includes {target} ({theirs}): an include running up")
    for dirpath, _, files in os.walk(root):
        for f in sorted(files):
            rel = os.path.relpath(os.path.join(dirpath, f), root)
            folder = rel.split(os.sep)[0]
            name = re.sub(r"(_cgal)?\.cpp$", "", f)
            if not f.endswith(".cpp") or folder not in FOLDERS or layer_of_public(name) is None:
                continue
            if FOLDERS[folder] != layer_of_public(name):
                problems.append(f"{rel}: implements pce/sim/{name}.hpp ({layer_of_public(name)}) "
                                f"in a folder of layer {FOLDERS[folder]}")
    for p in problems:
        print(p)
    print(f"include_layers: {len(problems)} problem(s) in {root}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "src/sim"))
