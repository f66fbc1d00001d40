#!/usr/bin/env python3
"""plot-crowd-budget.py — FLIP against frame time for the crowd under the segment budget.

Reads the crowd_budget.csv that `clhair_bench --only crowd --out DIR` writes (one row per
image size and variant: the full render, LOD alone, and each rule at each budget) and
draws, per image size, FLIP against the full render over the frame's wall time: one line
per rule through its budgets (1, 2, 4, 8 M, labelled), LOD alone as a point, and the
full render's time as a vertical line. Needs matplotlib (pip install matplotlib).

usage: scripts/plot-crowd-budget.py DIR/crowd_budget.csv docs/images/crowd_budget.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__.strip().splitlines()[-1])
    rows = list(csv.DictReader(open(sys.argv[1])))
    sizes = []
    for r in rows:
        s = (int(r["width"]), int(r["height"]))
        if s not in sizes:
            sizes.append(s)
    fig, axes = plt.subplots(1, len(sizes), figsize=(6.0 * len(sizes), 4.6), squeeze=False)
    styles = {"uniform": ("#c0392b", "o", "uniform rule (one factor)"),
              "screen": ("#2471a3", "s", "screen rule (by screen area)")}
    for ax, (w, h) in zip(axes[0], sizes):
        here = [r for r in rows if int(r["width"]) == w and int(r["height"]) == h]
        for rule, (color, marker, label) in styles.items():
            pts = sorted((int(r["budget"]), float(r["wall_ms"]), float(r["flip"]))
                         for r in here if r["variant"] == "budget" and r["rule"] == rule)
            ax.plot([p[1] / 1000 for p in pts], [p[2] for p in pts], color=color, marker=marker,
                    label=label)
            for b, t, f in pts:
                ax.annotate("%d M" % (b // 1000000), (t / 1000, f), textcoords="offset points",
                            xytext=(5, 4), fontsize=8, color=color)
        for r in here:
            if r["variant"] == "lod":
                ax.plot(float(r["wall_ms"]) / 1000, float(r["flip"]), "k^",
                        label="LOD alone (no budget)")
                ax.axhline(2 * float(r["flip"]), color="0.5", ls=":", lw=1,
                           label="target: 2x LOD alone's FLIP")
            if r["variant"] == "full":
                ax.axvline(float(r["wall_ms"]) / 1000, color="0.3", ls="--", lw=1,
                           label="LOD off (the reference): %.0f s" % (float(r["wall_ms"]) / 1000))
        ax.set_xscale("log")
        ax.set_xlabel("frame wall time, s (log)")
        ax.set_ylabel("FLIP against the full render")
        ax.set_title("crowd.json, %dx%d" % (w, h))
        ax.set_ylim(bottom=0)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
