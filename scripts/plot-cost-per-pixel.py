#!/usr/bin/env python3
"""plot-cost-per-pixel.py — a frame's cost against its pixel count.

Usage: plot-cost-per-pixel.py OUT.png BENCH.json [--title TITLE]

Reads the "pixels"/"cost" rows of a `clhair_bench --only pixels --pixel-parts cost` report
(bench.json: per image size and setting, "before" being LOD off with the scene's map
resolution and "default" LOD from the screen, the frame's device time and its shadow and
strands stages) and draws the frame time of both settings against the pixel count on log-log
axes, with the default's shadow maps (their strand passes included where the stage times
count them) as a dashed line and a line of slope 1 (cost proportional to the pixels) through
the default's smallest size for reference.
"""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(report, setting):
    cost = report.get("pixels", {}).get("cost", [])
    out = sorted((r for r in cost if r.get("lod") == setting), key=lambda r: r["pixels"])
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("report")
    ap.add_argument("--title", default="A frame's cost against its pixels (default scene, PoCL)")
    a = ap.parse_args()
    with open(a.report) as f:
        report = json.load(f)
    before, default = rows(report, "before"), rows(report, "default")
    if not default:
        sys.exit("plot-cost-per-pixel: the report has no pixels/cost rows")
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    for data, label, style in ((before, "LOD off, maps at the scene's size", "o-"),
                               (default, "default (LOD and maps from the screen)", "s-")):
        if data:
            ax.plot([r["pixels"] for r in data], [r["frame_ms"] for r in data], style, label=label)
    ax.plot([r["pixels"] for r in default], [r["shadow_ms"] for r in default], "s--",
            color="tab:orange", alpha=0.6, label="default: shadow stage (the maps' depth passes count as strands)")
    p0, t0 = default[0]["pixels"], default[0]["frame_ms"]
    xs = [r["pixels"] for r in default]
    ax.plot(xs, [t0 * x / p0 for x in xs], ":", color="grey", label="proportional to pixels")
    for r in default:
        ax.annotate(r["size"], (r["pixels"], r["frame_ms"]), textcoords="offset points",
                    xytext=(4, -12), fontsize=7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("pixels")
    ax.set_ylabel("frame device time, ms")
    ax.set_title(a.title, fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(a.out)


if __name__ == "__main__":
    main()
