"""Helpers shared by the export scripts: git commit, manifest writing, fixtures."""
import json
import subprocess

from deeprep_train.paths import ONNX_DIR, ROOT  # noqa: F401  (ONNX_DIR: re-exported for the exporters)


def git_commit() -> str:
    try:
        out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=True)
        dirty = subprocess.run(["git", "status", "--porcelain", "train"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
        return out.stdout.strip() + ("+dirty" if dirty else "")
    except Exception:
        return "unknown"


def write_json(path: str, obj) -> None:
    with open(path, "w") as f:
        json.dump(obj, f, indent=1)
        f.write("\n")


HALF_SUFFIX = "::float16"


def initializer_arrays(model):
    """Name -> float32 numpy array of every initializer of an ONNX model,
    with weights stored as float16 behind a Cast (export/half_weights.py) under the
    name the graph reads them by, widened back to float32."""
    import numpy as np
    from onnx import numpy_helper
    arrays = {i.name: numpy_helper.to_array(i) for i in model.graph.initializer}
    for n in model.graph.node:
        if n.op_type == "Cast" and len(n.input) == 1 and n.input[0] in arrays \
                and arrays[n.input[0]].dtype == np.float16:
            arrays[n.output[0]] = arrays.pop(n.input[0]).astype(np.float32)
    return arrays


def rewrite_cli(rewrite, what, form):
    """The command line of a graph rewrite: ONNX files in, each rewritten in
    place by `rewrite_files` (`what`: the places' name, `form`: what they
    become, for --help)."""
    import argparse
    ap = argparse.ArgumentParser(description=f"Rewrite {what} as {form}, in place; a parity fixture beside the file "
                                             "(fixtures/<name>.json) gets the rewritten file's onnxruntime output.")
    ap.add_argument("models", nargs="+", help="ONNX files to rewrite")
    rewrite_files(ap.parse_args().models, rewrite, what)


def rewrite_files(paths, rewrite, what):
    """Applies a graph rewrite (`rewrite(model)` -> how many places) to ONNX
    files in place; a parity fixture beside a file (fixtures/<name>.json)
    gets the rewritten file's onnxruntime output, and the line printed says
    how far that output moved."""
    import os

    import numpy as np
    import onnx
    from deeprep_train.export.half_weights import run
    for path in paths:
        fpath = os.path.join(os.path.dirname(path), "fixtures", os.path.basename(path)[:-len(".onnx")] + ".json")
        fixture = json.load(open(fpath)) if os.path.exists(fpath) else None
        ref = run(path, fixture) if fixture else None
        m = onnx.load(path)
        n = rewrite(m)
        onnx.save(m, path)
        moved = ""
        if fixture:
            out = run(path, fixture)
            moved = f", fixture output moved {float(np.abs(out - ref).max()):.2e}"
            fixture["output_onnxruntime"] = [float(x) for x in out.ravel()]
            write_json(fpath, fixture)
        print(f"{path}: {n} {what} rewritten{moved}")
