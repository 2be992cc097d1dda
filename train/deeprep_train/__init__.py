"""PyTorch side of deeprep: networks, training and ONNX export."""
