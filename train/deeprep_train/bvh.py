"""BVH on the training side, once: the hierarchy, the motion, resampling
to 60 fps, and forward kinematics with numpy. The crate's reader and FK
(crate/src/skeleton) are the full ones; tests/parity/test_fk.py checks
this FK against theirs on a fixture both sides read
(tests/fixtures/fk_native.json)."""
import numpy as np


def read_hierarchy(text: str):
    names, parents, offsets, channels = [], [], [], []
    stack = []
    pending = None
    for line in text.splitlines():
        t = line.split()
        if not t:
            continue
        if t[0] in ("ROOT", "JOINT"):
            pending = (" ".join(t[1:]), False)
        elif t[0] == "End":
            pending = (names[stack[-1]] + "_Nub", True)
        elif t[0] == "{":
            names.append(pending[0])
            parents.append(stack[-1] if stack else None)
            offsets.append(None)
            channels.append([])
            stack.append(len(names) - 1)
        elif t[0] == "}":
            stack.pop()
        elif t[0] == "OFFSET":
            offsets[stack[-1]] = [float(x) for x in t[1:4]]
        elif t[0] == "CHANNELS":
            channels[stack[-1]] = t[2:]
        elif t[0] == "MOTION":
            break
    return names, parents, offsets, channels


def resample(src, dst, step):
    text = open(src).read()
    head, motion = text.split("MOTION", 1)
    lines = [x for x in motion.strip().splitlines()[2:] if x.strip()]
    lines = lines[::step]
    with open(dst, "w") as f:
        f.write(head + f"MOTION\nFrames: {len(lines)}\nFrame Time: {1 / 60:.8f}\n" + "\n".join(lines) + "\n")
    return len(lines)


def read_bvh(path):
    """Names, parents (-1 for the root), offsets, channel lists and the motion matrix."""
    text = open(path).read()
    head, motion = text.split("MOTION", 1)
    names, parents, offsets, chans = read_hierarchy(head)
    parents = [-1 if p is None else p for p in parents]
    rows = [x for x in motion.strip().splitlines()[2:] if x.strip()]
    data = np.array([[float(v) for v in r.split()] for r in rows], dtype=np.float64)
    return names, parents, np.array(offsets), chans, data


def axis_rot(axis, a):
    c, s = np.cos(a), np.sin(a)
    o, z = np.ones_like(a), np.zeros_like(a)
    if axis == "X":
        m = [[o, z, z], [z, c, -s], [z, s, c]]
    elif axis == "Y":
        m = [[c, z, s], [z, o, z], [-s, z, c]]
    else:
        m = [[c, -s, z], [s, c, z], [z, z, o]]
    return np.stack([np.stack(r, -1) for r in m], -2)


def local_fk(bvh):
    """Per-joint translations [F, J, 3] (offset plus position channels) and
    local rotation matrices [F, J, 3, 3]."""
    names, _, offsets, chans, data = bvh
    F, J = len(data), len(names)
    trans = np.broadcast_to(offsets, (F, J, 3)).copy()
    rot = np.zeros((F, J, 3, 3))
    col = 0
    for j in range(J):
        r = np.broadcast_to(np.eye(3), (F, 3, 3)).copy()
        for c in chans[j]:
            v = data[:, col]
            col += 1
            if c.endswith("rotation"):
                r = r @ axis_rot(c[0], np.radians(v))
            else:
                trans[:, j, "XYZ".index(c[0])] += v
        rot[:, j] = r
    return trans, rot


def fk_from_local(bvh, trans, loc):
    """Global positions [F, J, 3] and rotations [F, J, 3, 3] from local_fk's
    translations and local rotations on bvh's skeleton."""
    parents = bvh[1]
    F, J = loc.shape[:2]
    rot, pos = np.zeros_like(loc), np.zeros((F, J, 3))
    for j in range(J):
        p = parents[j]
        if p < 0:
            rot[:, j], pos[:, j] = loc[:, j], trans[:, j]
        else:
            pos[:, j] = pos[:, p] + np.einsum("fij,fj->fi", rot[:, p], trans[:, j])
            rot[:, j] = rot[:, p] @ loc[:, j]
    return pos, rot


def global_fk(bvh):
    """Global positions [F, J, 3] and rotation matrices [F, J, 3, 3]."""
    return fk_from_local(bvh, *local_fk(bvh))


def mat_to_quat(m):
    """Unit quaternions [w, x, y, z] (w >= 0) of rotation matrices [..., 3, 3]."""
    w = np.sqrt(np.clip(1 + m[..., 0, 0] + m[..., 1, 1] + m[..., 2, 2], 0, None)) / 2
    x = np.copysign(np.sqrt(np.clip(1 + m[..., 0, 0] - m[..., 1, 1] - m[..., 2, 2], 0, None)) / 2, m[..., 2, 1] - m[..., 1, 2])
    y = np.copysign(np.sqrt(np.clip(1 - m[..., 0, 0] + m[..., 1, 1] - m[..., 2, 2], 0, None)) / 2, m[..., 0, 2] - m[..., 2, 0])
    z = np.copysign(np.sqrt(np.clip(1 - m[..., 0, 0] - m[..., 1, 1] + m[..., 2, 2], 0, None)) / 2, m[..., 1, 0] - m[..., 0, 1])
    q = np.stack([w, x, y, z], -1)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def mirror_joints(names):
    """Each joint's left/right counterpart by name (itself on the midline):
    "left"/"right" and l/r prefixes before a capital swapped. The map a
    left/right mirror (x -> -x) of a pose applies to its joints."""
    def other(n):
        for a, b in (("left", "right"), ("right", "left")):
            if n.startswith(a):
                return b + n[len(a):]
        if n[:1] in "lr" and n[1:2].isupper():
            return ("r" if n[0] == "l" else "l") + n[1:]
        return n
    idx = {n: i for i, n in enumerate(names)}
    return [idx.get(other(n), i) for i, n in enumerate(names)]
