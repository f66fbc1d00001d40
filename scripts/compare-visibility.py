#!/usr/bin/env python3
"""compare-visibility.py — how far baked visibility tables (.clhvis) are from a reference.

Usage: compare-visibility.py REFERENCE.clhvis TEST.clhvis [TEST2.clhvis ...] [--absorption A]
       compare-visibility.py --transmittance T.clhtrn TEST.clhvis [TEST2.clhvis ...]

Compares the cells the reference baked (any coefficient non-zero: a bake with
`--cell-stride N` leaves the others zero) and prints, per test table, the mean and max
absolute difference of the four L1 SH coefficients, and of the visibility
exp(-A x max(0, SH(d))) over 64 spherical Fibonacci directions d per cell (A = 0.5, the
scene default). Typical reference: `clhair bake-visibility SCENE -o ref.clhvis --rays 128
--points-per-cell 8 --cell-stride 16`, the tests baked with the same --cell-stride.

With --transmittance, the reference is what the tables approximate: the transmittance
exp(-A x events) of every traced ray before the L1 fit, averaged over each cell's points, per
direction, from `clhair bake-visibility SCENE -o r.clhvis --transmittance-out T.clhtrn --rays 64
--points-per-cell 8 --max-events 32 --cell-stride 64`. Per absorption A in the file, each test
table's exp(-A x max(0, SH(d))) is compared with it over the same directions: mean absolute
difference and mean signed difference (negative: the table shadows too much).
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


def read_transmittance(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"CLHTRN01" or len(data) < 20:
        sys.exit(f"compare-visibility: {path} is not a transmittance table")
    absorptions, cells, rays = struct.unpack_from("<III", data, 8)
    count = absorptions * cells * rays
    if cells != AXIS**3 or len(data) != 20 + 4 * absorptions + 4 * count:
        sys.exit(f"compare-visibility: {path} has an unexpected layout")
    a = np.frombuffer(data, dtype="<f4", offset=20, count=absorptions).astype(np.float64)
    t = np.frombuffer(data, dtype="<f4", offset=20 + 4 * absorptions, count=count)
    return a, t.reshape(absorptions, cells, rays).astype(np.float64)


def against_transmittance(path, tests):
    absorptions, t = read_transmittance(path)
    cells = np.any(t[0] != 0.0, axis=1)
    dirs = directions(t.shape[2])
    print(f"{path}: {int(cells.sum())} cells, {t.shape[2]} directions")
    print("table | " + " | ".join(f"A={a:g} mean / signed" for a in absorptions))
    for name in tests:
        sh = read(name)[cells]
        row = []
        for k, a in enumerate(absorptions):
            d = visibility(sh, dirs, a) - t[k][cells]
            row.append(f"{np.abs(d).mean():.4f} / {d.mean():+.4f}")
        print(f"{name} | " + " | ".join(row))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("reference", nargs="?")
    ap.add_argument("tests", nargs="+")
    ap.add_argument("--absorption", type=float, default=0.5)
    ap.add_argument("--transmittance", help="compare against this transmittance table instead")
    a = ap.parse_args()
    if a.transmittance:
        tests = ([a.reference] if a.reference else []) + a.tests
        against_transmittance(a.transmittance, tests)
        return
    if a.reference is None:
        sys.exit("compare-visibility: give a reference table or --transmittance")
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
