#!/usr/bin/env python3
"""World joint positions of a BVH file at the given times, computed with SciPy
independently of the engine (reference for integration tests).

usage: bvh_fk.py FILE TIME [TIME...]
prints {"times": [...], "joints": [names], "positions": [[[x, y, z] per joint] per time]}
"""
import json
import sys

import bvh_common


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        bvh = bvh_common.parse(f.read())
    times = [float(t) for t in sys.argv[2:]]
    positions = bvh_common.world_positions(bvh, times)
    json.dump({"times": times, "joints": [j.name for j in bvh.joints], "positions": positions.tolist()}, sys.stdout)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
