"""Exports the mesh autoencoder (train/deeprep_train/mesh/train.py) to models/onnx/ as two
graphs with the kernels of eq. 2.2 precomputed, as the thesis does at test
time:
  mesh_encoder.onnx   positions [batch, V, 3] (normalized) -> latent [batch, L, C]
  mesh_decoder.onnx   latent [batch, L, C] -> positions [batch, V, 3] (normalized)
Each conv is a gather of the neighbourhood table and a batched MatMul over
vertices; each residual pooling's weighted sum is a MatMul too
(export/fast_pool.py). --form factored (the default) stores A and B and lets the runtime
fold W = A·B once at load (small files); --form matmul / einsum store W
itself (large files) with a MatMul or an Einsum; tests/native/mesh_model.rs
times the forms in tract.

Run: train/.venv/bin/python -m deeprep_train.mesh.export [--name full] [--form matmul]
"""
import argparse
import os

import numpy as np
import onnx
import onnxruntime as ort
import torch
from torch import nn

from deeprep_train.paths import CACHE as CACHE_ROOT  # noqa: E402
from deeprep_train.mesh.model import AvgPool, MeshAE, density, load_topology  # noqa: E402
from deeprep_train.export import fast_pool  # noqa: E402
from deeprep_train.export.util import ONNX_DIR, git_commit, write_json  # noqa: E402

CACHE = os.path.join(CACHE_ROOT, "mesh")


class FrozenConv(nn.Module):
    def __init__(self, conv, form):
        super().__init__()
        self.form = form
        self.register_buffer("idx", conv.t.idx.clone())
        w = conv.kernels().detach()                                  # [N, E, O, I]
        n, e, o, i = w.shape
        self.shape = (n, e, o, i)
        if form == "factored":
            # A (masked) and B as constants; W = sum_k A_k B_k is a constant
            # expression that tract and onnxruntime fold once at load time.
            self.register_buffer("A", (conv.A * conv.t.mask[..., None]).detach().contiguous())
            self.register_buffer("B", conv.B.detach().permute(0, 2, 1).contiguous())   # [M, I, O]
        elif form == "matmul":
            self.register_buffer("w", w.permute(0, 1, 3, 2).reshape(n, e * i, o).contiguous())  # [N, E*I, O]
        else:
            self.register_buffer("w", w.contiguous())
        self.register_buffer("b", conv.b.detach().clone())

    def forward(self, x):                                            # [B, Nin, I]
        g = x[:, self.idx]                                           # [B, N, E, I]
        if self.form == "factored":
            n, e, o, i = self.shape
            w = torch.matmul(self.A.reshape(n * e, -1), self.B.reshape(self.B.shape[0], i * o)).reshape(n, e * i, o)
            b, _, _, _ = g.shape
            g = g.reshape(b, n, e * i).transpose(0, 1)
            return torch.matmul(g, w).transpose(0, 1) + self.b
        if self.form == "matmul":
            b, n, e, i = g.shape
            g = g.reshape(b, n, e * i).transpose(0, 1)               # [N, B, E*I]
            return torch.matmul(g, self.w).transpose(0, 1) + self.b  # [B, N, O]
        return torch.einsum("bnei,neoi->bno", g, self.w) + self.b


class FrozenRes(nn.Module):
    def __init__(self, res):
        super().__init__()
        self.register_buffer("idx", res.t.idx.clone())
        if isinstance(res, AvgPool):
            wts = res.t.mask / res.t.mask.sum(1, keepdim=True)
        else:
            wts = density(res.rho.detach(), res.t.mask)
        self.register_buffer("wts", wts[None, :, :, None].contiguous())
        self.C = None if res.C is None else res.C

    def forward(self, x):
        y = (x[:, self.idx] * self.wts).sum(2)
        return y if self.C is None else self.C(y)


class FrozenBlock(nn.Module):
    def __init__(self, block, form):
        super().__init__()
        self.conv = FrozenConv(block.conv, form)
        self.act = block.act
        self.res = None if block.res is None else FrozenRes(block.res)

    def forward(self, x):
        y = self.conv(x)
        if self.act:
            y = torch.nn.functional.elu(y)
        return y if self.res is None else y + self.res(x)


class Encoder(nn.Module):
    def __init__(self, net, form):
        super().__init__()
        self.blocks = nn.ModuleList(FrozenBlock(b, form) for b in net.enc)

    def forward(self, x):
        for b in self.blocks:
            x = b(x)
        return x


class Decoder(nn.Module):
    def __init__(self, net, form):
        super().__init__()
        self.blocks = nn.ModuleList(FrozenBlock(b, form) for b in net.dec)
        self.out = net.out

    def forward(self, z):
        for b in self.blocks:
            z = b(z)
        return self.out(z)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--name", default="full")
    ap.add_argument("--form", default="factored", choices=["factored", "matmul", "einsum"])
    ap.add_argument("--suffix", default="", help="appended to the file names (for the op-form comparison)")
    ap.add_argument("--out", default=ONNX_DIR, help="directory of the exported files (default models/onnx: the bundled "
                                                    "robot model, its fixtures and per-graph manifests)")
    ap.add_argument("--topology", default=None, help="topology file (default: the one the run recorded, else the robot's)")
    ap.add_argument("--test", default=None, help="test pose prefix for the parity inputs (default: the run's)")
    ap.add_argument("--training-data", default=None, help="the manifest's training_data sentence (default: the robot's)")
    args = ap.parse_args()
    ck = torch.load(os.path.join(CACHE, f"{args.name}.pt"), weights_only=False)
    # a run of mesh/train.py --topology/--test records its files; the robot's otherwise
    topo = load_topology(args.topology or ck.get("topology", os.path.join(CACHE, "topology.json")))
    test_prefix = args.test or ck.get("test", os.path.join(CACHE, "test"))
    bundled = os.path.abspath(args.out) == os.path.abspath(ONNX_DIR)
    os.makedirs(args.out, exist_ok=True)
    net = MeshAE(topo, widths=ck.get("widths", (3, 16, 32, 64, 16)), m=ck.get("m"),
                 residual=None if ck["residual"] == "none" else ck["residual"])
    net.load_state_dict(ck["net"])
    net.eval()
    enc, dec = Encoder(net, args.form).eval(), Decoder(net, args.form).eval()
    test = np.fromfile(test_prefix + ".f32", dtype="<f4").reshape(-1, len(topo["rest"]), 3)[:2]
    x = torch.tensor((test - np.array(ck["center"], dtype=np.float32)) / ck["height"])
    with torch.no_grad():
        z, y = enc(x), dec(enc(x))
        ref = net(x)
    print("frozen vs training graph:", float((y - ref).abs().max()))
    out = {}
    for name, mod, inp, iname, oname in [("mesh_encoder", enc, x, "positions", "latent"), ("mesh_decoder", dec, z, "latent", "positions")]:
        path = os.path.join(args.out, f"{name}{args.suffix}.onnx")
        torch.onnx.export(mod, (inp,), path, dynamo=False, opset_version=17, input_names=[iname], output_names=[oname],
                          dynamic_axes={iname: {0: "batch"}, oname: {0: "batch"}})
        graph = onnx.load(path)
        fast_pool.rewrite(graph)  # the pooling sums in the form tract runs fastest (issue 23)
        onnx.save(graph, path)
        sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
        o = sess.run(None, {iname: inp.numpy()})[0]
        with torch.no_grad():
            parity = float(np.abs(o - mod(inp).numpy()).max())
        print(name, args.form, "parity torch vs onnxruntime", parity)
        out[name] = parity
        if not args.suffix and bundled:
            write_json(os.path.join(ONNX_DIR, "fixtures", f"{name}.json"), {
                "model": f"{name}.onnx", "input_name": iname, "input_shape": list(inp.shape),
                "input": [float(v) for v in inp.numpy().ravel()],
                "output_shape": list(o.shape), "output_onnxruntime": [float(v) for v in o.ravel()],
                "onnxruntime_version": ort.__version__,
            })
    if not args.suffix:
        res = ck["result"]
        manifest = {
            "name": "mesh_autoencoder",
            "graphs": {"encoder": "mesh_encoder.onnx", "decoder": "mesh_decoder.onnx"},
            "inputs": {"encoder": ["batch", len(topo["rest"]), 3], "decoder": ["batch"] + res["latent"]},
            "normalization": {"center": ck["center"], "height": ck["height"],
                              "meaning": "network positions = (welded vertex positions - center) / height"},
            "op_form": args.form,
            "pooling_form": "MatMul of the pooling weights and the gathered neighbourhood (export/fast_pool.py)",
            "latent_seeds": topo["seeds"],
            "levels": [len(topo["rest"])] + [len(l["selected"]) for l in topo["levels"]],
            "training": res,
            "parity_torch_vs_onnxruntime": out,
            "training_data": args.training_data or "RobotExpressive.glb (CC0) posed by `deeprep mesh poses`: 12 clips + 3,000 random poses (seed 1) for training; clips Wave and Punch and 300 random poses (seed 2) held out",
            "topology": "deeprep mesh topology (welded, components joined, s = 2, r = 2)",
            "training_code_commit": git_commit(),
            "exporter": {"torch": torch.__version__, "dynamo": False, "opset": 17},
        }
        write_json(os.path.join(args.out, "mesh_autoencoder.manifest.json"), manifest)
        # per-graph manifests for the generic parity test
        for g in ("mesh_encoder", "mesh_decoder") if bundled else ():
            io = {"mesh_encoder": ([{"name": "positions", "shape": manifest["inputs"]["encoder"]}], [{"name": "latent", "shape": manifest["inputs"]["decoder"]}]),
                  "mesh_decoder": ([{"name": "latent", "shape": manifest["inputs"]["decoder"]}], [{"name": "positions", "shape": manifest["inputs"]["encoder"]}])}[g]
            write_json(os.path.join(ONNX_DIR, f"{g}.manifest.json"), {"name": g, "see": "mesh_autoencoder.manifest.json", "inputs": io[0], "outputs": io[1],
                                                                     **{k: manifest[k] for k in ("normalization", "training", "training_data", "training_code_commit")}})
    return args.out


if __name__ == "__main__":
    out = main()
    # the shipped files keep their weights as float16 (issue 21)
    from deeprep_train.export.half_weights import convert
    for name in ("mesh_encoder", "mesh_decoder"):
        convert(name, out)
