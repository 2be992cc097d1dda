"""ONNX export helpers shared by every system: manifests, PReLU rewrite,
float16 weight storage."""
