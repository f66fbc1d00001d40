#!/usr/bin/env python3
"""plot-flip-per-ms.py — quality against cost of every configuration of the quality table.

Usage: plot-flip-per-ms.py OUT.png BENCH.json [BENCH2.json ...] [--title TITLE]

Reads the "quality" section of `clhair_bench --only quality` reports (bench.json: per
configuration and distance the mean FLIP over the hair against the Embree reference and
the frame's device time) and draws, for every groom and distance, each configuration as a
point at (frame ms, hair FLIP): lower and further left is better. Several reports (for
example 960x540 and 1920x1080, each its own panel row) are drawn one row each. Rows of one
configuration family are joined: final N (N = 4, 16, 64) and final SWR1 N as lines, so the
slope shows how fast each converges per millisecond.
"""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.ticker  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

DISTANCES = ("close", "mid", "far")


def cells(report):
    """(groom name, {config: {distance: (ms, flip)}}) for each groom in a report."""
    q = report.get("quality", {})
    out = []
    for groom, node in (("groom1", q), ("groom2", q.get("groom2", {}))):
        rows = {}
        for name, per in node.items():
            if name in ("reference", "groom2", "lights_maps", "references_mid"):
                continue
            if not isinstance(per, dict):
                continue
            for d in DISTANCES:
                v = per.get(d)
                if isinstance(v, dict) and "flip_hair" in v and "frame_ms" in v:
                    rows.setdefault(name, {})[d] = (v["frame_ms"], v["flip_hair"])
        if rows:
            out.append((groom, rows))
    return out


def family(name):
    """The line a configuration belongs to (final N rows of one pass path), or None."""
    parts = name.split()
    if parts and parts[0] == "final" and parts[-1].isdigit():
        return " ".join(parts[:-1])
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("reports", nargs="+")
    ap.add_argument("--title", default="Hair FLIP against frame time (PoCL, 2-core CPU)")
    a = ap.parse_args()
    rows = []
    for path in a.reports:
        with open(path) as f:
            report = json.load(f)
        size = report.get("quality_size", path)
        for groom, data in cells(report):
            rows.append((f"{groom}, {size}", data))
    if not rows:
        sys.exit("plot-flip-per-ms.py: no quality rows in " + ", ".join(a.reports))
    names = sorted({n for _, data in rows for n in data})
    cmap = plt.get_cmap("tab20")
    colour = {n: cmap(i % 20) for i, n in enumerate(names)}
    fig, axes = plt.subplots(len(rows), 3, figsize=(15, 3.6 * len(rows)), squeeze=False)
    for r, (label, data) in enumerate(rows):
        for c, d in enumerate(DISTANCES):
            ax = axes[r][c]
            lines = {}
            for n in names:
                if d not in data.get(n, {}):
                    continue
                ms, flip = data[n][d]
                ax.scatter([ms], [flip], color=colour[n], s=28, label=n, zorder=3)
                fam = family(n)
                if fam:
                    lines.setdefault(fam, []).append((ms, flip, n))
            for fam, pts in lines.items():
                pts.sort()
                ax.plot([p[0] for p in pts], [p[1] for p in pts], color=colour[pts[-1][2]],
                        lw=1, zorder=2)
            ax.set_xscale("log")
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.set_title(f"{label}, {d}", fontsize=9)
            ax.set_xlabel("frame ms (log)", fontsize=8)
            ax.set_ylabel("hair FLIP", fontsize=8)
            ax.grid(True, which="both", alpha=0.3)
            ax.tick_params(labelsize=7)
    handles, labels = [], []
    for ax in axes.flat:
        for h, l in zip(*ax.get_legend_handles_labels()):
            if l not in labels:
                handles.append(h)
                labels.append(l)
    fig.legend(handles, labels, loc="lower center", ncol=min(len(labels), 5), fontsize=8)
    fig.suptitle(a.title)
    fig.tight_layout(rect=(0, 0.04 + 0.012 * ((len(labels) + 4) // 5), 1, 0.97))
    fig.savefig(a.out, dpi=90)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
