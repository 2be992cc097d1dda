"""A minimal BVH hierarchy reader for the training side (names, parents,
offsets, channels). The crate's reader is the full one."""


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
