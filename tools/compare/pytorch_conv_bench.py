#!/usr/bin/env python3
"""Times PyTorch (cuDNN) float32 convolutions on the shapes of `smokesvd bench conv`, for the comparison
in docs/benchmarks.md. Needs PyTorch with a CUDA device; TF32 is off so that both sides compute in
float32. Prints one line per pass: name, shape, median microseconds, GFLOP/s (same FLOP count as
smokesvd: 2 * N * Cout * Cin * k^d * outputs).

    python3 tools/compare/pytorch_conv_bench.py [--runs 50]
"""
import argparse

import torch
import torch.nn.functional as F

SHAPES = [  # name, shape label, x, w, stride, padding, transposed
    ("conv2d", "3x3 64->64 @ 64x64", (1, 64, 64, 64), (64, 64, 3, 3), 1, 1, False),
    ("conv2d-s2", "3x3 64->128 s2 @ 64x64", (1, 64, 64, 64), (128, 64, 3, 3), 2, 1, False),
    ("conv3d", "3x3x3 16->16 @ 64^3", (1, 16, 64, 64, 64), (16, 16, 3, 3, 3), 1, 1, False),
    ("conv3d", "3x3x3 32->32 @ 32^3", (1, 32, 32, 32, 32), (32, 32, 3, 3, 3), 1, 1, False),
    ("conv-transpose2d", "2x2 s2 64->32 @ 32x32", (1, 64, 32, 32), (64, 32, 2, 2), 2, 0, True),
    ("conv-transpose3d", "2x2x2 s2 32->16 @ 16^3", (1, 32, 16, 16, 16), (32, 16, 2, 2, 2), 2, 0, True),
]


def median_us(fn, runs):
    for _ in range(5):
        fn()
    torch.cuda.synchronize()
    times = []
    for _ in range(runs):
        start, stop = torch.cuda.Event(enable_timing=True), torch.cuda.Event(enable_timing=True)
        start.record()
        fn()
        stop.record()
        torch.cuda.synchronize()
        times.append(start.elapsed_time(stop) * 1000.0)
    times.sort()
    return times[len(times) // 2]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=50)
    args = parser.parse_args()
    torch.backends.cudnn.allow_tf32 = False
    torch.backends.cuda.matmul.allow_tf32 = False
    torch.backends.cudnn.benchmark = True
    device = torch.device("cuda")
    print(f"device: {torch.cuda.get_device_name(0)} (PyTorch {torch.__version__}, cuDNN {torch.backends.cudnn.version()})")
    for name, label, xs, ws, stride, padding, transposed in SHAPES:
        x = torch.randn(xs, device=device, requires_grad=True)
        w = torch.randn(ws, device=device, requires_grad=True)
        dims = len(xs) - 2
        conv = (F.conv_transpose2d if dims == 2 else F.conv_transpose3d) if transposed else (F.conv2d if dims == 2 else F.conv3d)
        y = conv(x, w, stride=stride, padding=padding)
        gy = torch.randn_like(y)
        # Every tap of every output (transposed: of every input), as smokesvd counts.
        flops = 2.0 * (x.numel() if transposed else y.numel()) * (w.numel() // w.shape[0])
        passes = {
            "forward": lambda: conv(x, w, stride=stride, padding=padding),
            "backward-input": lambda: torch.autograd.grad(y, x, gy, retain_graph=True),
            "backward-weight": lambda: torch.autograd.grad(y, w, gy, retain_graph=True),
        }
        for pass_name, fn in passes.items():
            us = median_us(fn, args.runs)
            print(f"{name + '/' + pass_name:<36} {label:<28} {us:10.1f} us {flops / us / 1e3:10.1f} GFLOP/s")


if __name__ == "__main__":
    main()
