#!/usr/bin/env python3
"""Rewrites a BVH file with the same motion expressed in another rotation
channel order (every joint with rotation channels gets three, in --order),
position channels in --position-order, and a new root OFFSET whose difference
is taken out of the root's position channels. Makes real files with other
channel orders and a non-zero root offset from one mocap file.

usage: bvh_reorder.py IN OUT --order XZY [--position-order ZXY] [--root-offset=x,y,z]
(write --root-offset=... with "=" when x is negative)
"""
import argparse
import warnings

import numpy as np

import bvh_common


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--order", required=True, help="rotation axes, e.g. XZY (intrinsic, as BVH lists them)")
    ap.add_argument("--position-order", default="ZXY")
    ap.add_argument("--root-offset", default=None, help="x,y,z")
    args = ap.parse_args()
    order, porder = args.order.upper(), args.position_order.upper()
    with open(args.input) as f:
        bvh = bvh_common.parse(f.read())

    locals_ = bvh_common.local_transforms(bvh, np.arange(len(bvh.frames)))
    new_offsets = [j.offset.copy() for j in bvh.joints]
    if args.root_offset:
        offset = np.array([float(v) for v in args.root_offset.split(",")])
        for k, j in enumerate(bvh.joints):
            if j.parent < 0:
                if not any(c.upper().endswith("POSITION") for c in j.channels):
                    raise SystemExit("root %s has no position channels; its OFFSET cannot move" % j.name)
                new_offsets[k] = offset

    columns, channels = [], []
    for k, j in enumerate(bvh.joints):
        rot, trans = locals_[k]
        present = [c[0].upper() for c in j.channels if c.upper().endswith("POSITION")]
        names, cols = [], []
        for a in porder:
            if a in present:
                names.append(a + "position")
                cols.append(trans[:, "XYZ".index(a)] - new_offsets[k]["XYZ".index(a)])
        if j.rotation_axes():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # gimbal lock: any split of the angles is the same rotation
                angles = rot.as_euler(order, degrees=True)
            names += [a + "rotation" for a in order]
            cols += [angles[:, i] for i in range(3)]
        channels.append(names)
        columns.extend(cols)

    for k, j in enumerate(bvh.joints):
        j.channels, j.offset = channels[k], new_offsets[k]
    bvh.frames = np.stack(columns, axis=1) if columns else np.zeros((len(bvh.frames), 0))
    with open(args.output, "w") as f:
        f.write(bvh_common.write(bvh))


if __name__ == "__main__":
    main()
