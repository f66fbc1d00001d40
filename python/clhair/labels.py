"""Labels hair models learn from, computed from a frame's tangent, alpha and depth layers.

- :func:`orientation`: the 2D orientation map (NeuralHaircut's kind): per pixel the angle of
  the strand in the image, modulo pi, counter-clockwise from the image's +x axis (y up), and
  a confidence in [0, 1].
- :func:`strand_map`: the HairStep strand map: red the hair mask, green and blue the unit 2D
  growth direction (root to tip, x right, y up) mapped from [-1, 1] to [0, 1]; black outside
  the mask.

The direction is exact for the pinhole camera the frame was drawn with: the world tangent is
turned into view space and differentiated through the projection at the pixel's own ray
(x = cx + fx X / Z, y = cy - fy Y / Z). These are computed on the host with NumPy from the
arrays ``Renderer.render`` returns (a few milliseconds at 512x512): the host reference of
the device computation ``Renderer.render`` does for every frame with aovs
(kernels/labels.cl, clhair/labels.h), which its tests compare with.
"""

from __future__ import annotations

from typing import Any, Dict, Mapping, Tuple

import numpy as np

__all__ = ["MASK_ALPHA", "image_directions", "orientation", "strand_map", "compute"]

# Hair alpha at and above which a pixel counts as hair (the depth layer's own rule: hair at
# least half opaque holds the pixel).
MASK_ALPHA = 0.5


def image_directions(frame: Mapping[str, Any]) -> Tuple[np.ndarray, np.ndarray]:
    """Per pixel the strand's image direction (H, W, 2) (x right, y up; unit length, 0 where
    no strand) and the sine of the angle between the tangent and the pixel's view ray (H, W):
    1 for a strand across the view, 0 for one pointing at the camera."""
    tangent = np.asarray(frame["tangent"], dtype=np.float32)
    cam = frame["camera"]
    h, w = tangent.shape[:2]
    m = np.asarray(cam["world_to_view"], dtype=np.float32)[:, :3]
    tv = tangent @ m.T  # view-space tangent: x right, y up, z forward
    xs = (np.arange(w, dtype=np.float32) + 0.5 - np.float32(cam["cx"])) / np.float32(cam["fx"])
    ys = -(np.arange(h, dtype=np.float32) + 0.5 - np.float32(cam["cy"])) / np.float32(cam["fy"])
    a = np.broadcast_to(xs[None, :], (h, w))  # X / Z of the pixel's ray
    b = np.broadcast_to(ys[:, None], (h, w))  # Y / Z
    # d(X/Z) = (tX - a tZ) / Z and d(Y/Z) = (tY - b tZ) / Z: the image direction up to 1 / Z
    d = np.stack([tv[..., 0] - a * tv[..., 2], tv[..., 1] - b * tv[..., 2]], axis=-1)
    length = np.linalg.norm(d, axis=-1)
    unit = np.where(length[..., None] > 1e-12, d / np.maximum(length, 1e-12)[..., None], 0.0)
    ray = np.stack([a, b, np.ones_like(a)], axis=-1)
    ray /= np.linalg.norm(ray, axis=-1, keepdims=True)
    tnorm = np.linalg.norm(tv, axis=-1)
    cross = np.linalg.norm(np.cross(tv, ray), axis=-1)
    sine = np.where(tnorm > 1e-12, cross / np.maximum(tnorm, 1e-12), 0.0)
    return unit.astype(np.float32), np.clip(sine, 0.0, 1.0).astype(np.float32)


def orientation(frame: Mapping[str, Any]) -> Tuple[np.ndarray, np.ndarray]:
    """(angle, confidence), each (H, W) float32: the angle in [0, pi) and the confidence
    (the hair alpha times the sine of the tangent to the view ray; 0 where no strand)."""
    unit, sine = image_directions(frame)
    angle = np.mod(np.arctan2(unit[..., 1], unit[..., 0]), np.pi).astype(np.float32)
    angle = np.where(angle >= np.float32(np.pi), np.float32(0.0), angle)
    alpha = np.clip(np.asarray(frame["alpha"], dtype=np.float32), 0.0, 1.0)
    has = np.any(unit != 0.0, axis=-1)
    confidence = np.where(has, alpha * sine, 0.0).astype(np.float32)
    return np.where(has, angle, 0.0).astype(np.float32), confidence


def strand_map(frame: Mapping[str, Any]) -> np.ndarray:
    """The HairStep strand map, (H, W, 3) float32 in [0, 1]."""
    unit, _ = image_directions(frame)
    mask = (np.asarray(frame["alpha"]) >= MASK_ALPHA) & np.any(unit != 0.0, axis=-1)
    out = np.zeros(unit.shape[:2] + (3,), dtype=np.float32)
    out[..., 0] = mask
    out[..., 1:] = np.where(mask[..., None], (unit + 1.0) * 0.5, 0.0)
    return out


def compute(frame: Dict[str, Any]) -> Dict[str, Any]:
    """Adds ``mask`` (H, W) bool, ``orientation``, ``confidence`` and ``strand_map`` to a
    frame dict (rendered with aovs) and returns it. ``Renderer.render`` with aovs already
    returns them, computed on the device (kernels/labels.cl); a frame that has them is
    returned as it is, any other gets them from the NumPy functions above."""
    if all(k in frame for k in ("mask", "orientation", "confidence", "strand_map")):
        return frame
    angle, confidence = orientation(frame)
    frame["mask"] = np.asarray(frame["alpha"]) >= MASK_ALPHA
    frame["orientation"] = angle
    frame["confidence"] = confidence
    frame["strand_map"] = strand_map(frame)
    return frame
