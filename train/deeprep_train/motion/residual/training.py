"""The residual network's training loop (resumable; the adversarial stage from residual_adv).

Part of deeprep_train.motion.residual (see its package docstring)."""
import copy
import json
import os
import time

import numpy as np
import torch

from deeprep_train.motion.residual_adv import Adversary
from deeprep_train.motion.residual.data import Clips, Skeleton
from deeprep_train.motion.residual.net import ResidualTween, grow, load_ema
from deeprep_train.motion.residual.losses import losses, make_batch
from deeprep_train.motion.residual.evaluation import l2p_sd


def train(args):
    torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    if args.cross_clip > 0 and args.gan_weight <= 0:
        raise SystemExit("--cross-clip needs --gan-weight > 0: a cross-clip window has no ground truth, "
                         "only the adversarial loss")
    rng = np.random.default_rng(args.seed)
    d = np.load(args.data)
    skel = Skeleton(d)
    keep = None
    if args.d2_filter:
        f = np.load(args.d2_filter)
        keep = f["keep"]
        print(f"D.2 filter {args.d2_filter}: {json.loads(str(f['summary']))}", flush=True)
    clips = Clips(d, "train", keep)
    dev = torch.device(args.device)
    ck = os.path.join(args.out, "ckpt.pt")
    # what --resume starts from: the run's own checkpoint (with its optimizer
    # state), else the committed float16 one; read once
    src = None
    if args.resume:
        src = ck if os.path.exists(ck) else args.portable if os.path.exists(args.portable) else None
    s = torch.load(src, map_location="cpu") if src else None
    if s is not None and s["width"] != args.width:
        # a resumed run keeps its checkpoint's width (e.g. a pruned network)
        print(f"{src} has width {s['width']}: training at {s['width']}, not --width {args.width}", flush=True)
        args.width = s["width"]
    if args.stride is None:
        # the checkpoint's stride unless one is asked for (a stride-1 network
        # resumed with --stride 2 keeps its weights and learns to run at 30 fps)
        args.stride = s.get("stride", 1) if s is not None else 1
    # --skip adds the full-rate skip to a resumed network; a checkpoint with one keeps it
    args.skip = bool(args.skip or (s is not None and s.get("skip", False)))
    net = ResidualTween(skel.K, args.width, args.dilations, args.stride, args.skip)
    ema = copy.deepcopy(net)
    step, opt_state = 0, None
    os.makedirs(args.out, exist_ok=True)
    if s is not None:
        added = grow(net, s["net"], args.dilations)
        grow(ema, s["ema"], args.dilations)
        opt_state = None if added else s.get("opt")
        step = s["step"]
        rng = np.random.default_rng(args.seed + step)
        fresh = " (fresh optimizer state)" if opt_state is None else ""
        print(f"resumed {src} at step {step}" + (f", {len(added)} new tensors" if added else "") + fresh, flush=True)
    net.to(dev)
    ema.to(dev)
    opt = torch.optim.Adam(net.parameters(), lr=args.lr)
    if opt_state is not None:
        opt.load_state_dict(opt_state)  # moves the state to the parameters' device
    for g in opt.param_groups:
        g["lr"] = args.lr
    print(f"device: {dev}", flush=True)
    print(f"parameters: {sum(p.numel() for p in net.parameters()):,}", flush=True)
    w = {"pos": 1.0, "rot": 0.5, "root": 1.0, "vel": 1.0, "speed": args.speed_weight, "foot": args.foot_weight,
         "l2p": args.l2p_weight, "spectral": args.spectral_weight, "gan": args.gan_weight,
         "distill": args.distill_weight, "distill_speed": args.distill_speed_weight}
    teacher = None
    if args.distill_speed_weight > 0 and not args.teacher:
        raise SystemExit("--distill-speed-weight needs --teacher")
    if args.teacher:
        if args.distill_weight <= 0:
            raise SystemExit("--teacher needs --distill-weight > 0")
        teacher = load_ema(args.teacher, dev)  # run under no_grad in `losses`
        print(f"teacher {args.teacher}: {teacher.arch()}", flush=True)
    skel.inv_sd = torch.from_numpy(1.0 / l2p_sd()).float().to(dev)
    # the adversarial stage (residual_adv): a discriminator, carried in the checkpoint
    adv = Adversary(len(skel.parents), args.lr_d, dev) if args.gan_weight > 0 else None

    def draw():
        return make_batch(clips, skel, args.batch, args.frames, rng, args.mirror, args.cross_clip, args.regular_keys,
                          args.fill_share, args.fill_gaps, args.fill_law)

    if adv is not None and not (s is not None and adv.load(s)):
        # no discriminator yet: train one against the network as it is first
        for i in range(args.d_warmup):
            batch, _, sup = draw()
            batch = [x.to(dev, non_blocking=True) for x in batch]
            with torch.no_grad():
                o = losses(net, skel, batch, w, sup, adv, args.gan_min_gap)
            ld = adv.d_step(o["_grel"], o["_rel"]) if "_grel" in o else None
            if (i + 1) % 50 == 0:
                print(json.dumps({"d_warmup": i + 1, "D": ld}), flush=True)
    log = open(os.path.join(args.out, "log.jsonl"), "a")
    t0, last = time.time(), time.time()
    acc = {}

    def save():
        state = {"net": net.state_dict(), "ema": ema.state_dict(), "opt": opt.state_dict(), "step": step,
                 **net.arch()}
        if adv is not None:
            state.update(adv.state())
        torch.save(state, ck + ".tmp")
        os.replace(ck + ".tmp", ck)

    while time.time() - t0 < args.minutes * 60:
        batch, _, sup = draw()
        batch = [x.to(dev, non_blocking=True) for x in batch]
        out = losses(net, skel, batch, w, sup, adv, args.gan_min_gap, teacher)
        opt.zero_grad()
        out["total"].backward()
        torch.nn.utils.clip_grad_norm_(net.parameters(), 1.0)
        opt.step()
        if adv is not None and "_grel" in out:
            out["D"] = torch.tensor(adv.d_step(out["_grel"], out["_rel"]))
        out["supervised"] = sup.float().mean()
        for k in [k for k in out if k.startswith("_")]:
            del out[k]
        with torch.no_grad():
            for pe, pn in zip(ema.parameters(), net.parameters()):
                pe.mul_(args.ema).add_(pn, alpha=1 - args.ema)
        step += 1
        for k, v in out.items():
            acc[k] = acc.get(k, 0.0) + float(v.detach())
        if step % 50 == 0:
            rec = {"step": step, "t": round(time.time() - t0), **{k: v / 50 for k, v in acc.items()}}
            log.write(json.dumps(rec) + "\n")
            log.flush()
            acc = {}
            if time.time() - last > 60:
                print(json.dumps(rec), flush=True)
                last = time.time()
        if step % args.save_every == 0:
            save()
            if step % args.snapshot_every == 0:
                torch.save({"ema": ema.state_dict(), "step": step, **net.arch()},
                           os.path.join(args.out, f"gen_{step}.pt"))
    save()
    print(f"done at step {step}", flush=True)
