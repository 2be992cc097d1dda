"""Parity: every model in models/onnx with a fixture runs in onnxruntime and
reproduces the saved outputs; every model has a manifest with the required
fields and passes the ONNX checker. (tract is compared against the same
fixtures by tests/native and tests/wasm.)"""
import glob
import json
import os

import numpy as np
import onnx
import onnxruntime as ort
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ONNX_DIR = os.path.join(ROOT, "models", "onnx")
FIXTURES = sorted(glob.glob(os.path.join(ONNX_DIR, "fixtures", "*.json")))
MODELS = sorted(glob.glob(os.path.join(ONNX_DIR, "*.onnx")))


def test_there_are_models_and_fixtures():
    assert MODELS, "no models in models/onnx"
    assert FIXTURES, "no fixtures in models/onnx/fixtures"


@pytest.mark.parametrize("path", MODELS, ids=os.path.basename)
def test_model_is_valid_and_has_a_manifest(path):
    onnx.checker.check_model(onnx.load(path))
    manifest = path[: -len(".onnx")] + ".manifest.json"
    assert os.path.exists(manifest), f"missing {manifest}"
    m = json.load(open(manifest))
    for key in ("inputs", "outputs", "training", "training_code_commit"):
        assert key in m, f"{manifest} lacks '{key}'"


@pytest.mark.parametrize("path", FIXTURES, ids=os.path.basename)
def test_onnxruntime_reproduces_fixture(path):
    f = json.load(open(path))
    sess = ort.InferenceSession(os.path.join(ONNX_DIR, f["model"]), providers=["CPUExecutionProvider"])
    if "inputs" in f:
        feeds = {k: np.asarray(v["data"], dtype=np.float32).reshape(v["shape"]) for k, v in f["inputs"].items()}
    else:
        feeds = {f["input_name"]: np.asarray(f["input"], dtype=np.float32).reshape(f["input_shape"])}
    y = sess.run(None, feeds)[0]
    expected = np.asarray(f["output_onnxruntime"], dtype=np.float32).reshape(f["output_shape"])
    assert y.shape == expected.shape
    diff = float(np.abs(y - expected).max())
    assert diff <= 1e-6, f"onnxruntime {ort.__version__} vs fixture ({f['onnxruntime_version']}): {diff}"
