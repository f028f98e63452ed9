"""The viewer's two looks of the world around the robot, ``dark`` (the default, for the
screen) and ``light`` (white background, for papers): background, floor, grid, label
and halo colours, and how deep shadows are.  Data only; colours RGBA floats in 0..1."""
from __future__ import annotations

from dataclasses import dataclass

RGBA = tuple[float, float, float, float]


@dataclass(frozen=True)
class Theme:
    """Colours of one theme.  ``background``: the clear colour; ``floor``/``grid``: the
    floor square (its alpha:
    parts below it show through) and its lines; ``label``/``halo``: text and the rim
    around it; ``shadow_strength``: how much of the floor's light a shadow takes away;
    ``below_floor``: the colour parts under the floor are mixed with (alpha = amount)."""

    name: str
    background: RGBA
    floor: RGBA
    grid: RGBA
    label: RGBA
    halo: RGBA
    shadow_strength: float
    below_floor: RGBA


THEMES: dict[str, Theme] = {
    "dark": Theme(
        name="dark",
        background=(0.16, 0.18, 0.22, 1.0),
        floor=(0.25, 0.27, 0.31, 0.7),
        grid=(0.62, 0.65, 0.70, 0.55),
        label=(1.0, 1.0, 1.0, 1.0),
        halo=(0.0, 0.0, 0.0, 0.85),
        shadow_strength=0.55,
        below_floor=(0.20, 0.22, 0.27, 0.3),
    ),
    "light": Theme(
        name="light",
        background=(0.97, 0.97, 0.98, 1.0),
        floor=(0.93, 0.93, 0.94, 0.75),
        grid=(0.55, 0.57, 0.61, 0.60),
        label=(0.08, 0.08, 0.10, 1.0),
        halo=(1.0, 1.0, 1.0, 0.9),
        shadow_strength=0.40,
        below_floor=(0.85, 0.86, 0.89, 0.3),
    ),
}
DEFAULT_THEME = "dark"


def theme(name: str) -> Theme:
    """The theme called ``name``; ValueError naming the accepted names otherwise."""
    found = THEMES.get(name)
    if found is None:
        raise ValueError(f"theme: expected one of {', '.join(sorted(THEMES))}, got {name!r}")
    return found
