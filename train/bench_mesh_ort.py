"""onnxruntime timings for the mesh autoencoder graphs, to set beside
`cargo bench --bench mesh` (tract). One thread, batch 1; JSON on stdout.
Run: .venv/bin/python train/bench_mesh_ort.py [DIR_WITH_FORMS]"""
import glob
import json
import os
import sys
import time

import numpy as np
import onnxruntime as ort

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
man = json.load(open(os.path.join(ROOT, "models", "onnx", "mesh_autoencoder.manifest.json")))
files = [os.path.join(ROOT, "models", "onnx", f) for f in ("mesh_encoder.onnx", "mesh_decoder.onnx")]
if len(sys.argv) > 1:
    files += sorted(glob.glob(os.path.join(sys.argv[1], "mesh_*_*.onnx")))
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
