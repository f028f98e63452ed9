"""The picture of ``robot-sim calibrate --report``: position error per pose before and after
calibration (log scale) and a histogram of the errors after, drawn with NumPy into an RGB
array and written by the offscreen PNG writer, labels in the project's label font."""
from __future__ import annotations

import os

import numpy as np
from numpy.typing import NDArray

from robot_sim.calibration.calibrate import CalibrationResult
from robot_sim.graphics.font import atlas
from robot_sim.graphics.offscreen import save_png

WIDTH, HEIGHT = 1000, 420
MARGIN, GAP = 60, 50
BEFORE, AFTER, HELD, INK, GRID = (200, 120, 90), (40, 110, 200), (240, 170, 40), (30, 30, 30), (225, 225, 225)
FONT_PX = 15


def _text(img: NDArray[np.uint8], text: str, x: int, y: int, color: tuple[int, int, int] = INK) -> None:
    """Write ``text`` with its line box's top-left corner at pixel (x, y)."""
    font = atlas(FONT_PX)
    pen, baseline = float(x), int(y + font.ascender)
    pad = font.halo + 1
    for char in text:
        g = font.glyph(char)
        cover = font.image[g.y + pad:g.y + g.height - pad, g.x + pad:g.x + g.width - pad, 0] / 255.0
        top, left = baseline + g.top + pad, int(round(pen)) + g.left + pad
        h, w = cover.shape
        h, w = min(h, img.shape[0] - top), min(w, img.shape[1] - left)
        if h > 0 and w > 0 and top >= 0 and left >= 0:
            area = img[top:top + h, left:left + w].astype(float)
            c = cover[:h, :w, None]
            img[top:top + h, left:left + w] = (area * (1 - c) + np.array(color) * c).astype(np.uint8)
        pen += g.advance


def report_image(res: CalibrationResult) -> NDArray[np.uint8]:
    """The report (HEIGHT, WIDTH, 3): left, the error of each pose [µm, log scale] before
    (red-brown) and after (blue), held-out poses' predictions (amber); right, a histogram of
    the errors after calibration."""
    img = np.full((HEIGHT, WIDTH, 3), 255, dtype=np.uint8)
    top, bottom = MARGIN, HEIGHT - MARGIN
    split = int(WIDTH * 0.6)
    before, after = res.before.position * 1e6, res.after.position * 1e6
    lo = np.floor(np.log10(max(min(after.min(), res.holdout.position.min() * 1e6), 1e-3)))
    hi = np.ceil(np.log10(max(before.max(), 1e-3)))
    hi = max(hi, lo + 1)

    def y_of(value: NDArray[np.float64]) -> NDArray[np.int64]:
        frac = (np.log10(np.maximum(value, 10**lo)) - lo) / (hi - lo)
        return (bottom - frac * (bottom - top)).astype(int)

    for decade in range(int(lo), int(hi) + 1):
        y = int(y_of(np.array([10.0**decade]))[0])
        img[y, MARGIN:split - GAP // 2] = GRID
        _text(img, f"{10.0**decade:g}", 6, y - FONT_PX // 2)
    n = len(before)
    step = (split - GAP // 2 - MARGIN) / max(n, 1)
    width = max(int(step * 0.4), 1)
    held = set(res.holdout.poses.tolist())
    predicted = dict(zip(res.holdout.poses.tolist(), res.holdout.position * 1e6))
    for i in range(n):
        x = int(MARGIN + i * step)
        for offset, value, color in ((0, before[i], BEFORE), (width, after[i], AFTER)):
            img[int(y_of(np.array([value]))[0]):bottom, x + offset:x + offset + width] = color
        if i in held:
            y = int(y_of(np.array([predicted[i]]))[0])
            img[max(y - 1, 0):y + 2, x:x + 2 * width] = HELD
    img[bottom, MARGIN:split - GAP // 2] = INK
    _text(img, "position error per pose [µm]: before, after, held-out prediction", MARGIN, 12)
    _text(img, "before", MARGIN, HEIGHT - 40, BEFORE)
    _text(img, "after", MARGIN + 70, HEIGHT - 40, AFTER)
    _text(img, "held out (fitted without it)", MARGIN + 130, HEIGHT - 40, HELD)
    # histogram of the errors after
    left, right = split + GAP // 2, WIDTH - 20
    edges = np.linspace(0.0, max(after.max(), 1e-9) * 1.0001, 13)
    counts, _ = np.histogram(after, edges)
    peak = max(counts.max(), 1)
    bin_w = (right - left) / len(counts)
    for k, count in enumerate(counts):
        x0, x1 = int(left + k * bin_w) + 1, int(left + (k + 1) * bin_w) - 1
        img[int(bottom - count / peak * (bottom - top)):bottom, x0:x1] = AFTER
    img[bottom, left:right] = INK
    _text(img, f"errors after [µm]: poses per bin (tallest {peak})", left, 12)
    _text(img, "0", left, bottom + 4)
    _text(img, f"{edges[-1]:.3g}", right - 40, bottom + 4)
    _text(img, f"RMS {res.rms_before * 1e3:.3g} mm → {res.rms_after * 1e6:.3g} µm "
               f"(held out {res.holdout.rms * 1e6:.3g} µm)", MARGIN, HEIGHT - 22)
    return img


def write_report(res: CalibrationResult, path: str | os.PathLike[str], command: str) -> None:
    """Write :func:`report_image` to ``path`` as a PNG recording ``command`` (text chunk
    ``Source``, as ``--screenshot`` does)."""
    save_png(path, report_image(res), {"Software": "robot-sim", "Source": command})
