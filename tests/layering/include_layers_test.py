#!/usr/bin/env python3
"""The include graph between LRay's source folders runs one way.

Every folder of src/ (and bindings/) has a layer (README.md, "Layout"); a
file may include headers of its own folder and of folders in lower layers
only. So the pipeline runs one way (render calls the backends, never the
reverse), there is no loop between folders, and a new folder must be given
its layer here before it can be used.
"""
import argparse
import os
import re
import sys

# The layers, lowest first; folders in one layer do not include each other.
LAYERS = [
    ["math", "util"],                                               # numbers, records, errors
    ["geometry/shapes", "shading/lights", "shading/pigments"],      # the kinds
    ["scene"],                                                      # the scene model
    ["geometry"],                                                   # entities' ray tests
    ["shading", "accel", "bindings"],                               # integrator, interface, Lua
    ["accel/embree", "accel/kdtree"],                               # the backends
    ["render"],                                                     # backends x integrators, tiles
    ["run"],                                                        # options -> run plan
    ["app/watch", "compare"],                                       # live preview; lray-compare
    ["app"],                                                        # the programs
]
LAYER = {folder: i for i, folders in enumerate(LAYERS) for folder in folders}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def folder_of(root, path):
    rel = os.path.relpath(path, root)
    return "bindings" if rel.startswith("bindings" + os.sep) else os.path.dirname(
        os.path.relpath(path, os.path.join(root, "src")))


def check(root):
    problems = []
    for top in ("src", "bindings"):
        for dirpath, _, files in os.walk(os.path.join(root, top)):
            for name in sorted(files):
                if not name.endswith((".h", ".cpp")):
                    continue
                path = os.path.join(dirpath, name)
                here = folder_of(root, path)
                if here not in LAYER:
                    problems.append(f"{os.path.relpath(path, root)}: folder '{here}' has no layer "
                                    "in tests/layering/include_layers_test.py")
                    continue
                with open(path, encoding="utf-8") as f:
                    for number, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        if not m:
                            continue
                        target = m.group(1)
                        if os.path.exists(os.path.join(root, "src", target)):
                            there = os.path.dirname(target)
                        elif target.startswith("bindings/") and os.path.exists(os.path.join(root, target)):
                            there = "bindings"
                        else:
                            continue  # a system header, or one of the file's own folder
                        if there == here:
                            continue
                        if there not in LAYER or LAYER[there] >= LAYER[here]:
                            problems.append(
                                f"{os.path.relpath(path, root)}:{number}: '{here}' (layer "
                                f"{LAYER[here]}) includes {target} of '{there}' (layer "
                                f"{LAYER.get(there, '?')}): a folder includes only lower layers")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--root", default=os.path.join(os.path.dirname(__file__), "..", ".."))
    args = parser.parse_args()
    problems = check(os.path.abspath(args.root))
    for p in problems:
        print(p)
    # The checker itself: a file of accel/ including render/ must be caught.
    if "render" in LAYER and LAYER["render"] <= LAYER["accel"]:
        print("the layer table puts render at or below accel")
        return 1
    print(f"include layers: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
