"""Exports HairNet to models/onnx/ in the two graphs the Rust side needs:
  hair_features.onnx   image [1, 3, 256, 256] -> strand features [1, C, 32, 32]
  hair_strands.onnx    strand features [1, C, H, W] -> positions [1, 300, H, W], curvatures [1, 100, H, W]
The strand heads are 1x1 convolutions, so Rust can feed any number K of
strand features it has upsampled itself as [1, C, K, 1].
Run after hair/train.py:  train/.venv/bin/python -m deeprep_train.hair.export [--name full]
"""
import argparse
import json
import os

import numpy as np
import onnxruntime as ort
import torch
from torch import nn

from deeprep_train.hair.model import CURV_MAX, CURV_SCALE, GRID, POINTS, POS_SCALE, HairNet  # noqa: E402
from deeprep_train.export.util import ONNX_DIR, git_commit, write_json  # noqa: E402
from deeprep_train.hair.train import CACHE, Data  # noqa: E402


class Heads(nn.Module):
    def __init__(self, heads):
        super().__init__()
        self.heads = heads

    def forward(self, feat):
        return self.heads(feat)


def fixture(name, path, feeds, torch_out):
    sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
    outs = sess.run(None, feeds)
    parity = max(float(np.abs(o - t).max()) for o, t in zip(outs, torch_out))
    (iname, x), = feeds.items()
    write_json(os.path.join(ONNX_DIR, "fixtures", f"{name}.json"), {
        "model": f"{name}.onnx", "input_name": iname, "input_shape": list(x.shape),
        "input": [round(float(v), 6) for v in x.ravel()],
        "output_shape": list(outs[0].shape), "output_onnxruntime": [float(v) for v in outs[0].ravel()],
        "onnxruntime_version": ort.__version__,
    })
    return parity


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--name", default="full")
    args = ap.parse_args()
    ck = torch.load(os.path.join(CACHE, f"{args.name}.pt"), weights_only=False)
    net = HairNet(ck["div"])
    net.load_state_dict(ck["net"])
    net.eval()
    data = Data(os.path.join(CACHE, "data"))
    r = data.renders["test"][0]
    img = torch.from_numpy(data.images[r:r + 1].astype(np.float32) / 255.0)
    c = net.body.c_feat
    with torch.no_grad():
        feat = net.body(img)
        # a few features at upsampled scalp points, as Rust feeds them: [1, C, K, 1]
        k_feat = feat.reshape(1, c, GRID * GRID)[:, :, :37].reshape(1, c, 37, 1).contiguous()
        pos, curv = net.heads(k_feat)
    fpath = os.path.join(ONNX_DIR, "hair_features.onnx")
    torch.onnx.export(net.body, (img,), fpath, dynamo=False, opset_version=17, input_names=["image"], output_names=["features"])
    spath = os.path.join(ONNX_DIR, "hair_strands.onnx")
    torch.onnx.export(Heads(net.heads), (k_feat,), spath, dynamo=False, opset_version=17, input_names=["features"],
                      output_names=["positions", "curvatures"],
                      dynamic_axes={"features": {2: "h", 3: "w"}, "positions": {2: "h", 3: "w"}, "curvatures": {2: "h", 3: "w"}})
    parity = {
        "hair_features": fixture("hair_features", fpath, {"image": img.numpy()}, [feat.numpy()]),
        "hair_strands": fixture("hair_strands", spath, {"features": k_feat.numpy()}, [pos.numpy(), curv.numpy()]),
    }
    print("parity torch vs onnxruntime", parity)
    res = ck["result"]
    common = {
        "network": "HairNet (thesis Table B.1) with channel widths / %d" % ck["div"],
        "image": "[1, 3, 256, 256]: channels 0-1 (cos 2θ + 1)/2 and (sin 2θ + 1)/2 of the undirected 2-D orientation on hair pixels, "
                 "0 elsewhere; channel 2 segmentation (hair 1, body 0.5, background 0); as deeprep::hair::render writes it",
        "decoding": {"points": POINTS, "grid": GRID, "feature_channels": c,
                     "positions": "output[0, 3j + a, i] * pos_scale = metres, root-relative, point j, axis a, strand i",
                     "curvatures": "output[0, j, i] * curv_scale = 1/m", "pos_scale": POS_SCALE, "curv_scale": CURV_SCALE,
                     "curv_target_clip": CURV_MAX},
        "scalp": "deeprep::hair::Scalp::default(): 32 x 32 grid centres, strand i = row * 32 + column",
        "roots": data.meta["roots"],
        "body": data.meta["body"],
        "training": res,
        "parity_torch_vs_onnxruntime": parity,
        "training_data": "procedural hair (deeprep hair dataset --base 20 --blends 1 --views 4, seed 1): "
                         f"{data.meta['hairs']} hairs in 18 length x curl classes, {data.meta['renders']} renders; "
                         f"splits by base style {json.dumps(data.meta['split_counts'])}; NOT USC-HairSalon",
        "training_code_commit": git_commit(),
        "exporter": {"torch": torch.__version__, "dynamo": False, "opset": 17},
    }
    write_json(os.path.join(ONNX_DIR, "hair_features.manifest.json"), {
        "name": "hair_features", "inputs": [{"name": "image", "shape": [1, 3, 256, 256]}],
        "outputs": [{"name": "features", "shape": [1, c, GRID, GRID]}], **common})
    write_json(os.path.join(ONNX_DIR, "hair_strands.manifest.json"), {
        "name": "hair_strands", "inputs": [{"name": "features", "shape": [1, c, "h", "w"]}],
        "outputs": [{"name": "positions", "shape": [1, 3 * POINTS, "h", "w"]}, {"name": "curvatures", "shape": [1, POINTS, "h", "w"]}],
        **common})
    print("wrote", fpath, spath)


if __name__ == "__main__":
    main()
    # the shipped files keep their weights as float16 (issue 21)
    from deeprep_train.export.half_weights import convert
    for name in ("hair_features", "hair_strands"):
        convert(name)
