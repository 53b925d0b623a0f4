"""A small BVH model shared by the reference scripts: parse, write, and local
joint transforms with SciPy. Independent of the C++ engine on purpose: the
engine is checked against it."""

import numpy as np
from scipy.spatial.transform import Rotation, Slerp


class Joint:
    def __init__(self, name, parent):
        self.name = name
        self.parent = parent
        self.offset = np.zeros(3)
        self.channels = []  # "Xposition" ... "Zrotation", file order
        self.end_site = None

    def rotation_axes(self):
        return "".join(c[0].upper() for c in self.channels if c.upper().endswith("ROTATION"))


class Bvh:
    def __init__(self):
        self.joints = []
        self.frame_time = 0.0
        self.frames = np.zeros((0, 0))  # frames x columns

    def columns(self):
        """Column index range of each joint's channels in a frame row."""
        out, col = [], 0
        for j in self.joints:
            out.append(range(col, col + len(j.channels)))
            col += len(j.channels)
        return out


def parse(text):
    tokens = text.split()
    bvh, stack, i, in_end_site = Bvh(), [], 0, False

    def take():
        nonlocal i
        i += 1
        return tokens[i - 1]

    while i < len(tokens):
        tok = take()
        up = tok.upper()
        if up in ("ROOT", "JOINT"):
            bvh.joints.append(Joint(take(), stack[-1] if stack else -1))
            stack.append(len(bvh.joints) - 1)
        elif up == "END":
            take()  # Site
            in_end_site = True
        elif up == "OFFSET":
            v = np.array([float(take()) for _ in range(3)])
            if in_end_site:
                bvh.joints[stack[-1]].end_site = v
            else:
                bvh.joints[stack[-1]].offset = v
        elif up == "CHANNELS":
            n = int(take())
            bvh.joints[stack[-1]].channels = [take() for _ in range(n)]
        elif tok == "}":
            if in_end_site:
                in_end_site = False
            else:
                stack.pop()
        elif up == "MOTION":
            break
    take()  # Frames:
    n = int(take())
    take(), take()  # Frame Time:
    bvh.frame_time = float(take())
    cols = sum(len(j.channels) for j in bvh.joints)
    values = np.array([float(t) for t in tokens[i:]])
    if values.size != n * cols:
        raise ValueError("expected %d values, found %d" % (n * cols, values.size))
    bvh.frames = values.reshape(n, cols)
    return bvh


def write(bvh):
    lines, open_joints = ["HIERARCHY"], []

    def fmt(v):
        return " ".join("%.8f" % x for x in v)

    def close():
        j = bvh.joints[open_joints.pop()]
        pad = "\t" * len(open_joints)
        if j.end_site is not None:
            lines.extend([pad + "\tEnd Site", pad + "\t{", pad + "\t\tOFFSET " + fmt(j.end_site), pad + "\t}"])
        lines.append(pad + "}")

    for idx, j in enumerate(bvh.joints):
        while open_joints and open_joints[-1] != j.parent:
            close()
        pad = "\t" * len(open_joints)
        lines.append(pad + ("ROOT " if j.parent < 0 else "JOINT ") + j.name)
        lines.append(pad + "{")
        lines.append(pad + "\tOFFSET " + fmt(j.offset))
        lines.append((pad + "\tCHANNELS %d %s" % (len(j.channels), " ".join(j.channels))).rstrip())
        open_joints.append(idx)
    while open_joints:
        close()
    lines += ["MOTION", "Frames: %d" % len(bvh.frames), "Frame Time: %r" % bvh.frame_time]
    lines += [fmt(row) for row in bvh.frames]
    return "\n".join(lines) + "\n"


def local_transforms(bvh, frames):
    """Per joint: (Rotation stack over `frames`, translations frames x 3).
    Rotation channels compose intrinsically in the order listed (SciPy's
    uppercase axes); position channels add to the OFFSET."""
    out = []
    rows = bvh.frames[frames]
    for j, cols in zip(bvh.joints, bvh.columns()):
        trans = np.tile(j.offset, (len(frames), 1))
        angles, axes = [], ""
        for c, col in zip(j.channels, cols):
            k = "XYZ".index(c[0].upper())
            if c.upper().endswith("ROTATION"):
                axes += c[0].upper()
                angles.append(rows[:, col])
            else:
                trans[:, k] += rows[:, col]
        if axes:
            rot = Rotation.from_euler(axes, np.stack(angles, axis=1), degrees=True)
        else:
            rot = Rotation.identity(len(frames))
        out.append((rot, trans))
    return out


def world_positions(bvh, times):
    """World joint positions (times x joints x 3): neighbouring frames'
    local rotations slerped and translations lerped, then FK."""
    n = len(bvh.frames)
    x = np.clip(np.asarray(times, dtype=float) / bvh.frame_time, 0, n - 1)
    i0 = np.minimum(np.floor(x).astype(int), n - 1)
    i1 = np.minimum(i0 + 1, n - 1)
    u = x - i0
    a, b = local_transforms(bvh, i0), local_transforms(bvh, i1)
    result = np.zeros((len(times), len(bvh.joints), 3))
    world_rot = [None] * len(bvh.joints)
    for j, joint in enumerate(bvh.joints):
        rots = []
        for t in range(len(times)):
            pair = Rotation.concatenate([a[j][0][t], b[j][0][t]])
            rots.append(Slerp([0.0, 1.0], pair)([u[t]])[0])
        rot = Rotation.concatenate(rots)
        trans = (1 - u)[:, None] * a[j][1] + u[:, None] * b[j][1]
        if joint.parent < 0:
            world_rot[j], result[:, j] = rot, trans
        else:
            p = joint.parent
            world_rot[j] = world_rot[p] * rot
            result[:, j] = result[:, p] + world_rot[p].apply(trans)
    return result
