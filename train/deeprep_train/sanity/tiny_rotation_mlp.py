"""Trains and exports the tiny network that proves the ONNX path (issue 2).

The network is the sanity-test autoencoder of thesis Sec. 4.4.1 at small
width: a rotation matrix (9 numbers) -> MLP -> 6D representation -> f_GS
(Gram-Schmidt + cross product, inside the graph) -> rotation matrix (9).

Writes:
  models/onnx/rot6d_autoencoder.onnx            (legacy exporter, opset 17, dynamic batch)
  models/onnx/rot6d_autoencoder.manifest.json   (inputs, outputs, training, accuracy)
  models/onnx/fixtures/rot6d_autoencoder.json   (fixed inputs + onnxruntime outputs)

Run:  train/.venv/bin/python -m deeprep_train.sanity.tiny_rotation_mlp [--steps 4000]
"""
import argparse
import math
import os
import time

import numpy as np
import torch
import torch.nn as nn

from deeprep_train.rotation import geodesic, random_so3, sixd_to_matrix  # noqa: E402
from deeprep_train.export.util import ONNX_DIR, git_commit, write_json  # noqa: E402


class RotAutoencoder(nn.Module):
    def __init__(self, hidden: int = 64):
        super().__init__()
        self.enc = nn.Sequential(
            nn.Linear(9, hidden), nn.LeakyReLU(0.2),
            nn.Linear(hidden, hidden), nn.LeakyReLU(0.2),
            nn.Linear(hidden, hidden), nn.LeakyReLU(0.2),
            nn.Linear(hidden, 6),
        )

    def forward(self, m_flat: torch.Tensor) -> torch.Tensor:
        r = self.enc(m_flat)
        return sixd_to_matrix(r).reshape(-1, 9)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=4000)
    ap.add_argument("--batch", type=int, default=256)
    ap.add_argument("--threads", type=int, default=1)
    args = ap.parse_args()
    torch.set_num_threads(args.threads)
    torch.manual_seed(0)
    g = torch.Generator().manual_seed(0)
    net = RotAutoencoder()
    opt = torch.optim.Adam(net.parameters(), lr=1e-3)
    sched = torch.optim.lr_scheduler.CosineAnnealingLR(opt, args.steps)
    t0 = time.time()
    for step in range(args.steps):
        m = random_so3(args.batch, g).float().reshape(-1, 9)
        loss = ((net(m) - m) ** 2).sum(-1).mean()
        opt.zero_grad()
        loss.backward()
        opt.step()
        sched.step()
        if step % 500 == 0 or step == args.steps - 1:
            print(f"step {step} loss {loss.item():.6f}", flush=True)
    train_s = time.time() - t0
    net.eval()

    # Held-out accuracy: geodesic error on 10^5 uniform rotations.
    with torch.no_grad():
        test = random_so3(100_000, torch.Generator().manual_seed(123)).float()
        out = net(test.reshape(-1, 9)).reshape(-1, 3, 3)
        err = torch.rad2deg(geodesic(out.double(), test.double())).numpy()
    acc = {"test_rotations": 100_000, "mean_deg": float(err.mean()), "max_deg": float(err.max()),
           "std_deg": float(err.std()), "p99_deg": float(np.percentile(err, 99))}
    print("geodesic error (deg):", acc)

    os.makedirs(os.path.join(ONNX_DIR, "fixtures"), exist_ok=True)
    path = os.path.join(ONNX_DIR, "rot6d_autoencoder.onnx")
    example = random_so3(4, torch.Generator().manual_seed(1)).float().reshape(-1, 9)
    torch.onnx.export(net, (example,), path, dynamo=False, opset_version=17,
                      input_names=["matrix_in"], output_names=["matrix_out"],
                      dynamic_axes={"matrix_in": {0: "batch"}, "matrix_out": {0: "batch"}})

    import onnxruntime as ort
    fixed = random_so3(64, torch.Generator().manual_seed(7)).float().reshape(-1, 9)
    sess = ort.InferenceSession(path, providers=["CPUExecutionProvider"])
    ort_out = sess.run(None, {"matrix_in": fixed.numpy()})[0]
    with torch.no_grad():
        torch_out = net(fixed).numpy()
    parity = float(np.abs(ort_out - torch_out).max())
    print(f"parity torch vs onnxruntime: max abs diff {parity:.3g}")
    assert parity < 1e-5, parity

    write_json(os.path.join(ONNX_DIR, "fixtures", "rot6d_autoencoder.json"), {
        "model": "rot6d_autoencoder.onnx",
        "input_name": "matrix_in",
        "input_shape": list(fixed.shape),
        "input": [float(x) for x in fixed.numpy().ravel()],
        "output_shape": list(ort_out.shape),
        "output_onnxruntime": [float(x) for x in ort_out.ravel()],
        "onnxruntime_version": ort.__version__,
    })
    write_json(os.path.join(ONNX_DIR, "rot6d_autoencoder.manifest.json"), {
        "name": "rot6d_autoencoder",
        "description": "Sanity-test autoencoder (thesis Sec. 4.4.1) at small width: matrix -> MLP -> 6D -> f_GS -> matrix.",
        "inputs": [{"name": "matrix_in", "shape": ["batch", 9], "dtype": "float32", "meaning": "row-major rotation matrices"}],
        "outputs": [{"name": "matrix_out", "shape": ["batch", 9], "dtype": "float32", "meaning": "row-major rotation matrices (orthonormal by construction)"}],
        "normalization": None,
        "training": {"data": "rotations sampled uniformly on SO(3) (random normalized quaternions)",
                     "steps": args.steps, "batch": args.batch, "optimizer": "Adam lr 1e-3, cosine decay",
                     "loss": "L2 between matrices", "seconds": round(train_s, 1), "threads": args.threads},
        "accuracy": acc,
        "parity_torch_vs_onnxruntime": parity,
        "exporter": {"torch": torch.__version__, "dynamo": False, "opset": 17},
        "training_code_commit": git_commit(),
    })
    print("wrote", path)


if __name__ == "__main__":
    main()
    # the shipped files keep their weights as float16 (issue 21)
    from deeprep_train.export.half_weights import convert
    for name in ("rot6d_autoencoder",):
        convert(name)
