"""Trains HairNet (thesis ch. 3) on the procedural hair data and reports
Table 3.2's columns on the test split.

Data (written by the Rust CLI, so the page and the training share one
generator and renderer):
    target/release/deeprep hair dataset --out train/cache/hair/data --base 20 --blends 1 --views 4

Usage:
    train/.venv/bin/python -m deeprep_train.hair.train --steps 2000 [--name full]
    train/.venv/bin/python -m deeprep_train.hair.train --steps 2000 --no-vaw --name no_vaw      # -VAW
    train/.venv/bin/python -m deeprep_train.hair.train --steps 2000 --no-col --name no_col      # -Col
    train/.venv/bin/python -m deeprep_train.hair.train --steps 2000 --no-curv --name no_curv    # -Curv
    train/.venv/bin/python -m deeprep_train.hair.train --nn                                     # NN baseline
Writes train/cache/hair/<name>.pt and a row of docs/hair_results.json.
"""
import argparse
import json
import os
import time

import numpy as np
import torch

from deeprep_train.paths import ROOT, CACHE as CACHE_ROOT  # noqa: E402
from deeprep_train.hair.model import CURV_MAX, CURV_SCALE, GRID, POINTS, POS_SCALE, HairNet, collision, curv_from, strands_from  # noqa: E402

CACHE = os.path.join(CACHE_ROOT, "hair")
N = GRID * GRID


class Data:
    def __init__(self, prefix):
        m = json.load(open(prefix + ".json"))
        self.meta = m
        self.views, self.size = m["views"], m["size"]
        self.images = np.memmap(prefix + ".images.u8", dtype=np.uint8, mode="r", shape=(m["renders"], 3, self.size, self.size))
        self.visible = np.memmap(prefix + ".visible.u8", dtype=np.uint8, mode="r", shape=(m["renders"], N, POINTS))
        self.strands = np.memmap(prefix + ".strands.f32", dtype="<f4", mode="r", shape=(m["hairs"], N, POINTS, 3))
        self.curv = np.memmap(prefix + ".curvature.f32", dtype="<f4", mode="r", shape=(m["hairs"], N, POINTS))
        self.roots = torch.tensor(m["roots"], dtype=torch.float32)           # N x 3
        self.centers = [torch.tensor(b["center"]) for b in m["body"]]
        self.radii = [torch.tensor(b["radii"]) for b in m["body"]]
        split = [h["split"] for h in m["hair"]]
        self.renders = {s: [r for r in range(m["renders"]) if split[r // self.views] == s] for s in ("train", "val", "test")}

    def batch(self, rs):
        rs = np.sort(np.asarray(rs))
        hs = rs // self.views
        img = torch.from_numpy(self.images[rs].astype(np.float32) / 255.0)
        vis = torch.from_numpy(self.visible[rs].astype(np.float32))
        pts = torch.from_numpy(np.ascontiguousarray(self.strands[hs]))
        cur = torch.from_numpy(np.ascontiguousarray(self.curv[hs]))
        return img, vis, pts, cur


def losses(net, data, img, vis, pts, cur, vaw=True):
    _, pos, curv = net(img)
    p = strands_from(pos)                 # metres
    c = curv_from(curv)                   # 1/m
    w = (vis * 9.9 + 0.1) if vaw else torch.ones_like(vis)   # eq. 3.2: 10 visible, 0.1 otherwise
    l_pos = (w * (((p - pts) / POS_SCALE) ** 2).sum(-1)).mean()
    l_curv = (w * ((c - cur.clamp(max=CURV_MAX)) / CURV_SCALE) ** 2).mean()
    l_col = collision(p + data.roots[None, :, None, :], data.centers, data.radii).mean()
    return l_pos, l_curv, l_col, p, c


def evaluate(predict, data, split="test", batch=16):
    """Table 3.2's columns: mean square distance (m^2) on visible and on
    invisible samples, and the collision error (eq. 3.3) of the prediction."""
    sv = nv = si = ni = 0.0
    col = []
    dist_v = dist_i = 0.0
    rs = data.renders[split]
    for k in range(0, len(rs), batch):
        img, vis, pts, _ = data.batch(rs[k:k + batch])
        p = predict(img, rs[k:k + batch])
        d2 = ((p - pts) ** 2).sum(-1)
        d = d2.sqrt()
        sv += (d2 * vis).sum().item()
        nv += vis.sum().item()
        si += (d2 * (1 - vis)).sum().item()
        ni += (1 - vis).sum().item()
        dist_v += (d * vis).sum().item()
        dist_i += (d * (1 - vis)).sum().item()
        col.append(collision(p + data.roots[None, :, None, :], data.centers, data.radii))
    return {"visible_pos_error_m2": sv / max(nv, 1), "invisible_pos_error_m2": si / max(ni, 1),
            "visible_mean_distance_cm": 100 * dist_v / max(nv, 1), "invisible_mean_distance_cm": 100 * dist_i / max(ni, 1),
            "collision_error": torch.cat(col).mean().item(), "eval_renders": len(rs), "eval_split": split, "visible_fraction": nv / max(nv + ni, 1)}


def save_result(name, res):
    out = os.path.join(ROOT, "docs", "hair_results.json")
    allr = json.load(open(out)) if os.path.exists(out) else {}
    allr[name] = res
    with open(out, "w") as f:
        json.dump(allr, f, indent=1)
        f.write("\n")


def nearest_neighbour(data):
    """Chai et al.'s first step as Table 3.2's NN row: the training render
    whose image (hair and body pixels, 64 x 64) is closest, and its hair."""
    def small(rs):
        x = torch.from_numpy(data.images[np.sort(np.asarray(rs))].astype(np.float32) / 255.0)
        return torch.nn.functional.avg_pool2d(x, data.size // 64).flatten(1)
    train = data.renders["train"]
    feats = torch.cat([small(train[k:k + 256]) for k in range(0, len(train), 256)])

    def predict(img, rs):
        q = torch.nn.functional.avg_pool2d(img, data.size // 64).flatten(1)
        nn_idx = torch.cdist(q, feats).argmin(1)
        hs = [train[i] // data.views for i in nn_idx.tolist()]
        return torch.from_numpy(np.stack([np.asarray(data.strands[h]) for h in hs]))
    return predict


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=25)
    ap.add_argument("--steps", type=int, default=0, help="train exactly this many steps instead of --minutes (equal-budget ablations)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--batch", type=int, default=16)
    ap.add_argument("--div", type=int, default=8, help="divide Table B.1's channel widths by this")
    ap.add_argument("--lr", type=float, default=5e-4)
    ap.add_argument("--col-weight", type=float, default=1.0)
    ap.add_argument("--no-vaw", action="store_true")
    ap.add_argument("--no-col", action="store_true")
    ap.add_argument("--no-curv", action="store_true")
    ap.add_argument("--nn", action="store_true", help="evaluate the nearest-neighbour baseline only")
    ap.add_argument("--name", default=None)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    data = Data(os.path.join(CACHE, "data"))
    meta = {"hairs": data.meta["hairs"], "renders": data.meta["renders"], "split_counts": data.meta["split_counts"],
            "train_renders": len(data.renders["train"]), "test_renders": len(data.renders["test"])}
    if args.nn:
        t0 = time.time()
        res = evaluate(nearest_neighbour(data), data)
        res.update(meta, model="nn", seconds=round(time.time() - t0, 1))
        print(json.dumps(res), flush=True)
        save_result("nn", res)
        return
    name = args.name or "full"
    net = HairNet(args.div)
    params = sum(p.numel() for p in net.parameters())
    opt = torch.optim.Adam(net.parameters(), lr=args.lr)
    rng = np.random.default_rng(args.seed)
    train = np.asarray(data.renders["train"])
    t0, step = time.time(), 0
    log = open(os.path.join(CACHE, f"{name}.log"), "w")
    while (step < args.steps) if args.steps else (time.time() - t0 < args.minutes * 60):
        img, vis, pts, cur = data.batch(rng.choice(train, args.batch, replace=False))
        l_pos, l_curv, l_col, _, _ = losses(net, data, img, vis, pts, cur, vaw=not args.no_vaw)
        loss = l_pos + (0.0 if args.no_curv else 1.0) * l_curv + (0.0 if args.no_col else args.col_weight) * l_col
        opt.zero_grad()
        loss.backward()
        opt.step()
        step += 1
        if step % 50 == 0:
            line = json.dumps({"model": name, "step": step, "pos": round(l_pos.item(), 5), "curv": round(l_curv.item(), 5),
                               "col": float(f"{l_col.item():.3g}"), "sec": round(time.time() - t0)})
            print(line, flush=True)
            log.write(line + "\n")
            log.flush()
    net.eval()
    with torch.no_grad():
        res = evaluate(lambda img, rs: strands_from(net(img)[1]), data)
    res.update(meta, model=name, steps=step, minutes=round((time.time() - t0) / 60, 1), params=params, div=args.div,
               losses={"vaw": not args.no_vaw, "col": not args.no_col, "curv": not args.no_curv, "col_weight": args.col_weight},
               batch=args.batch, lr=args.lr)
    print(json.dumps(res), flush=True)
    torch.save({"net": net.state_dict(), "div": args.div, "result": res}, os.path.join(CACHE, f"{name}.pt"))
    save_result(name, res)


if __name__ == "__main__":
    main()
