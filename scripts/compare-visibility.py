#!/usr/bin/env python3
"""compare-visibility.py — how far baked visibility tables (.clhvis) are from a reference.

Usage: compare-visibility.py REFERENCE.clhvis TEST.clhvis [TEST2.clhvis ...] [--absorption A]

Compares the cells the reference baked (any coefficient non-zero: a bake with
`--cell-stride N` leaves the others zero) and prints, per test table, the mean and max
absolute difference of the four L1 SH coefficients, and of the visibility
exp(-A x max(0, SH(d))) over 64 spherical Fibonacci directions d per cell (A = 0.5, the
scene default). Typical reference: `clhair bake-visibility SCENE -o ref.clhvis --rays 128
--points-per-cell 8 --cell-stride 16`, the tests baked with the same --cell-stride.
"""
import argparse
import math
import struct
import sys

import numpy as np

HEADER = 40
AXIS = 64
COEFFS = 4


def read(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"CLHVIS01":
        sys.exit(f"compare-visibility: {path} is not a .clhvis file")
    axis, coeffs = struct.unpack_from("<II", data, 12)
    if axis != AXIS or coeffs != COEFFS or len(data) != HEADER + 4 * AXIS**3 * COEFFS:
        sys.exit(f"compare-visibility: {path} has an unexpected layout")
    return np.frombuffer(data, dtype="<f4", offset=HEADER).reshape(-1, COEFFS).astype(np.float64)


def directions(n):
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = math.pi * (3.0 - math.sqrt(5.0)) * k
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def visibility(sh, dirs, absorption):
    y0 = 0.5 / math.sqrt(math.pi)
    y1 = math.sqrt(3.0 / (4.0 * math.pi))
    # coefficients Y00, Y1-1 (y), Y10 (z), Y11 (x)
    events = sh[:, :1] * y0 + y1 * (
        sh[:, 1:2] * dirs[None, :, 1] + sh[:, 2:3] * dirs[None, :, 2] + sh[:, 3:4] * dirs[None, :, 0]
    )
    return np.exp(-absorption * np.maximum(events, 0.0))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("reference")
    ap.add_argument("tests", nargs="+")
    ap.add_argument("--absorption", type=float, default=0.5)
    a = ap.parse_args()
    ref = read(a.reference)
    cells = np.any(ref != 0.0, axis=1)
    dirs = directions(64)
    rv = visibility(ref[cells], dirs, a.absorption)
    print(f"{a.reference}: {int(cells.sum())} cells")
    print("table | SH mean | SH max | visibility mean | visibility max")
    for t in a.tests:
        sh = read(t)[cells]
        d = np.abs(sh - ref[cells])
        v = np.abs(visibility(sh, dirs, a.absorption) - rv)
        print(f"{t} | {d.mean():.4f} | {d.max():.4f} | {v.mean():.5f} | {v.max():.4f}")


if __name__ == "__main__":
    main()
