"""onnxruntime timings for the mesh autoencoder graphs, to set beside
`cargo bench --bench mesh` (tract). One thread, batch 1; JSON on stdout.
Run: .venv/bin/python -m deeprep_train.mesh.bench_ort [DIR_WITH_FORMS]"""
import argparse
import glob
import json
import os
import time

import numpy as np
import onnxruntime as ort

from deeprep_train.paths import ROOT  # noqa: E402


def main():
    man = json.load(open(os.path.join(ROOT, "models", "onnx", "mesh_autoencoder.manifest.json")))
    files = [os.path.join(ROOT, "models", "onnx", f) for f in ("mesh_encoder.onnx", "mesh_decoder.onnx")]
    ap = argparse.ArgumentParser(description="onnxruntime timings of the mesh autoencoder graphs (JSON on stdout).")
    ap.add_argument("forms", nargs="?", help="a folder with mesh_*_<form>.onnx to time as well")
    forms = ap.parse_args().forms
    if forms:
        files += sorted(glob.glob(os.path.join(forms, "mesh_*_*.onnx")))
    rows = []
    for f in files:
        so = ort.SessionOptions()
        so.intra_op_num_threads = 1
        so.inter_op_num_threads = 1
        t0 = time.perf_counter()
        s = ort.InferenceSession(f, so, providers=["CPUExecutionProvider"])
        inp = s.get_inputs()[0]
        shape = [1, man["levels"][0], 3] if "encoder" in os.path.basename(f) else [1] + man["inputs"]["decoder"][1:]
        x = (np.arange(np.prod(shape)) % 97 / 97.0 - 0.5).astype(np.float32).reshape(shape)
        s.run(None, {inp.name: x})
        load = (time.perf_counter() - t0) * 1e3
        t1 = time.perf_counter()
        for _ in range(20):
            s.run(None, {inp.name: x})
        rows.append({"file": os.path.basename(f), "bytes": os.path.getsize(f), "load_and_first_run_ms": load,
                     "run_ms": (time.perf_counter() - t1) * 1e3 / 20})
    print(json.dumps({"onnxruntime_mesh_autoencoder": rows, "threads": 1, "onnxruntime": ort.__version__}, indent=1))


if __name__ == "__main__":
    main()
