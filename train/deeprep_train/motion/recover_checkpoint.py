"""Rebuilds PyTorch checkpoints of the bundled in-betweening networks from
models/onnx/tween_{generator,path}.onnx, so that training can continue on a
machine that never held train/cache (checkpoints are not committed).

The legacy exporter keeps parameter names for most initializers; PReLU
slopes and Linear weights get anonymous names, which are mapped back
through their nodes' scope names. Each rebuilt network is checked against
its parity fixture (models/onnx/fixtures/) and the script fails if it is
off by more than 1e-4.

Writes OUT (--out, default train/cache/tween)/gen.pt (generator only: a
--resume of it trains a fresh discriminator first, see --d-warmup) and
path.pt.

  train/.venv/bin/python -m deeprep_train.motion.recover_checkpoint
  train/.venv/bin/python -m deeprep_train.motion.train --resume train/cache/tween/gen.pt --path-ckpt train/cache/tween/path.pt ...
"""
import argparse
import json
import os
import sys

import numpy as np
import onnx
import torch

from deeprep_train.rcfk import RCFK  # noqa: E402
from deeprep_train.motion.nets import Generator, PathPredictor  # noqa: E402
from deeprep_train.export.fast_prelu import slopes  # noqa: E402
from deeprep_train.export.util import ONNX_DIR, initializer_arrays  # noqa: E402
from deeprep_train.motion.train import OUT, Data  # noqa: E402

from deeprep_train.paths import CACHE  # noqa: E402


def scope_path(node_name):
    """'/enc.1/act/PRelu' -> 'enc.1.act'; '/dna/mlp/mlp.0/MatMul' -> 'dna.mlp.0'."""
    segs = []
    for part in node_name.strip("/").split("/")[:-1]:
        if segs and "." in part and part.rsplit(".", 1)[0] == segs[-1]:
            segs[-1] = part
        else:
            segs.append(part)
    return ".".join(segs)


def load_onnx_weights(model, m, path):
    """Copies the initializers of the ONNX model m (read from path) into model."""
    init = {k: torch.from_numpy(v.copy()) for k, v in initializer_arrays(m).items()}
    sd = model.state_dict()
    got = {k: init[k] for k in sd if k in init}
    for n in m.graph.node:
        if n.op_type in ("PRelu", "MatMul") and len(n.input) > 1 and n.input[1].startswith("onnx::") \
                and n.input[1] in init:
            t = init[n.input[1]]
            got[scope_path(n.name) + ".weight"] = t.T if n.op_type == "MatMul" else t
    # PReLUs as export/fast_prelu.py writes them, named after the PRelu node
    # each replaced ("/enc.1/act/PRelu")
    for name, a in slopes(m).items():
        got[scope_path(name) + ".weight"] = torch.from_numpy(a.copy())
    missing = [k for k in sd if k not in got]
    if missing:
        sys.exit(f"{path}: no initializer for {missing}")
    model.load_state_dict({k: got[k].reshape(sd[k].shape) for k in sd})
    model.eval()


def check(model, fixture_name):
    fx = json.load(open(os.path.join(ONNX_DIR, "fixtures", f"{fixture_name}.json")))
    ins = [torch.tensor(v["data"], dtype=torch.float32).reshape(v["shape"]) for v in fx["inputs"].values()]
    with torch.no_grad():
        out = model(*ins).numpy().ravel()
    err = float(np.abs(out - np.array(fx["output_onnxruntime"])).max())
    if err > 1e-4:
        sys.exit(f"{fixture_name}: rebuilt network is off its fixture by {err:.3g}")
    return err


def main(argv=None):
    ap = argparse.ArgumentParser(description="Rebuilds train/cache/tween checkpoints from the bundled ONNX files.")
    ap.add_argument("--out", default=OUT, help="where gen.pt and path.pt go (default train/cache/tween)")
    out = ap.parse_args(argv).out
    data = Data(os.path.join(CACHE, "motion60.npz"), "train")
    P = 3 * len(data.joints)
    fk = RCFK(data.joints, data.parents, data.offsets, data.channel_joints)
    gman = json.load(open(os.path.join(ONNX_DIR, "tween_generator.manifest.json")))
    pman = json.load(open(os.path.join(ONNX_DIR, "tween_path.manifest.json")))
    gpath, ppath = (os.path.join(ONNX_DIR, f"tween_{x}.onnx") for x in ("generator", "path"))
    gm = onnx.load(gpath)
    skips = len({k.split(".")[1] for k in initializer_arrays(gm) if k.startswith("skip.")})
    gen = Generator(P, fk.output_dim, skips=skips)
    load_onnx_weights(gen, gm, gpath)
    eg = check(gen, "tween_generator")
    path_config = pman["training"].get("config", {})  # written by motion/export.py since session 13
    path = PathPredictor(P, **path_config)
    load_onnx_weights(path, onnx.load(ppath), ppath)
    ep = check(path, "tween_path")
    os.makedirs(out, exist_ok=True)
    steps = gman["training"]["steps"]
    args = {"skips": skips, "gate_tau": None, "base": gman.get("base", "linear"), "recovered_from": "onnx"}
    torch.save({"G": gen.state_dict(), "steps": steps, "args": args, "weights": gman["training"]["loss_weights"]},
               os.path.join(out, "gen.pt"))
    torch.save({"model": path.state_dict(), "steps": pman["training"]["steps"],
                "table_5_2_val": pman["training"].get("table_5_2_validation"), "config": path_config},
               os.path.join(out, "path.pt"))
    print(f"{out}: gen.pt ({steps} steps, skips {skips}, base {args['base']}, fixture error {eg:.2g}), "
          f"path.pt (fixture error {ep:.2g})")


if __name__ == "__main__":
    main()
