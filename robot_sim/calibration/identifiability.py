"""What a set of measurements can identify: dependent parameters, condition number and
Borm and Menq's observability index O1.

Columns of the parameter Jacobian are taken in an order of preference (base, tool
position, the joints from the base out, tool orientation) and kept when they add a new
direction: a column that is (numerically) zero is not seen by the data; one that lies in
the span of the kept columns moves the measurements exactly as a combination of them, and
no data from this robot can separate them (``d1`` with ``base.z``).  Those are held at
their nominal values.  The test is on the measured poses' Jacobian at the nominal
parameters, relative to each column's size, so it does not depend on units.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: A column whose size is below this fraction of the largest is not seen by the data.
ZERO_COLUMN = 1e-9
#: A column is dependent when what the kept columns cannot explain is below this fraction.
DEPENDENT = 1e-7
#: Coefficients below this fraction of the largest are left out of a reported combination.
NEGLIGIBLE = 1e-6


@dataclass(frozen=True)
class Unidentifiable:
    """A parameter the data cannot identify: ``name``, the parameters it moves with
    (``partners``, empty when the data do not see it at all) and the ``reason`` in words."""

    name: str
    partners: tuple[str, ...]
    reason: str


def preference(names: tuple[str, ...]) -> list[int]:
    """Indices of ``names`` in the order columns are kept: base, tool position, the joints'
    parameters in chain order, then the tool's orientation."""
    def rank(k: int) -> int:
        name = names[k]
        if name.startswith("base."):
            return 0
        if name.startswith("tool.") and name[5:] in ("x", "y", "z"):
            return 1
        return 3 if name.startswith("tool.") else 2

    return sorted(range(len(names)), key=lambda k: (rank(k), k))


def dependencies(J: FloatArray, names: tuple[str, ...], rotations_seen: bool
                 ) -> tuple[list[int], list[Unidentifiable]]:
    """The columns of J (m, P) that the data identify (indices, in column order) and the
    others, each with the kept columns it is a combination of.  ``names`` label the
    columns; ``rotations_seen`` is False for position-only data (said in the reasons)."""
    norms = np.linalg.norm(J, axis=0)
    biggest = norms.max() if norms.size else 0.0
    basis = np.zeros((J.shape[0], 0))
    kept: list[int] = []
    lost: list[Unidentifiable] = []
    for k in preference(names):
        column = J[:, k]
        if norms[k] <= ZERO_COLUMN * biggest:
            why = "does not move the measured points"
            if names[k].startswith("tool.r") and not rotations_seen:
                why += " (positions only: the tool's orientation is not seen)"
            elif names[k].startswith("tool.r") or names[k].startswith("alpha"):
                why += " (it turns them about an axis through them)"
            lost.append(Unidentifiable(names[k], (), why))
            continue
        rest = column - basis @ (basis.T @ column)
        rest -= basis @ (basis.T @ rest)  # second pass: Gram-Schmidt twice is enough
        if np.linalg.norm(rest) > DEPENDENT * norms[k]:
            basis = np.column_stack([basis, rest / np.linalg.norm(rest)])
            kept.append(k)
            continue
        coef = np.linalg.lstsq(J[:, kept], column, rcond=None)[0] * norms[kept] / norms[k]
        big = np.abs(coef) > NEGLIGIBLE * np.abs(coef).max()
        partners = tuple(names[kept[i]] for i in np.flatnonzero(big))
        what = partners[0] + " does" if len(partners) == 1 else "a combination of " + ", ".join(partners)
        lost.append(Unidentifiable(names[k], partners, f"moves the measurements exactly as {what}"))
    return sorted(kept), lost


def condition_number(J: FloatArray) -> float:
    """Condition number of J with each column scaled to unit length (what the fit solves)."""
    norms = np.linalg.norm(J, axis=0)
    s = np.linalg.svd(J / np.where(norms > 0, norms, 1.0), compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else float("inf")


def observability(J: FloatArray) -> float:
    """Borm and Menq's O1 = (σ_1 ⋯ σ_P)^(1/P) / √m of J (m, P), the geometric mean of its
    singular values per measured value (Borm & Menq, Int. J. Robotics Research 10(1), 1991).
    Callers scale angle columns by a length so O1 has the unit of a length per length."""
    s = np.linalg.svd(J, compute_uv=False)
    if s.size == 0 or s[-1] <= 0:
        return 0.0
    return float(np.exp(np.log(s).mean()) / np.sqrt(J.shape[0]))
