#!/usr/bin/env python3
"""PyTorch twins of smokesvd's networks (docs/models.md), to move models between smokesvd and PyTorch.

Stand-alone: needs only PyTorch and NumPy (Debian: python3-torch python3-numpy); weights are read and
written with the small .safetensors reader/writer below, so the safetensors package is not needed.

Usage as a module (from tools/compare/, or with that folder on sys.path):

    import torch, smokesvd_models as sm
    model = sm.load_model("run/grho-fine")          # a folder with config.json and model.safetensors
    density = model(lifted, presence)                # UNet3+: x [N, C, (D,) H, W] (+ presence [N, slots])
    y, heads = model(lifted, presence, deep_supervision=True)
    out = svdiff(x, t)                               # DDPM UNet: x [N, C, H, W], t [N] diffusion steps -> eps or v
    model = sm.build_model(json.load(open("config.json")))   # a whole config or its "model" section
    sm.save_weights(model, "model.safetensors")      # state_dict back to smokesvd (F32, same names)

The networks as the pipeline feeds them (inputs in the networks' units, docs/models.md) are the
functions density_generator, velocity_generator, refine and predict_side_view; side_view_estimates turns a
side-view model's output (the noise eps, or v: the config's options.prediction) into the noise and clean image.

Usage from the command line (arrays in .npz files; outputs float32):

    python3 smokesvd_models.py MODEL_DIR --inputs in.npz --out out.npz [--deep-supervision] [--dtype float64]
                               [--save-weights resaved.safetensors]

in.npz may hold the architecture's input, the network's inputs, or both; out.npz gets the outputs of each:
    architecture: x, plus presence [N, slots] (G_rho) or t [N] (SvDiff) -> y, and with --deep-supervision
                  supervision_1 .. supervision_{L-1} (UNet3+)
    network, by the config's "network":
        grho-coarse, grho-fine: lifted [16, D, H, W], presence [16]  -> density [D, H, W]
        gu:                      current, next [D, H, W]              -> velocity [3, D, H, W]
        nvref:                   render, minus, plus, previous, before_previous [N, 1, h, w]
                                                                      -> refined, residual [N, 1, h, w]
        svdiff, svdiff-init:     noisy [N, S, h, w] in [-1, 1], condition [N, C, h, w] in [0, 1], steps [N]
                                 -> prediction (the output: eps or v), eps and clean (x0), each [N, S, h, w]
MODEL_DIR holds config.json and model.safetensors (what `smokesvd train` writes).
"""

import argparse
import json
import math
import os
import struct
import sys
from collections import OrderedDict

import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F

# ---------------------------------------------------------------------------------------------------
# .safetensors: 8-byte little-endian header length N, N bytes of JSON {name: {dtype, shape,
# data_offsets: [begin, end]}, "__metadata__": {str: str}}, then the tensors' little-endian bytes.

_SAFETENSORS_DTYPES = {"F32": np.float32, "F64": np.float64, "F16": np.float16, "I32": np.int32, "I64": np.int64}


def read_safetensors(path):
    """Returns (OrderedDict name -> float32 torch.Tensor, in file order; metadata dict)."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 8:
        raise ValueError(f"{path}: too short for a .safetensors header")
    (header_length,) = struct.unpack("<Q", data[:8])
    if 8 + header_length > len(data):
        raise ValueError(f"{path}: header length {header_length} runs past the end of the file")
    header = json.loads(data[8:8 + header_length].decode("utf-8"))
    metadata = header.pop("__metadata__", {})
    body = memoryview(data)[8 + header_length:]
    tensors = OrderedDict()
    for name, entry in sorted(header.items(), key=lambda item: item[1]["data_offsets"][0]):
        if entry["dtype"] not in _SAFETENSORS_DTYPES:
            raise ValueError(f"{path}: tensor '{name}' has dtype {entry['dtype']}, expected one of "
                             f"{', '.join(_SAFETENSORS_DTYPES)}")
        begin, end = entry["data_offsets"]
        array = np.frombuffer(body[begin:end], dtype=np.dtype(_SAFETENSORS_DTYPES[entry["dtype"]]).newbyteorder("<"))
        if array.size != math.prod(entry["shape"]):
            raise ValueError(f"{path}: tensor '{name}' holds {array.size} values, its shape {entry['shape']} needs "
                             f"{math.prod(entry['shape'])}")
        tensors[name] = torch.from_numpy(array.astype(np.float32).reshape(entry["shape"]))
    return tensors, metadata


def write_safetensors(path, tensors, metadata=None):
    """Writes name -> tensor (any float dtype; stored as F32) in the given order, as smokesvd does."""
    path = os.fspath(path)
    header, chunks, offset = {}, [], 0
    for name, tensor in tensors.items():
        array = np.ascontiguousarray(tensor.detach().cpu().numpy(), dtype="<f4")
        header[name] = {"dtype": "F32", "shape": list(array.shape), "data_offsets": [offset, offset + array.nbytes]}
        chunks.append(array.tobytes())
        offset += array.nbytes
    if metadata:
        header["__metadata__"] = {str(k): str(v) for k, v in metadata.items()}
    encoded = json.dumps(header, separators=(",", ":")).encode("utf-8")
    encoded += b" " * (-len(encoded) % 8)  # keep the data 8-byte aligned
    with open(path + ".tmp", "wb") as f:
        f.write(struct.pack("<Q", len(encoded)))
        f.write(encoded)
        for chunk in chunks:
            f.write(chunk)
    os.replace(path + ".tmp", path)


def load_weights(model, path, strict=True):
    """Loads a .safetensors file into `model` (strict like load_state_dict); returns the file's metadata."""
    tensors, metadata = read_safetensors(path)
    model.load_state_dict(tensors, strict=strict)
    return metadata


def save_weights(model, path, metadata=None):
    write_safetensors(path, model.state_dict(), metadata)


# ---------------------------------------------------------------------------------------------------
# UNet3+ from pre-activation bottleneck blocks (nets/models/unet3plus.h, bottleneck.h).

def _conv(dims, cin, cout, kernel, stride=1, padding=0):
    return (nn.Conv2d if dims == 2 else nn.Conv3d)(cin, cout, kernel, stride, padding)


def _interpolate_mode(dims):
    return "bilinear" if dims == 2 else "trilinear"


class Bottleneck(nn.Module):
    """y = skip(x) + expand(a(conv(a(reduce(a(x)))))), a = LeakyReLU(slope); mid = max(out // 4, min_mid)."""

    def __init__(self, dims, cin, cout, downsample, min_mid, slope):
        super().__init__()
        mid = max(cout // 4, min_mid)
        stride = 2 if downsample else 1
        self.slope = slope
        self.reduce = _conv(dims, cin, mid, 1)
        self.conv = _conv(dims, mid, mid, 3, stride, 1)
        self.expand = _conv(dims, mid, cout, 1)
        self.skip = _conv(dims, cin, cout, 2 if downsample else 1, stride, 0)

    def forward(self, x):
        a = lambda t: F.leaky_relu(t, self.slope)
        return self.skip(x) + self.expand(a(self.conv(a(self.reduce(a(x))))))


class UNet3Plus(nn.Module):
    """smokesvd's lean UNet3+ (G_rho, G_u, NvRef). Every spatial size must be divisible by 2^(L-1)."""

    def __init__(self, dims, in_channels, out_channels, filters, cat_channels, min_mid, negative_slope, output,
                 presence_slots=0):
        super().__init__()
        self.dims, self.levels, self.output_relu = dims, len(filters), output == "relu"
        levels, fused = len(filters), cat_channels * len(filters)
        block = lambda cin, cout, down: Bottleneck(dims, cin, cout, down, min_mid, negative_slope)
        self.stem = _conv(dims, in_channels, filters[0], 3, 1, 1)
        self.presence = nn.Linear(presence_slots, filters[0]) if presence_slots > 0 else None
        self.down = nn.ModuleList(block(filters[l - 1], filters[l], True) for l in range(1, levels))
        # decoder[d][s] for s = 0..L-1 makes the source of level s; decoder[d][L] fuses them.
        self.decoder = nn.ModuleList()
        for d in range(levels - 1):
            stage = nn.ModuleList(block(fused if d < s < levels - 1 else filters[s], cat_channels, False)
                                  for s in range(levels))
            stage.append(block(fused, fused, False))
            self.decoder.append(stage)
        self.heads = nn.ModuleList(_conv(dims, fused if k < levels - 1 else filters[-1], out_channels, 1)
                                   for k in range(levels))

    def _pool(self, x):
        return (F.max_pool2d if self.dims == 2 else F.max_pool3d)(x, 2, 2, ceil_mode=True)

    def _head(self, k, x):
        y = self.heads[k](x)
        return F.relu(y) if self.output_relu else y

    def forward(self, x, presence=None, deep_supervision=False):
        if (self.presence is not None) != (presence is not None):
            raise ValueError("UNet3+: a presence vector is needed exactly when the config has presence_slots > 0")
        h = self.stem(x)
        if self.presence is not None:
            h = h + self.presence(presence.reshape(x.shape[0], -1)).reshape(*h.shape[:2], *([1] * self.dims))
        encoder = [h]
        for block in self.down:
            encoder.append(block(encoder[-1]))
        decoder = [None] * (self.levels - 1)
        for d in range(self.levels - 2, -1, -1):
            parts = []
            for s in range(self.levels):
                block = self.decoder[d][s]
                if s <= d:
                    source = encoder[s]
                    for _ in range(d - s):
                        source = self._pool(source)
                    parts.append(block(source))
                else:
                    deeper = encoder[-1] if s == self.levels - 1 else decoder[s]
                    parts.append(F.interpolate(block(deeper), scale_factor=2 ** (s - d),
                                               mode=_interpolate_mode(self.dims), align_corners=False))
            decoder[d] = self.decoder[d][self.levels](torch.cat(parts, 1))
        y = self._head(0, decoder[0])
        if not deep_supervision:
            return y
        heads = [F.interpolate(self._head(k, decoder[k] if k < self.levels - 1 else encoder[-1]),
                               scale_factor=2 ** k, mode="nearest") for k in range(1, self.levels)]
        return y, heads


# ---------------------------------------------------------------------------------------------------
# SvDiff's attention-free DDPM UNet (nets/models/ddpm_unet.h, nets/modules/res_block.h).

def timestep_embedding(t, dim, dtype):
    """[sin(t f_j), cos(t f_j)], f_j = exp(-ln(10000) j / (dim/2 - 1)); the angles in float32 as smokesvd's
    kernel computes them, sin and cos in `dtype`; a trailing zero column when dim is odd."""
    half = dim // 2
    j = torch.arange(half, dtype=torch.float32)
    frequencies = torch.exp(-math.log(10000.0) * j / (half - 1.0))
    angles = (t.reshape(-1, 1).to(torch.float32) * frequencies[None, :]).to(dtype)
    embedding = torch.cat([torch.sin(angles), torch.cos(angles)], 1)
    return F.pad(embedding, (0, dim % 2))


class Holder(nn.Module):
    """A module that only names its children (temb, down.i, mid, ...)."""


class ResnetBlock(nn.Module):
    def __init__(self, cin, cout, temb_channels, groups, dropout):
        super().__init__()
        self.norm1 = nn.GroupNorm(groups, cin, eps=1e-6)
        self.conv1 = nn.Conv2d(cin, cout, 3, 1, 1)
        self.temb_proj = nn.Linear(temb_channels, cout)
        self.norm2 = nn.GroupNorm(groups, cout, eps=1e-6)
        self.dropout = nn.Dropout(dropout)
        self.conv2 = nn.Conv2d(cout, cout, 3, 1, 1)
        self.nin_shortcut = nn.Conv2d(cin, cout, 1) if cin != cout else None

    def forward(self, x, temb):
        h = self.conv1(F.silu(self.norm1(x)))
        h = h + self.temb_proj(F.silu(temb))[:, :, None, None]
        h = self.conv2(self.dropout(F.silu(self.norm2(h))))
        return (x if self.nin_shortcut is None else self.nin_shortcut(x)) + h


class DdpmUNet(nn.Module):
    """out = UNet(x, t) (eps or v, as the config's options.prediction says); every spatial size must be divisible
    by 2^(L-1)."""

    def __init__(self, in_channels, out_channels, channels, channel_mult, res_blocks, groups, dropout=0.0):
        super().__init__()
        self.channels, self.levels, temb = channels, len(channel_mult), 4 * channels
        block = lambda cin, cout: ResnetBlock(cin, cout, temb, groups, dropout)
        self.temb = Holder()
        self.temb.dense = nn.ModuleList([nn.Linear(channels, temb), nn.Linear(temb, temb)])
        self.conv_in = nn.Conv2d(in_channels, channels, 3, 1, 1)
        skips, current = [channels], channels
        self.down = nn.ModuleList()
        for i, mult in enumerate(channel_mult):
            level = Holder()
            level.block = nn.ModuleList()
            for _ in range(res_blocks):
                level.block.append(block(current, channels * mult))
                current = channels * mult
                skips.append(current)
            if i < self.levels - 1:
                level.downsample = Holder()
                level.downsample.conv = nn.Conv2d(current, current, 3, 2, 1)
                skips.append(current)
            self.down.append(level)
        self.mid = Holder()
        self.mid.block_1 = block(current, current)
        self.mid.block_2 = block(current, current)
        up_levels = [None] * self.levels
        for i in reversed(range(self.levels)):
            out, blocks = channels * channel_mult[i], []
            for _ in range(res_blocks + 1):
                blocks.append(block(current + skips.pop(), out))
                current = out
            up_levels[i] = (blocks, out)
        self.up = nn.ModuleList()
        for i, (blocks, out) in enumerate(up_levels):
            level = Holder()
            level.block = nn.ModuleList(blocks)
            if i > 0:
                level.upsample = Holder()
                level.upsample.conv = nn.Conv2d(out, out, 3, 1, 1)
            self.up.append(level)
        self.norm_out = nn.GroupNorm(groups, current, eps=1e-6)
        self.conv_out = nn.Conv2d(current, out_channels, 3, 1, 1)

    def forward(self, x, t):
        dense = self.temb.dense
        temb = dense[1](F.silu(dense[0](timestep_embedding(t, self.channels, x.dtype))))
        h = self.conv_in(x)
        skips = [h]
        for i, level in enumerate(self.down):
            for block in level.block:
                h = block(h, temb)
                skips.append(h)
            if i < self.levels - 1:
                h = level.downsample.conv(h)
                skips.append(h)
        h = self.mid.block_2(self.mid.block_1(h, temb), temb)
        for i in reversed(range(self.levels)):
            level = self.up[i]
            for block in level.block:
                h = block(torch.cat([h, skips.pop()], 1), temb)
            if i > 0:
                h = level.upsample.conv(F.interpolate(h, scale_factor=2, mode="nearest"))
        return self.conv_out(F.silu(self.norm_out(h)))


# ---------------------------------------------------------------------------------------------------
# Building from configs.

_UNET3PLUS_KEYS = {"architecture", "dims", "in_channels", "out_channels", "filters", "cat_channels", "min_mid",
                   "negative_slope", "output", "presence_slots"}
_DDPM_KEYS = {"architecture", "in_channels", "out_channels", "channels", "channel_mult", "res_blocks", "groups",
              "dropout"}


def build_model(config):
    """The architecture of a network config (the whole config.json, or its "model" section)."""
    model = config["model"] if "model" in config else config
    architecture = model.get("architecture")
    if architecture == "unet3plus":
        unknown = set(model) - _UNET3PLUS_KEYS
        if unknown:
            raise ValueError(f"model: unknown keys {sorted(unknown)} (known: {sorted(_UNET3PLUS_KEYS)})")
        return UNet3Plus(model["dims"], model["in_channels"], model["out_channels"], model["filters"],
                         model["cat_channels"], model["min_mid"], model["negative_slope"], model["output"],
                         model.get("presence_slots", 0))
    if architecture == "ddpm_unet":
        unknown = set(model) - _DDPM_KEYS
        if unknown:
            raise ValueError(f"model: unknown keys {sorted(unknown)} (known: {sorted(_DDPM_KEYS)})")
        return DdpmUNet(model["in_channels"], model["out_channels"], model["channels"], model["channel_mult"],
                        model["res_blocks"], model["groups"], model.get("dropout", 0.0))
    raise ValueError(f"model: 'architecture' must be \"unet3plus\" or \"ddpm_unet\", got {architecture!r}")


def read_config(folder):
    with open(os.path.join(folder, "config.json")) as f:
        return json.load(f)


def load_model(folder, dtype=torch.float32):
    """The trained model in `folder` (config.json + model.safetensors), in evaluation mode."""
    model = build_model(read_config(folder))
    load_weights(model, os.path.join(folder, "model.safetensors"))
    return model.to(dtype).eval()


# ---------------------------------------------------------------------------------------------------
# The networks with their input encodings (pipeline/networks/*.h).

def density_generator(model, lifted, presence):
    """G_rho: the 16 slot images lifted into the volume [16, D, H, W] (missing views zero), presence [16] of
    0/1 -> density [D, H, W]."""
    return model(lifted.unsqueeze(0), presence.reshape(1, -1))[0, 0]


def velocity_generator(model, current, next_density):
    """G_u: densities [D, H, W] at t and t+1 -> cell-centred velocity [3, D, H, W] (cells per step)."""
    return model(torch.stack([current, next_density]).unsqueeze(0))[0]


def _blurred(image):
    half = F.interpolate(image, scale_factor=0.5, mode="bilinear", align_corners=False)
    return F.interpolate(half, scale_factor=2, mode="bilinear", align_corners=False)


def refine(model, render, minus, plus, previous, before_previous):
    """NvRef: images [N, 1, h, w] in [0, 1] -> (refined = render + residual, residual)."""
    residual = model(torch.cat([render, minus, plus, _blurred(previous), _blurred(before_previous)], 1))
    return render + residual, residual


def predict_side_view(model, noisy, condition, steps):
    """SvDiff / SvDiff-init: noisy [N, S, h, w] in [-1, 1], condition [N, C, h, w] in [0, 1], steps [N] -> the
    network's output: the noise eps, or v = sqrt(abar) eps - sqrt(1 - abar) x0 (options.prediction "v")."""
    return model(torch.cat([noisy, 2 * condition - 1], 1), steps)


def side_view_estimates(config, noisy, output, steps):
    """(eps, x0) that a side-view model's output implies for noisy [N, S, h, w] at integer steps [N], with the
    config's linear schedule (options diffusion_steps, beta_start, beta_end; abar_s = prod_{k<=s} (1 - beta_k)):
        epsilon: eps = out,                        x0 = (x - sqrt(1 - abar) eps) / sqrt(abar)
        v:       eps = sqrt(1 - abar) x + sqrt(abar) out,   x0 = sqrt(abar) x - sqrt(1 - abar) out"""
    options = config["options"]
    betas = np.linspace(options["beta_start"], options["beta_end"], options["diffusion_steps"], dtype=np.float64)
    abar = torch.from_numpy(np.cumprod(1.0 - betas))[steps.long()].to(noisy.dtype).reshape(-1, 1, 1, 1)
    a, b = abar.sqrt(), (1 - abar).sqrt()
    prediction = options.get("prediction", "epsilon")
    if prediction == "epsilon":
        return output, (noisy - b * output) / a
    if prediction == "v":
        return b * noisy + a * output, a * noisy - b * output
    raise ValueError(f"options.prediction must be 'epsilon' or 'v', not {prediction!r}")


# ---------------------------------------------------------------------------------------------------
# Command line.

def _tensor(arrays, key, dtype):
    if key not in arrays:
        raise ValueError(f"inputs: missing array '{key}' (present: {', '.join(sorted(arrays))})")
    return torch.from_numpy(np.asarray(arrays[key])).to(dtype)


_NETWORK_INPUTS = {"grho-coarse": ["lifted", "presence"], "grho-fine": ["lifted", "presence"],
                   "gu": ["current", "next"],
                   "nvref": ["render", "minus", "plus", "previous", "before_previous"],
                   "svdiff": ["noisy", "condition", "steps"], "svdiff-init": ["noisy", "condition", "steps"]}


def _network_outputs(config, model, inputs):
    network = config.get("network")
    if network in ("grho-coarse", "grho-fine"):
        return {"density": density_generator(model, *inputs)}
    if network == "gu":
        return {"velocity": velocity_generator(model, *inputs)}
    if network == "nvref":
        refined, residual = refine(model, *inputs)
        return {"refined": refined, "residual": residual}
    noisy, steps = inputs[0], inputs[2]
    output = predict_side_view(model, *inputs)
    eps, clean = side_view_estimates(config, noisy, output, steps)
    return {"prediction": output, "eps": eps, "clean": clean}


def _architecture_outputs(model, arrays, dtype, deep_supervision):
    x = _tensor(arrays, "x", dtype)
    if isinstance(model, DdpmUNet):
        return {"y": model(x, _tensor(arrays, "t", dtype))}
    presence = _tensor(arrays, "presence", dtype) if model.presence is not None else None
    if not deep_supervision:
        return {"y": model(x, presence)}
    y, heads = model(x, presence, True)
    return {"y": y, **{f"supervision_{k + 1}": head for k, head in enumerate(heads)}}


def main(argv):
    parser = argparse.ArgumentParser(description="Run a smokesvd network in PyTorch (see the top of this file).")
    parser.add_argument("model_dir", help="folder with config.json and model.safetensors")
    parser.add_argument("--inputs", required=True, help=".npz of the input arrays")
    parser.add_argument("--out", required=True, help=".npz to write the outputs to (float32)")
    parser.add_argument("--deep-supervision", action="store_true", help="also the UNet3+ supervision heads")
    parser.add_argument("--dtype", choices=["float32", "float64"], default="float32", help="the twin's precision")
    parser.add_argument("--save-weights", metavar="PATH", help="also write the loaded model's state_dict (F32) to PATH")
    args = parser.parse_args(argv)
    dtype = getattr(torch, args.dtype)
    config = read_config(args.model_dir)
    network = config.get("network")
    model = load_model(args.model_dir, dtype)
    if args.save_weights:
        save_weights(model, args.save_weights)
    with np.load(args.inputs) as data:
        arrays = {key: data[key] for key in data.files}
    outputs = {}
    with torch.no_grad():
        if "x" in arrays:
            outputs.update(_architecture_outputs(model, arrays, dtype, args.deep_supervision))
        keys = _NETWORK_INPUTS.get(network, [])
        if keys and any(key in arrays for key in keys):
            outputs.update(_network_outputs(config, model, [_tensor(arrays, key, dtype) for key in keys]))
    if not outputs:
        raise ValueError(f"{args.inputs}: neither the architecture's input 'x' nor the inputs of network "
                         f"{network!r} ({', '.join(keys) or 'none known'})")
    np.savez(args.out, **{key: value.to(torch.float32).numpy() for key, value in outputs.items()})


if __name__ == "__main__":
    try:
        main(sys.argv[1:])
    except (ValueError, KeyError, OSError, RuntimeError) as error:
        print(f"smokesvd_models: error: {error}", file=sys.stderr)
        sys.exit(1)
