# Issue 23 experiment (session 27, not part of the package): single-operator
# ONNX models with the bundled residual network's matrix shapes (width 112,
# kernel 3, 1,024 columns: its blocks at 2,048 frames), as plain convolutions
# and as plain matrix products, for docs/experiments/bench_gemm_forms.mjs.
# Writes train/cache/gemm/*.onnx (ignored).  Usage:
#   train/.venv/bin/python docs/experiments/gemm_forms.py
import os
import numpy as np
import onnx
from onnx import helper as h, TensorProto as T, numpy_helper as nh

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "train", "cache", "gemm")
os.makedirs(OUT, exist_ok=True)
rng = np.random.default_rng(0)


def save(name, nodes, inputs, inits, out_shape):
    g = h.make_graph(nodes, name, inputs, [h.make_tensor_value_info('y', T.FLOAT, out_shape)], inits)
    m = h.make_model(g, opset_imports=[h.make_opsetid('', 17)])
    m.ir_version = 8
    onnx.checker.check_model(m)
    onnx.save(m, os.path.join(OUT, f'{name}.onnx'))


N = 1024
W3 = nh.from_array((rng.standard_normal((112, 112, 3)) * 0.05).astype(np.float32), 'w')
B = nh.from_array(np.zeros(112, np.float32), 'b')
for d in (1, 8, 64):
    save(f'conv3_d{d}', [h.make_node('Conv', ['x', 'w', 'b'], ['y'], dilations=[d], pads=[d, d], kernel_shape=[3])],
         [h.make_tensor_value_info('x', T.FLOAT, [1, 112, N])], [W3, B], [1, 112, N])
W1 = nh.from_array((rng.standard_normal((112, 336, 1)) * 0.05).astype(np.float32), 'w')
save('conv1_k336', [h.make_node('Conv', ['x', 'w', 'b'], ['y'], kernel_shape=[1])],
     [h.make_tensor_value_info('x', T.FLOAT, [1, 336, N])], [W1, B], [1, 112, N])
WM = nh.from_array((rng.standard_normal((336, 112)) * 0.05).astype(np.float32), 'w')
save('matmul_x_w', [h.make_node('MatMul', ['x', 'w'], ['y'])],
     [h.make_tensor_value_info('x', T.FLOAT, [N, 336])], [WM], [N, 112])
WT = nh.from_array((rng.standard_normal((112, 336)) * 0.05).astype(np.float32), 'w')
save('matmul_w_x', [h.make_node('MatMul', ['w', 'x'], ['y'])],
     [h.make_tensor_value_info('x', T.FLOAT, [336, N])], [WT], [112, N])
print('ok')
