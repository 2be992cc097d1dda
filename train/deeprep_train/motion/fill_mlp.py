"""The short-gap fill network (issue 50): an MLP that reads the frames at a
gap's two edges and corrects the context-tangent Hermite curve across it.

At gaps of 10-45 frames the Hermite curve (motion::fill::hermite_curve,
cond.hermite_base here) is hard to beat: a learned linear kernel over the
known frames gains 0-12% on it, and the 1-D convolutional networks gain
0-5% on the validation takes. A plain MLP that sees every edge frame at
full rate is what gained here (train/notes/cond.md, 2026-12-08).

The layout (crate/src/motion/fill_mlp.rs is the runtime twin):
- `CTX` frames before the gap (the last one is a), the gap's T frames, `AFT`
  frames after it (the first one is b = a + T + 1). Fewer known frames on
  either side are padded with the outermost known one; the input says how
  many are known.
- Input x: every edge frame's joint rotations as scaled axes in the tangent
  space of that joint's rotation at a (`_step(q_a, q_f)`), and its root
  offset from a's in a's heading frame (the hips' forward axis turned into
  +z about the vertical); then T / 45, known-before / CTX, known-after / AFT.
- Output: M coefficients per channel (3 per rotating joint, 3 for the root)
  of a sine series over the gap, sin(pi m f / (T + 1)) for m = 1..M at gap
  frame f = 1..T, added to the Hermite curve in the same coordinates: zero
  at both edges, so the seams stay where the curve puts them.

Commands:
  python -m deeprep_train.motion.fill_mlp train --out cache/fill_mlp --minutes 60
  python -m deeprep_train.motion.fill_mlp look --ckpt cache/fill_mlp/gen_N.pt   (held-out training takes)
  python -m deeprep_train.motion.fill_mlp export --ckpt cache/fill_mlp/gen_N.pt --fill-from 10 --fill-up-to 45
  python -m deeprep_train.motion.fill_mlp fixture   (tests/fixtures/fill_mlp: a small random network for the Rust tests)
  python -m deeprep_train.motion.fill_mlp portable --ckpt cache/fill_mlp/gen_N.pt  (train/checkpoints/tween_fill_mlp.pt)
"""
import argparse
import json
import os
import time
import zlib

import numpy as np
import torch
import torch.nn as nn

from deeprep_train.paths import CACHE, ROOT
from deeprep_train.motion.data import take_of
from deeprep_train.motion.cond import _exp, _step, hermite_base
from deeprep_train.motion.eval import l2p_stats
from deeprep_train.motion.residual.data import Clips, Skeleton, canonical, mirror, quat_to_mat
from deeprep_train.motion.residual.net import fk
from deeprep_train.motion.residual_adv import quat_mul

CTX = 8
AFT = 8
M = 16
T_NORM = 45.0
T_RANGE = (8, 48)
HIDDEN = 384


def window_features(root, quat, T, c, A, ctx=CTX, aft=AFT):
    """One window of ctx + T + aft frames (root [n,3], quat [n,K,4], double):
    the input x [D], the Hermite curve over the gap in the network's
    coordinates (w [T,K,3], r [T,3]), and the frame (q_a [K,4], r_a [3],
    C [3,3]) to take them back. c, A: frames known before / after (>= 1)."""
    a, b = ctx - 1, ctx + T
    idx = [max(i, a - c + 1) for i in range(ctx)] + [min(b + i, b + A - 1) for i in range(aft)]
    qa, ra = quat[a], root[a]
    C, _ = canonical(root, quat, a)  # a's heading: the hips' forward axis turned into +z
    w = _step(qa.expand(len(idx), -1, -1), quat[idx])
    r = (root[idx] - ra) @ C.T
    base_r, base_q = root.clone(), quat.clone()
    hermite_base([(a, b, a - 1 if c >= 2 else None, b + 1 if A >= 2 else None)], root, quat, base_r, base_q)
    hw = _step(qa.expand(T, -1, -1), base_q[a + 1:b])
    hr = (base_r[a + 1:b] - ra) @ C.T
    x = torch.cat([w.flatten(), r.flatten(), torch.tensor([T / T_NORM, c / ctx, A / aft], dtype=w.dtype)])
    return x, hw, hr, (qa, ra, C)


def basis(T, dtype=torch.float32):
    """[T, M]: sin(pi m f / (T + 1)) at gap frames f = 1..T."""
    f = torch.arange(1, T + 1, dtype=dtype)[:, None]
    m = torch.arange(1, M + 1, dtype=dtype)[None]
    return torch.sin(torch.pi * m * f / (T + 1))


def decode(coef, hw, hr, frame):
    """Network output coef [B, M, 3K+3] (already scaled) on the Hermite curve
    (hw [B,T,K,3], hr [B,T,3]) -> root [B,T,3] and quaternions [B,T,K,4] in
    the clip's frame. frame: (q_a [B,K,4], r_a [B,3], C [B,3,3])."""
    qa, ra, C = frame
    B, T, K, _ = hw.shape
    res = torch.einsum("tm,bmc->btc", basis(T, coef.dtype), coef)
    w = hw + res[..., :3 * K].reshape(B, T, K, 3)
    r = hr + res[..., 3 * K:]
    q = quat_mul(qa[:, None].expand(-1, T, -1, -1), _exp(w))
    q = q / q.norm(dim=-1, keepdim=True)
    root = torch.einsum("btj,bjk->btk", r, C) + ra[:, None]
    return root, q


class Net(nn.Module):
    def __init__(self, d_in, channels, mean, std, out_scale, hidden=HIDDEN, ctx=CTX, aft=AFT):
        super().__init__()
        self.hidden, self.ctx, self.aft = hidden, ctx, aft
        self.register_buffer("mean", mean)
        self.register_buffer("std", std)
        self.register_buffer("out_scale", out_scale)
        self.channels = channels
        self.mlp = nn.Sequential(nn.Linear(d_in, hidden), nn.GELU(), nn.Dropout(0.1),
                                 nn.Linear(hidden, hidden), nn.GELU(), nn.Dropout(0.1),
                                 nn.Linear(hidden, M * channels))
        nn.init.zeros_(self.mlp[-1].weight)
        nn.init.zeros_(self.mlp[-1].bias)

    def forward(self, x):
        y = self.mlp((x - self.mean) / self.std).view(-1, M, self.channels)
        # the correction's size grows with the gap's length (the curve's
        # error does, about as T^2): (T / t_norm)^2, read from the input
        gain = x[:, -3:-2].square().unsqueeze(-1)
        return y * self.out_scale * gain


# training takes kept out of the fit, to pick snapshots on (about 12% of the
# training split's frames; a salsa take's second conversion goes with it)
PICK = {"indian/08", "martial/06", "salsa/09"}


def held_out(name):
    """Whether a training segment ("cls/NN.bvh@start" or "extra/...") is in
    the pick set: the takes in PICK, and every 4th cmu-extra clip."""
    file = name.split("@")[0]
    if file.startswith("extra/"):
        return zlib.crc32(file.encode()) % 4 == 0
    cls, num = file.split("/")
    return take_of(cls, int(num[:-4])) in PICK


class Data:
    def __init__(self):
        d = np.load(os.path.join(CACHE, "resid60x.npz"))
        self.skel = Skeleton(d)
        clips = Clips(d, "train")
        self.pick = np.array([held_out(n) for n in clips.names])
        self.clips = clips
        mu, sd = l2p_stats()
        self.mu, self.sd = torch.tensor(mu, dtype=torch.float32), torch.tensor(sd, dtype=torch.float32)

    def batch(self, rng, B, T, fixed=None, ctx=CTX, aft=AFT):
        """B windows with T gap frames from the fit takes (or, with fixed=(c, A,
        windows), the given windows), ctx frames before and aft after."""
        xs, hws, hrs, fr, gts, offs = [], [], [], [], [], []
        items = fixed[2] if fixed else range(B)
        for it in items:
            if fixed:
                root, quat = it
                c, A = fixed[0], fixed[1]
                off = self.skel.offsets
            else:
                root, quat = self.clips.window(ctx + T + aft, rng, among=~self.pick)
                off = self.skel.offsets
                if rng.random() < 0.5:
                    root, quat = mirror(root, quat, self.skel)
                    off = self.skel.mirror_offsets
                c = ctx if rng.random() < 0.8 else int(rng.integers(1, ctx + 1))
                A = int(rng.choice([1, aft])) if rng.random() < 0.7 else int(rng.integers(1, aft + 1))
            root, quat = root.double(), quat.double()
            x, hw, hr, frame = window_features(root, quat, T, c, A, ctx, aft)
            xs.append(x.float())
            hws.append(hw.float())
            hrs.append(hr.float())
            fr.append([v.float() for v in frame])
            gts.append((root[ctx:ctx + T].float(), quat[ctx:ctx + T].float(), root[ctx - 1].float()))
            offs.append(off)
        frame = tuple(torch.stack([f[i] for f in fr]) for i in range(3))
        gt = tuple(torch.stack([g[i] for g in gts]) for i in range(3))
        return torch.stack(xs), torch.stack(hws), torch.stack(hrs), frame, gt, torch.stack(offs)

    def positions(self, root, q, offs):
        return fk(self.skel, root, quat_to_mat(q), offs)

    def l2p(self, P, G, ra):
        """Per window: LaFAN1's L2P (motion.eval.score's normalization)."""
        off = ra.clone()
        off[:, 1] = 0
        B, T = P.shape[:2]
        Pn = ((P - off[:, None, None]).reshape(B, T, -1) - self.mu) / self.sd
        Gn = ((G - off[:, None, None]).reshape(B, T, -1) - self.mu) / self.sd
        return (Pn - Gn).norm(dim=-1).mean(1)


def loss_of(data, net, batch):
    """The batch's loss relative to the Hermite curve's L2P on the same
    windows (each batch has one gap length, so short gaps, where the curve
    is close, weigh as much as long ones), and its L2P."""
    x, hw, hr, frame, (groot, gq, ra), offs = batch
    root, q = decode(net(x), hw, hr, frame)
    P = data.positions(root, q, offs)
    G = data.positions(groot, gq, offs)
    with torch.no_grad():
        hroot, hq = decode(torch.zeros(x.shape[0], M, net.channels), hw, hr, frame)
        curve = data.l2p(data.positions(hroot, hq, offs), G, ra).mean().clamp(min=1e-3)
    l2p = data.l2p(P, G, ra).mean()
    # velocities of the normalized positions (the motion's texture, NPSS)
    vel = ((P[:, 1:] - P[:, :-1]) - (G[:, 1:] - G[:, :-1])).norm(dim=-1).mean() / data.sd.mean()
    # rotations where positions do not see them (end joints): the 6-D columns
    rot = (quat_to_mat(q)[..., :2] - quat_to_mat(gq)[..., :2]).square().mean()
    return (l2p + 2.0 * vel + 4.0 * rot) / curve, l2p


def look_windows(data, T, ctx=CTX, aft=AFT, stride=40):
    """Fixed windows of the held-out training takes (every `stride` frames)."""
    out = []
    n = ctx + T + aft
    for s0, ln, keep in zip(data.clips.starts, data.clips.lens, data.pick):
        if keep:
            out += [(data.clips.root[a:a + n], data.clips.quat[a:a + n]) for a in range(s0, s0 + ln - n + 1, stride)]
    return out


def look(data, net, lengths=(10, 20, 30, 45), afters=None):
    """L2P of the network and of the Hermite curve on the held-out training
    takes: every frame of its context known before the gap, 1 or all of
    its own after it (`afters`)."""
    afters = afters or (1, net.aft)
    net.eval()
    res = {}
    with torch.no_grad():
        for T in lengths:
            ws = look_windows(data, T, net.ctx, net.aft)
            for A in afters:
                x, hw, hr, frame, (groot, gq, ra), offs = data.batch(None, 0, T, fixed=(net.ctx, min(A, net.aft), ws),
                                                                     ctx=net.ctx, aft=net.aft)
                G = data.positions(groot, gq, offs)
                root, q = decode(net(x), hw, hr, frame)
                net_l2p = data.l2p(data.positions(root, q, offs), G, ra).mean().item()
                root, q = decode(torch.zeros(len(ws), M, hw.shape[2] * 3 + 3), hw, hr, frame)
                her = data.l2p(data.positions(root, q, offs), G, ra).mean().item()
                res[f"{T}@after{A}"] = {"windows": len(ws), "net": net_l2p, "hermite": her,
                                        "change": net_l2p / her - 1}
    net.train()
    return res


def new_net(data, rng, hidden=HIDDEN, ctx=CTX, aft=AFT):
    """Input normalization and output scale from a sample of fit windows."""
    xs, res = [], []
    for T in range(T_RANGE[0], T_RANGE[1] + 1, 8):
        x, hw, hr, frame, (groot, gq, ra), offs = data.batch(rng, 64, T, ctx=ctx, aft=aft)
        xs.append(x)
        qa, ra_, C = frame
        gw = _step(qa[:, None].expand(-1, T, -1, -1), gq)
        gr = torch.einsum("btk,bjk->btj", groot - ra_[:, None], C)
        res.append(torch.cat([(gw - hw).flatten(2), gr - hr], -1).flatten(0, 1) / (T / T_NORM) ** 2)
    x = torch.cat(xs)
    r = torch.cat(res)
    channels = r.shape[1]
    return Net(x.shape[1], channels, x.mean(0), x.std(0) + 1e-3, r.std(0) + 1e-4, hidden, ctx, aft)


def save(path, net, step, opt=None):
    torch.save({"step": step, "net": net.state_dict(), "d_in": net.mean.shape[0], "channels": net.channels,
                "hidden": net.hidden, "context": net.ctx, "after": net.aft,
                "opt": opt.state_dict() if opt else None}, path)


def load(path):
    ck = torch.load(path, weights_only=False)
    z = torch.zeros(ck["d_in"])
    net = Net(ck["d_in"], ck["channels"], z, z + 1, torch.ones(ck["channels"]), ck.get("hidden", HIDDEN),
              ck.get("context", CTX), ck.get("after", AFT))
    net.load_state_dict(ck["net"])
    return net, ck


def train(args):
    torch.set_num_threads(args.threads)
    os.makedirs(args.out, exist_ok=True)
    data = Data()
    rng = np.random.default_rng(args.seed)
    torch.manual_seed(args.seed)
    last = os.path.join(args.out, "last.pt")
    src = last if os.path.exists(last) else args.portable
    if args.resume and src and os.path.exists(src):
        net, ck = load(src)
        net.float()
        step = ck["step"]
        opt = torch.optim.AdamW(net.parameters(), args.lr, weight_decay=1e-4)
        if ck["opt"]:
            opt.load_state_dict(ck["opt"])
    else:
        net, step = new_net(data, rng, args.hidden, args.context, args.after), 0
        opt = torch.optim.AdamW(net.parameters(), args.lr, weight_decay=1e-4)
    t0 = time.time()
    log = open(os.path.join(args.out, "log.jsonl"), "a")
    while time.time() - t0 < args.minutes * 60:
        T = int(rng.integers(T_RANGE[0], T_RANGE[1] + 1))
        loss, l2p = loss_of(data, net, data.batch(rng, args.batch, T, ctx=net.ctx, aft=net.aft))
        opt.zero_grad()
        loss.backward()
        opt.step()
        step += 1
        if step % 100 == 0:
            log.write(json.dumps({"step": step, "t": round(time.time() - t0), "loss": loss.item(), "l2p": l2p.item(), "T": T}) + "\n")
            log.flush()
        if step % args.snapshot_every == 0:
            save(os.path.join(args.out, f"gen_{step}.pt"), net, step)
            save(last, net, step, opt)
    save(last, net, step, opt)
    save(os.path.join(args.out, f"gen_{step}.pt"), net, step)
    print(f"stopped at step {step}")


def export(args):
    """models/onnx/NAME.onnx (input x [batch, D] -> coef [batch, M, 3K + 3]),
    its manifest (the layout crate/src/motion/fill_mlp.rs reads, and the
    band), its parity fixture, float16 weights, and
    fixtures/runtime/NAME_motion.json: windows of the pick set and the gap
    this module makes from them with the shipped file (onnxruntime), which
    the Rust twin must reproduce."""
    import onnxruntime as ort
    from deeprep_train.motion.export import fixture
    from deeprep_train.export.util import ONNX_DIR as ONNX_DIR_DEFAULT, git_commit, write_json
    from deeprep_train.export.half_weights import convert
    net, ck = (args.net, args.ck) if getattr(args, "net", None) else load(args.ckpt)
    net.eval()
    name = args.name
    ONNX_DIR = args.dir or ONNX_DIR_DEFAULT
    if not 1 <= args.fill_from <= args.fill_up_to <= T_RANGE[1]:
        raise SystemExit(f"--fill-from and --fill-up-to must satisfy 1 <= from <= up to <= {T_RANGE[1]} "
                         "(the longest gap it trains on)")
    data = Data()
    path = os.path.join(ONNX_DIR, f"{name}.onnx")
    # fixture windows: the pick set's first segment; (T, known before, known after)
    root, quat = data.clips.root, data.clips.quat
    s0 = int(data.clips.starts[np.nonzero(data.pick)[0][0]])
    ctx, aft = net.ctx, net.aft
    cases = [(12, ctx, 1, s0 + 100), (30, min(3, ctx), aft, s0 + 400), (45, 1, min(2, aft), s0 + 700)]
    feats = [window_features(root[s:s + ctx + T + aft].double(), quat[s:s + ctx + T + aft].double(), T, c, A, ctx, aft)
             for T, c, A, s in cases]
    x = feats[0][0].float()[None]
    torch.onnx.export(net, (x,), path, input_names=["x"], output_names=["coef"], opset_version=17,
                      dynamic_axes={"x": {0: "batch"}, "coef": {0: "batch"}}, dynamo=False)
    with torch.no_grad():
        ref = net(x).numpy()
    sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
    parity = fixture(name, sess, {"x": x.numpy()}, ref, directory=ONNX_DIR)
    K = data.skel.K
    write_json(os.path.join(ONNX_DIR, f"{name}.manifest.json"), {
        "name": name,
        "kind": "fill-mlp",
        "description": (f"the short-gap fill network (train/deeprep_train/motion/fill_mlp.py; issue 50): an MLP over "
                        f"{ctx} frames before and {aft} after a gap that corrects the context-tangent Hermite curve "
                        f"across it; the `model` fill's network for gaps of {args.fill_from}-{args.fill_up_to} frames"),
        "fill_from": args.fill_from, "fill_up_to": args.fill_up_to,
        "context": ctx, "after": aft, "terms": M, "t_norm": T_NORM, "longest_gap": T_RANGE[1],
        "inputs_len": ck["d_in"], "channels": ck["channels"],
        "joints": [data.skel.names[j] for j in data.skel.rotating],
        "inputs": [{"name": "x", "shape": ["batch", ck["d_in"]],
                    "channels": "per known frame (context before, then after; padded with the outermost known "
                                "one): each rotating joint's scaled axis from its rotation at the last frame before "
                                "the gap (3K), then per frame the root's offset from that frame's in its heading "
                                "frame (3); then T / t_norm, known before / context, known after / after"}],
        "outputs": [{"name": "coef", "shape": ["batch", M, ck["channels"]],
                     "channels": "sine coefficients sin(pi m f / (T + 1)), m = 1..terms, per channel: each rotating "
                                 "joint's scaled axis (3K), then the root in the heading frame (3), added to the "
                                 "Hermite curve"}],
        "training": {"steps": int(ck["step"]), "hidden": net.hidden,
                     "checkpoint": os.path.relpath(args.ckpt, ROOT) if args.ckpt else "none (random weights)",
                     **({"recipe": args.recipe} if args.recipe else {})},
        "parity_torch_vs_onnxruntime": parity,
        "training_data": ("CMU train takes at 60 fps and cmu-extra's retargeted training clips "
                          "(train/cache/resid60x.npz), mirrored, without the pick set "
                          f"({', '.join(sorted(PICK))} and every 4th cmu-extra clip)"),
        "training_code_commit": git_commit(),
        "exporter": {"torch": torch.__version__, "onnxruntime": ort.__version__, "opset": 17},
    })
    convert(name, directory=ONNX_DIR)
    sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
    out = []
    for (T, c, A, s), (xc, hw, hr, frame) in zip(cases, feats):
        coef = torch.from_numpy(sess.run(None, {"x": xc.float()[None].numpy()})[0]).double()
        r, q = decode(coef, hw[None], hr[None], tuple(f[None] for f in frame))
        w = slice(s, s + ctx + T + aft)
        wr, wq = root[w].double(), quat[w].double()
        a, b = ctx - 1, ctx + T
        known = lambda i: {"root": wr[i].tolist(), "quat": wq[i].tolist()}
        out.append({"t": T, "before": [known(i) for i in range(a - c + 1, a + 1)],
                    "after": [known(i) for i in range(b, b + A)],
                    "root": r[0].tolist(), "quat": q[0].tolist()})
    os.makedirs(os.path.join(ONNX_DIR, "fixtures", "runtime"), exist_ok=True)
    write_json(os.path.join(ONNX_DIR, "fixtures", "runtime", f"{name}_motion.json"), {
        "model": f"{name}.onnx",
        "about": ("gaps of the pick set's first training segment: the known frames before and after each (root "
                  "position, each rotating joint's local rotation as a quaternion [w, x, y, z]) and the gap this "
                  "module fills from them with the shipped file (onnxruntime): root positions and quaternions"),
        "joints": K, "cases": out})
    print(f"exported {path} (step {ck['step']}), parity {parity:.2e}; {os.path.getsize(path)} bytes")


def test_fixture(args):
    """tests/fixtures/fill_mlp: a small network with random weights (hidden
    16, every layer random, so its correction is not zero) exported with
    its runtime fixture, for the Rust twin's tests whether or not a
    trained network is bundled."""
    torch.manual_seed(5)
    data = Data()
    d_in = (CTX + AFT) * (3 * data.skel.K + 3) + 3
    ch = 3 * data.skel.K + 3
    net = Net(d_in, ch, torch.zeros(d_in), torch.full((d_in,), 10.0), torch.full((ch,), 0.5), hidden=16)
    nn.init.normal_(net.mlp[-1].weight, std=0.3)
    args.net, args.ck, args.ckpt = net, {"step": 0, "d_in": d_in, "channels": ch}, None
    export(args)


def portable(args):
    """The snapshot's weights in float16, to resume on a new machine
    (train --resume --portable FILE)."""
    net, ck = load(args.ckpt)
    to = args.to
    os.makedirs(os.path.dirname(os.path.abspath(to)), exist_ok=True)
    torch.save({"step": ck["step"], "net": {k: v.half() for k, v in net.state_dict().items()},
                "d_in": ck["d_in"], "channels": ck["channels"], "hidden": net.hidden, "context": net.ctx,
                "after": net.aft, "opt": None}, to)
    print(f"wrote {to} (step {ck['step']}, {os.path.getsize(to) / 1e6:.1f} MB)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    t = sub.add_parser("train")
    t.add_argument("--out", default=os.path.join(CACHE, "fill_mlp"))
    t.add_argument("--minutes", type=float, default=60)
    t.add_argument("--threads", type=int, default=1)
    t.add_argument("--batch", type=int, default=64)
    t.add_argument("--lr", type=float, default=1e-3)
    t.add_argument("--seed", type=int, default=0)
    t.add_argument("--hidden", type=int, default=HIDDEN)
    t.add_argument("--context", type=int, default=CTX, help="frames before the gap it reads")
    t.add_argument("--after", type=int, default=AFT, help="frames after the gap it reads")
    t.add_argument("--snapshot-every", type=int, default=1000)
    t.add_argument("--resume", action="store_true", help="from OUT/last.pt, else from --portable")
    t.add_argument("--portable", help="a portable checkpoint (fill_mlp portable) to resume from on a new machine")
    lk = sub.add_parser("look")
    lk.add_argument("--ckpt", required=True)
    lk.add_argument("--json")
    e = sub.add_parser("export")
    e.add_argument("--ckpt", required=True)
    e.add_argument("--name", default="tween_fill_mlp")
    e.add_argument("--fill-from", type=int, default=10)
    e.add_argument("--fill-up-to", type=int, default=45)
    e.add_argument("--recipe", default="")
    e.add_argument("--dir", help="default models/onnx")
    fx = sub.add_parser("fixture")
    fx.add_argument("--dir", default=os.path.join(ROOT, "tests", "fixtures", "fill_mlp"))
    fx.add_argument("--name", default="tween_fill_mlp")
    fx.add_argument("--fill-from", type=int, default=10)
    fx.add_argument("--fill-up-to", type=int, default=30)
    fx.add_argument("--recipe", default="")
    pt = sub.add_parser("portable")
    pt.add_argument("--ckpt", required=True)
    pt.add_argument("--to", default=os.path.join(ROOT, "train", "checkpoints", "tween_fill_mlp.pt"))
    args = ap.parse_args()
    if args.cmd == "train":
        train(args)
    elif args.cmd == "look":
        torch.set_num_threads(1)
        net, ck = load(args.ckpt)
        res = look(Data(), net)
        print(json.dumps({"step": ck["step"], **res}, indent=1))
        if args.json:
            with open(args.json, "w") as f:
                json.dump({"step": ck["step"], **res}, f, indent=1)
    elif args.cmd == "fixture":
        test_fixture(args)
    elif args.cmd == "portable":
        portable(args)
    else:
        export(args)


if __name__ == "__main__":
    main()
