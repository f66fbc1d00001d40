"""Shared fixtures: one renderer for the session, small synthetic grooms and scenes."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Dict

import numpy as np
import pytest

import clhair

ROOT = Path(__file__).resolve().parents[2]
# Ray's local cluster in the tests: no usage report sent anywhere
os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
W, H = 64, 48  # small frames: the suite's time stays small


def straight_groom(angle_deg: float = 30.0, tilt_deg: float = 0.0, strands: int = 40,
                   points: int = 6, length: float = 0.25, spacing: float = 0.003,
                   widths: bool = False, colors: bool = False) -> clhair.Groom:
    """Parallel straight strands in a plane through the origin: direction at `angle_deg`
    in the x-y plane, the plane then turned by `tilt_deg` about +x (toward the camera)."""
    a = np.radians(angle_deg)
    t = np.array([np.cos(a), np.sin(a), 0.0])
    side = np.array([-np.sin(a), np.cos(a), 0.0])
    c, s = np.cos(np.radians(tilt_deg)), np.sin(np.radians(tilt_deg))
    rx = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    t, side = rx @ t, rx @ side
    k = np.arange(points) / (points - 1) - 0.5
    offs = (np.arange(strands) - (strands - 1) / 2) * spacing
    pts = offs[:, None, None] * side + k[None, :, None] * length * t
    pts = pts.reshape(-1, 3).astype(np.float32)
    counts = np.full(strands, points, dtype=np.int32)
    w = np.full(len(pts), 0.002, dtype=np.float32) if widths else None
    col = None
    if colors:
        col = np.tile(np.array([[0.6, 0.3, 0.1]], dtype=np.float32), (len(pts), 1))
        col[:, 1] = np.linspace(0.1, 0.5, len(pts), dtype=np.float32)
    return clhair.Groom(pts, counts, widths=w, colors=col, name="straight")


def base_scene(groom_entry: Dict[str, Any]) -> Dict[str, Any]:
    """A 64x48 frame of the groom 0.6 from the camera; fibres drawn at least a pixel wide
    (the grooms here are far thinner than a pixel)."""
    groom_entry = dict(groom_entry)
    groom_entry.setdefault("appearance", {"min_hit_diameter_px": 1.0})
    return {
        "resolution": [W, H],
        "camera": {"position": [0.0, 0.0, 0.6], "target": [0.0, 0.0, 0.0], "fov": 35},
        "background": [0.1, 0.2, 0.3],
        "ambient": [0.1, 0.1, 0.1],
        "lights": [{"type": "directional", "direction": [0.3, 0.8, 0.5], "intensity": 3}],
        "grooms": [groom_entry],
    }


@pytest.fixture(scope="session")
def renderer() -> clhair.Renderer:
    return clhair.Renderer(device=os.environ.get("CLHAIR_DEVICE", ""))


@pytest.fixture(scope="session")
def cli() -> Path:
    path = Path(os.environ.get("CLHAIR_CLI", ROOT / "build" / "clhair"))
    if not path.exists():
        pytest.skip(f"the command {path} is not built (set CLHAIR_CLI)")
    return path
