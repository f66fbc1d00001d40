"""Grooms from USD files, and strand files written from grooms.

:func:`read_usd` reads every ``UsdGeom.BasisCurves`` prim of a stage (``usd-core`` from PyPI:
``pip install usd-core``) into one :class:`clhair.Groom`, in world space (each prim's
local-to-world transform at the default time applied):

- linear curves keep their points;
- cubic curves (bezier, bspline, catmullRom; nonperiodic or pinned wrap) are evaluated into
  polylines of ``samples_per_span`` points per span, which pass through the curve;
- ``widths`` (constant, uniform, varying or vertex) become per-point widths;
- ``primvars:displayColor`` (constant, uniform, varying or vertex) becomes per-point linear
  colour. Vertex primvars of cubic curves are evaluated with the curve's basis, varying ones
  linearly along each span.

Periodic curves (closed loops) are refused: a strand has a root and a tip.
"""

from __future__ import annotations

import os
from typing import List, Optional, Tuple, Union

import numpy as np

from . import Error, Groom

__all__ = ["read_usd", "write_strands"]

_BEZIER = np.array([[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 3, 0, 0], [1, 0, 0, 0]], dtype=np.float64)
_BSPLINE = np.array([[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 0, 3, 0], [1, 4, 1, 0]],
                    dtype=np.float64) / 6.0
_CATMULL = np.array([[-1, 3, -3, 1], [2, -5, 4, -1], [-1, 0, 1, 0], [0, 2, 0, 0]],
                    dtype=np.float64) / 2.0


def _spans(n: int, basis: str, wrap: str, where: str) -> Tuple[np.ndarray, int]:
    """Control-point indices of each span (spans, 4) and the span step, for a curve of n
    control points (pinned: phantom points at -1 and n, handled by the caller)."""
    if basis == "bezier":
        if n < 4 or (n - 4) % 3:
            raise Error(f"{where}: a bezier curve of {n} points; expected 4, 7, 10, ... "
                        "(3 per span plus 1)")
        starts = np.arange(0, n - 3, 3)
    else:
        m = n + 2 if wrap == "pinned" else n
        if m < 4:
            raise Error(f"{where}: a {basis} curve of {n} points; expected at least "
                        f"{2 if wrap == 'pinned' else 4}")
        starts = np.arange(0, m - 3)
    return starts[:, None] + np.arange(4)[None, :], len(starts)


def _evaluate(values: np.ndarray, basis: str, wrap: str, samples: int,
              where: str) -> np.ndarray:
    """A cubic curve's (n, k) control values evaluated at `samples` points per span (the
    last span's end included)."""
    n = len(values)
    v = values.astype(np.float64)
    if basis != "bezier" and wrap == "pinned":
        v = np.concatenate([2 * v[:1] - v[1:2], v, 2 * v[-1:] - v[-2:-1]])
    idx, spans = _spans(n, basis, wrap, where)
    matrix = {"bezier": _BEZIER, "bspline": _BSPLINE, "catmullRom": _CATMULL}[basis]
    t = np.arange(samples, dtype=np.float64) / samples
    powers = np.stack([t ** 3, t ** 2, t, np.ones_like(t)], axis=1)  # (samples, 4)
    weights = powers @ matrix  # (samples, 4)
    out = np.einsum("sj,cjk->csk", weights, v[idx]).reshape(spans * samples, -1)
    end = np.array([[1.0, 1.0, 1.0, 1.0]]) @ matrix  # t = 1
    last = end @ v[idx[-1]]
    return np.concatenate([out, last], axis=0)


def _linear_spans(values: np.ndarray, samples: int) -> np.ndarray:
    """Values given per span end (varying) interpolated linearly to `samples` per span."""
    t = np.arange(samples, dtype=np.float64) / samples
    a, b = values[:-1].astype(np.float64), values[1:].astype(np.float64)
    out = a[:, None, :] * (1 - t)[None, :, None] + b[:, None, :] * t[None, :, None]
    return np.concatenate([out.reshape(-1, values.shape[1]), values[-1:]], axis=0)


def _primvar(values: Optional[np.ndarray], interp: str, counts: np.ndarray, spans: List[int],
             cubic: bool, basis: str, wrap: str, samples: int, name: str,
             where: str) -> Optional[List[np.ndarray]]:
    """A primvar given per curve ("uniform"), once ("constant"), per span end ("varying") or
    per control point ("vertex"), as per-output-point arrays, curve by curve."""
    if values is None or len(values) == 0:
        return None
    values = np.asarray(values, dtype=np.float64).reshape(len(values), -1)
    out: List[np.ndarray] = []
    varying = [s + 1 for s in spans] if cubic else list(counts)
    expected = {"constant": 1, "uniform": len(counts), "vertex": int(np.sum(counts)),
                "varying": int(np.sum(varying))}
    if interp not in expected:
        raise Error(f"{where}: {name} has interpolation \"{interp}\"; expected constant, "
                    "uniform, varying or vertex")
    if len(values) != expected[interp]:
        raise Error(f"{where}: {name} has {len(values)} values for {interp} interpolation; "
                    f"expected {expected[interp]}")
    vo = yo = 0
    for c, (n, s) in enumerate(zip(counts, spans)):
        points = s * samples + 1 if cubic else int(n)
        if interp == "constant":
            out.append(np.repeat(values[:1], points, axis=0))
        elif interp == "uniform":
            out.append(np.repeat(values[c:c + 1], points, axis=0))
        elif interp == "vertex":
            v = values[vo:vo + n]
            out.append(_evaluate(v, basis, wrap, samples, where) if cubic else v)
        else:
            k = varying[c]
            v = values[yo:yo + k]
            out.append(_linear_spans(v, samples) if cubic else v)
            yo += k
        vo += int(n)
    return out


def read_usd(path: Union[str, "os.PathLike[str]"], samples_per_span: int = 4,
             name: Optional[str] = None) -> Groom:
    """Every BasisCurves prim of the USD file at ``path`` as one groom (see the module)."""
    try:
        from pxr import Usd, UsdGeom  # noqa: F401 (usd-core)
    except ImportError as e:
        raise Error("clhair.io.read_usd needs usd-core: pip install usd-core") from e
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise Error(f"{path}: does not exist")
    if not 1 <= int(samples_per_span) <= 64:
        raise Error(f"samples_per_span must be 1..64, not {samples_per_span}")
    samples = int(samples_per_span)
    stage = Usd.Stage.Open(path)
    if stage is None:
        raise Error(f"{path}: USD cannot open it")
    points_all: List[np.ndarray] = []
    counts_all: List[int] = []
    widths_all: List[np.ndarray] = []
    colors_all: List[np.ndarray] = []
    any_width = any_color = False
    prims = [p for p in stage.Traverse() if p.IsA(UsdGeom.BasisCurves)]
    if not prims:
        raise Error(f"{path}: holds no BasisCurves prim")
    time = Usd.TimeCode.Default()
    for prim in prims:
        where = f"{path}: {prim.GetPath()}"
        curves = UsdGeom.BasisCurves(prim)
        kind = curves.GetTypeAttr().Get(time) or "cubic"
        basis = curves.GetBasisAttr().Get(time) or "bezier"
        wrap = curves.GetWrapAttr().Get(time) or "nonperiodic"
        if wrap == "periodic":
            raise Error(f"{where}: periodic (closed) curves are not strands; expected "
                        "nonperiodic or pinned")
        if kind not in ("linear", "cubic"):
            raise Error(f"{where}: type \"{kind}\"; expected linear or cubic")
        if kind == "cubic" and basis not in ("bezier", "bspline", "catmullRom"):
            raise Error(f"{where}: basis \"{basis}\"; expected bezier, bspline or catmullRom")
        cubic = kind == "cubic"
        pts = np.asarray(curves.GetPointsAttr().Get(time), dtype=np.float64).reshape(-1, 3)
        counts = np.asarray(curves.GetCurveVertexCountsAttr().Get(time), dtype=np.int64)
        if counts.size == 0 or int(counts.sum()) != len(pts):
            raise Error(f"{where}: curveVertexCounts add up to {int(counts.sum())}, "
                        f"but there are {len(pts)} points")
        xform = np.asarray(
            UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(time), dtype=np.float64)
        spans: List[int] = []
        offset = 0
        for i, n in enumerate(counts):
            if n < 2:
                raise Error(f"{where}: curve {i} has {n} point(s); a strand needs 2")
            p = pts[offset:offset + n]
            if cubic:
                _, s = _spans(int(n), basis, wrap, f"{where}: curve {i}")
                spans.append(s)
                p = _evaluate(p, basis, wrap, samples, f"{where}: curve {i}")
            else:
                spans.append(int(n) - 1)
            # USD matrices act on row vectors: p' = [p 1] M
            world = np.concatenate([p, np.ones((len(p), 1))], axis=1) @ xform
            points_all.append(world[:, :3])
            counts_all.append(len(p))
            offset += int(n)
        # widths: object units, scaled by the transform's mean scale
        scale = float(np.cbrt(abs(np.linalg.det(xform[:3, :3])))) or 1.0
        widths = curves.GetWidthsAttr().Get(time)
        w = _primvar(None if widths is None else np.asarray(widths), curves.GetWidthsInterpolation(),
                     counts, spans, cubic, basis, wrap, samples, "widths", where)
        color_pv = UsdGeom.PrimvarsAPI(prim).GetPrimvar("displayColor")
        c = None
        if color_pv and color_pv.HasValue():
            c = _primvar(np.asarray(color_pv.ComputeFlattened(time)), color_pv.GetInterpolation(),
                         counts, spans, cubic, basis, wrap, samples, "displayColor", where)
        n_out = [len(p) for p in points_all[-len(counts):]]
        if w is not None:
            any_width = True
            widths_all.extend([x[:, 0] * scale for x in w])
        else:
            widths_all.extend([np.full(k, np.nan) for k in n_out])
        if c is not None:
            any_color = True
            colors_all.extend(c)
        else:
            colors_all.extend([np.full((k, 3), np.nan) for k in n_out])
    points = np.concatenate(points_all).astype(np.float32)
    counts_arr = np.asarray(counts_all, dtype=np.int64)
    widths_arr = colors_arr = None
    if any_width:
        widths_arr = np.concatenate(widths_all).astype(np.float32)
        if np.isnan(widths_arr).any():
            raise Error(f"{path}: some BasisCurves prims have widths and others none; give "
                        "all of them widths or none")
    if any_color:
        colors_arr = np.concatenate(colors_all).astype(np.float32)
        if np.isnan(colors_arr).any():
            raise Error(f"{path}: some BasisCurves prims have displayColor and others none; "
                        "give all of them colours or none")
    stem = os.path.splitext(os.path.basename(path))[0]
    return Groom(points, counts_arr, widths_arr, colors_arr, name=name or stem)


def write_strands(groom: Groom, path: Union[str, "os.PathLike[str]"]) -> None:
    """Writes a groom to a strand file (.hair, .ply or .data by extension)."""
    groom.write(path)
