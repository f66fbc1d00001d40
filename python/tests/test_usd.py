"""USD BasisCurves in (files written here with usd-core), and python -m clhair.convert."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import clhair
from clhair.io import read_usd
from conftest import base_scene

pxr = pytest.importorskip("pxr", reason="usd-core is not installed (pip install usd-core)")
from pxr import Gf, Sdf, Usd, UsdGeom, Vt  # noqa: E402


def write_curves(path: Path, points, counts, kind="linear", basis=None, wrap="nonperiodic",
                 widths=None, widths_interp="vertex", color=None, color_interp="constant",
                 translate=None) -> None:
    stage = Usd.Stage.CreateNew(str(path))
    curves = UsdGeom.BasisCurves.Define(stage, "/hair")
    curves.CreatePointsAttr(Vt.Vec3fArray([Gf.Vec3f(*map(float, p)) for p in points]))
    curves.CreateCurveVertexCountsAttr(Vt.IntArray([int(c) for c in counts]))
    curves.CreateTypeAttr(kind)
    if basis:
        curves.CreateBasisAttr(basis)
    curves.CreateWrapAttr(wrap)
    if widths is not None:
        curves.CreateWidthsAttr(Vt.FloatArray([float(w) for w in widths]))
        curves.SetWidthsInterpolation(widths_interp)
    if color is not None:
        pv = curves.CreateDisplayColorPrimvar(color_interp)
        pv.Set(Vt.Vec3fArray([Gf.Vec3f(*map(float, c)) for c in color]))
    if translate is not None:
        UsdGeom.Xformable(curves).AddTranslateOp().Set(Gf.Vec3d(*translate))
    stage.GetRootLayer().Save()


def test_linear_with_widths_and_colour(tmp_path: Path) -> None:
    pts = np.array([[0, 0, 0], [0, 0.05, 0], [0, 0.1, 0], [0.01, 0, 0], [0.01, 0.1, 0]],
                   dtype=np.float32)
    write_curves(tmp_path / "a.usda", pts, [3, 2], widths=[1e-3, 2e-3, 3e-3, 4e-3, 5e-3],
                 color=[[0.2, 0.3, 0.4], [0.5, 0.6, 0.7]], color_interp="uniform",
                 translate=(0.0, 1.0, 0.0))
    g = read_usd(tmp_path / "a.usda")
    assert list(g.counts) == [3, 2]
    assert np.allclose(g.points, pts + [0, 1, 0])
    assert np.allclose(g.widths, [1e-3, 2e-3, 3e-3, 4e-3, 5e-3])
    assert np.allclose(g.colors, [[0.2, 0.3, 0.4]] * 3 + [[0.5, 0.6, 0.7]] * 2)


@pytest.mark.parametrize("basis", ["bezier", "bspline", "catmullRom"])
def test_cubic_curves(tmp_path: Path, basis: str) -> None:
    # control points on a line, evenly spaced: every basis keeps the curve on the line
    n = 7
    ctrl = np.stack([np.zeros(n), np.linspace(0, 0.3, n), np.zeros(n)], axis=1)
    write_curves(tmp_path / "c.usda", ctrl, [n], kind="cubic", basis=basis,
                 widths=np.linspace(1e-3, 2e-3, n), color=[[0.3, 0.2, 0.1]])
    g = read_usd(tmp_path / "c.usda", samples_per_span=4)
    spans = {"bezier": 2, "bspline": 4, "catmullRom": 4}[basis]
    assert list(g.counts) == [spans * 4 + 1]
    assert np.allclose(g.points[:, [0, 2]], 0)
    assert np.all(np.diff(g.points[:, 1]) > 0)  # monotone along the line
    if basis == "bezier":  # ends on the end points
        assert np.allclose(g.points[[0, -1], 1], [0, 0.3], atol=1e-6)
    if basis == "catmullRom":  # through the interior control points, a span apart
        assert np.allclose(g.points[::4, 1], ctrl[1:-1, 1], atol=1e-6)
    if basis == "bspline":  # (p0 + 4 p1 + p2) / 6 = p1 on an even line
        assert np.allclose(g.points[0, 1], ctrl[1, 1], atol=1e-6)
    assert np.allclose(g.colors, [0.3, 0.2, 0.1])
    assert np.all(np.diff(g.widths) > 0)


def test_pinned_catmull_rom_passes_through_the_ends(tmp_path: Path) -> None:
    ctrl = np.array([[0, 0, 0], [0, 0.1, 0.02], [0, 0.2, 0], [0, 0.3, 0.03]])
    write_curves(tmp_path / "p.usda", ctrl, [4], kind="cubic", basis="catmullRom", wrap="pinned")
    g = read_usd(tmp_path / "p.usda", samples_per_span=3)
    assert np.allclose(g.points[::3], ctrl, atol=1e-6)


def test_refusals(tmp_path: Path) -> None:
    ctrl = np.zeros((5, 3))
    ctrl[:, 1] = np.arange(5)
    write_curves(tmp_path / "b.usda", ctrl, [5], kind="cubic", basis="bezier")
    with pytest.raises(clhair.Error, match="bezier curve of 5 points"):
        read_usd(tmp_path / "b.usda")
    write_curves(tmp_path / "l.usda", ctrl[:4], [4], kind="cubic", basis="bspline", wrap="periodic")
    with pytest.raises(clhair.Error, match="periodic"):
        read_usd(tmp_path / "l.usda")
    with pytest.raises(clhair.Error, match="does not exist"):
        read_usd(tmp_path / "missing.usda")


def test_convert_and_render(renderer: clhair.Renderer, tmp_path: Path) -> None:
    k = np.arange(6) / 5 - 0.5
    pts = np.concatenate([np.stack([np.full(6, x), 0.2 * k, np.zeros(6)], axis=1)
                          for x in np.linspace(-0.05, 0.05, 30)])
    write_curves(tmp_path / "h.usda", pts, [6] * 30, color=[[0.4, 0.25, 0.1]])
    for ext in ("ply", "hair"):
        r = subprocess.run([sys.executable, "-m", "clhair.convert", str(tmp_path / "h.usda"),
                            str(tmp_path / f"h.{ext}")], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        assert "30 strands, 180 points" in r.stdout
    g = read_usd(tmp_path / "h.usda")
    a = renderer.render(base_scene({"groom": g}))
    assert (a["alpha"] >= 0.5).sum() > 50
    # .hair keeps the linear colours exactly; PLY stores 8-bit sRGB colours, so its frame
    # has the same geometry layers and colours within the 8-bit step
    b = renderer.render(base_scene({"strands_file": str(tmp_path / "h.hair")}))
    for key in ("rgba", "alpha", "tangent", "depth", "strand"):
        assert np.array_equal(a[key], b[key]), key
    c = renderer.render(base_scene({"strands_file": str(tmp_path / "h.ply")}))
    for key in ("alpha", "tangent", "depth", "strand"):
        assert np.array_equal(a[key], c[key]), key
    bad = subprocess.run([sys.executable, "-m", "clhair.convert", str(tmp_path / "h.usda"),
                          str(tmp_path / "h.xyz")], capture_output=True, text=True)
    assert bad.returncode == 1 and bad.stderr.count("\n") == 1 and ".xyz" in bad.stderr
