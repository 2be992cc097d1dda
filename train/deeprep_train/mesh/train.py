"""Trains the fully convolutional mesh autoencoder (thesis ch. 2) on posed
robot meshes and reports Table 2.2-style numbers.

Data (written by the Rust CLI, so Rust and Python share one sampler):
    cargo build --release --bin deeprep
    target/release/deeprep mesh topology ../shared/data/gltf/RobotExpressive.glb --out train/cache/mesh/topology.json
    target/release/deeprep mesh poses ../shared/data/gltf/RobotExpressive.glb --out train/cache/mesh/train --random 3000 --seed 1
    target/release/deeprep mesh poses ../shared/data/gltf/RobotExpressive.glb --out train/cache/mesh/test --random 300 --seed 2 --fps 30
Split: by clip (TEST_CLIPS are held out from both pose files' clip frames)
and by random seed (seed 1 random poses train, seed 2 test).

Any other template (issue 25): a topology file and two pose files of it
(`deeprep mesh topology`, `mesh deform` or `mesh poses --subdivide`), e.g.
    target/release/deeprep mesh shape tet --out T/tet.obj
    target/release/deeprep mesh topology T/tet.obj --out T/tet.topology.json
    target/release/deeprep mesh deform T/tet.obj --out T/tet.train --count 2000 --seed 1
    target/release/deeprep mesh deform T/tet.obj --out T/tet.test --count 200 --seed 2
    train/.venv/bin/python -m deeprep_train.mesh.train --topology T/tet.topology.json --train T/tet.train --test T/tet.test --name tet
A user's own posed meshes of a template (an OBJ sequence) become a pose file
with `deeprep mesh pack TEMPLATE.obj POSE1.obj ... --out PREFIX`.
Test poses are the test file's held-out clips and its random, deformed or
packed poses; a pose file that lists "interior" vertices (a solid) gets their
error reported apart from the surface's.

Usage: train/.venv/bin/python -m deeprep_train.mesh.train --minutes 10 [--residual vd|avg|none] [--threads 1] [--m M]
       train/.venv/bin/python -m deeprep_train.mesh.train --steps 4602 --residual avg   (equal-step ablation)
Writes train/cache/mesh/<name>.pt and adds a row to docs/mesh_results.json.
"""
import argparse
import json
import os
import time

import numpy as np
import torch

from deeprep_train.paths import ROOT, CACHE as CACHE_ROOT  # noqa: E402
from deeprep_train.mesh.model import MeshAE, load_topology  # noqa: E402

CACHE = os.path.join(CACHE_ROOT, "mesh")
TEST_CLIPS = {"Wave", "Punch"}


def load_poses(prefix, keep):
    meta = json.load(open(prefix + ".json"))
    x = np.fromfile(prefix + ".f32", dtype="<f4").reshape(meta["poses"], meta["vertices"], 3)
    sel = [i for i, l in enumerate(meta["labels"]) if keep(l)]
    return x[sel]


def default_widths(levels):
    """Channels per level: 3 in, doubling from 16 up to 128, 16 at the latent
    level; (3, 16, 32, 64, 16) for the robot's four levels."""
    return (3,) + tuple(min(16 * 2 ** k, 128) for k in range(levels - 1)) + (16,)


def laplacian(x, nbr, nmask):
    """Uniform Laplacian coordinates: x_i - mean of its neighbours."""
    g = x[:, nbr] * nmask[None, :, :, None]
    return x - g.sum(2) / nmask.sum(1).clamp(min=1)[None, :, None]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=10)
    ap.add_argument("--steps", type=int, default=0, help="train exactly this many steps instead of --minutes (for equal-budget ablations)")
    ap.add_argument("--residual", default="vd", choices=["vd", "avg", "none"])
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--batch", type=int, default=16)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--lap-weight", type=float, default=1.0)
    ap.add_argument("--m", type=int, default=None, help="kernel basis size M of every vcConv (Table 2.2); default: "
                                                     "each level's mean neighbourhood size")
    ap.add_argument("--topology", default=os.path.join(CACHE, "topology.json"))
    ap.add_argument("--train", default=os.path.join(CACHE, "train"), help="training pose file prefix")
    ap.add_argument("--test", default=os.path.join(CACHE, "test"), help="test pose file prefix")
    ap.add_argument("--name", default=None, help="result name (default: from --residual)")
    args = ap.parse_args()
    torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    topo = load_topology(args.topology)
    train = load_poses(args.train, lambda l: l["clip"] not in TEST_CLIPS)
    test = np.concatenate([
        load_poses(args.test, lambda l: l["clip"] in TEST_CLIPS),
        load_poses(args.test, lambda l: l["clip"] in ("random", "deform", "pose")),
    ])
    interior = json.load(open(args.test + ".json")).get("interior", [])
    rest = np.array(topo["rest"], dtype=np.float32)
    center = rest.mean(0)
    height = float(rest[:, 1].max() - rest[:, 1].min())
    bbox = float(np.linalg.norm(rest.max(0) - rest.min(0)))
    norm = lambda a: torch.tensor((a - center) / height)
    xtr, xte = norm(train), norm(test)
    n = len(rest)
    # neighbour table of the welded mesh for the Laplacian loss
    adj = [[] for _ in range(n)]
    for a, b in topo["edges"]:
        adj[a].append(b)
        adj[b].append(a)
    w = max(len(a) for a in adj)
    nbr = torch.tensor([a + [0] * (w - len(a)) for a in adj])
    nmask = torch.tensor([[1.0] * len(a) + [0.0] * (w - len(a)) for a in adj])
    residual = None if args.residual == "none" else args.residual
    widths = default_widths(len(topo["levels"]))
    net = MeshAE(topo, widths=widths, m=args.m, residual=residual)
    params = sum(p.numel() for p in net.parameters())
    opt = torch.optim.Adam(net.parameters(), lr=1e-3)
    g = torch.Generator().manual_seed(args.seed)
    t0, step = time.time(), 0
    name = args.name or {"vd": "full", "avg": "avgpool", "none": "noresidual"}[args.residual]
    while (step < args.steps) if args.steps else (time.time() - t0 < args.minutes * 60):
        idx = torch.randint(0, len(xtr), (args.batch,), generator=g)
        x = xtr[idx]
        y = net(x)
        loss = (y - x).abs().mean() + args.lap_weight * (laplacian(y, nbr, nmask) - laplacian(x, nbr, nmask)).abs().mean()
        opt.zero_grad()
        loss.backward()
        opt.step()
        step += 1
        if step % 100 == 0:
            print(json.dumps({"model": name, "step": step, "loss": round(loss.item(), 6), "sec": round(time.time() - t0)}), flush=True)
    net.eval()
    with torch.no_grad():
        errs = torch.cat([(net(xte[i:i + 32]) - xte[i:i + 32]).norm(dim=-1) for i in range(0, len(xte), 32)]) * height
    res = {"model": name, "steps": step, "minutes": round((time.time() - t0) / 60, 1), "params": params, "train_poses": len(xtr), "test_poses": len(xte),
           "mean_error": errs.mean().item(), "max_error": errs.max().item(), "mean_error_pct_bbox": 100 * errs.mean().item() / bbox,
           "latent": list(net.encode(xte[:1]).shape[1:]), "units": "the mesh's units (it is %.2f tall)" % height,
           "vertices": n, "levels": [len(rest)] + [len(l["selected"]) for l in topo["levels"]], "m": args.m,
           "topology": os.path.relpath(args.topology, ROOT)}
    if interior:
        inner = torch.zeros(n, dtype=torch.bool)
        inner[interior] = True
        res["interior_vertices"] = len(interior)
        res["mean_error_interior_pct_bbox"] = 100 * errs[:, inner].mean().item() / bbox
        res["mean_error_surface_pct_bbox"] = 100 * errs[:, ~inner].mean().item() / bbox
    print(json.dumps(res), flush=True)
    os.makedirs(CACHE, exist_ok=True)
    torch.save({"net": net.state_dict(), "residual": args.residual, "center": center.tolist(), "height": height, "result": res,
                "widths": list(widths), "m": args.m, "topology": os.path.abspath(args.topology),
                "test": os.path.abspath(args.test)},
               os.path.join(CACHE, f"{name}.pt"))
    out = os.path.join(ROOT, "docs", "mesh_results.json")
    allr = json.load(open(out)) if os.path.exists(out) else {}
    allr[name] = res
    with open(out, "w") as f:
        json.dump(allr, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
