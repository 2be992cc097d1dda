"""Where things are: the repository root, train/ and its working folders.

Every module takes its paths from here, so they do not depend on which
file of the package asks, or on the directory a command is run from.
"""
import os

#: train/
TRAIN = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
#: the repository root (crate/, models/, docs/, ...)
ROOT = os.path.dirname(TRAIN)
#: train/cache: run outputs and derived data, not committed
CACHE = os.path.join(TRAIN, "cache")
#: train/checkpoints: the portable checkpoints that are committed
CHECKPOINTS = os.path.join(TRAIN, "checkpoints")
#: models/onnx: the bundled models and their manifests
ONNX_DIR = os.path.join(ROOT, "models", "onnx")
