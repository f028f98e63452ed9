"""The compiled model of a robot: one table of per-joint constants with named columns,
built once per robot by one cache, read by every compiled kernel (kinematics, dynamics,
collision, task-space control, planning) and by the NumPy code that shares it.

As in Pinocchio, the model is kept apart from the data the algorithms write into: the
model is read only, each algorithm allocates its own scratch arrays and passes them
explicitly.  :func:`compiled_model` is the one per-robot cache of the package: it holds
the model weakly keyed by the :class:`RobotParams` (the entry goes when the robot's last
user does), and per-robot data derived from it by the layers above (the chain model of
``kinematics``, the recursion model of ``dynamics``, the DH capsules and the self-contact
pairs of ``collision``) is kept in the model (:func:`per_robot`), so it goes with it.  Nothing stored there may hold the robot itself.

Columns of :attr:`CompiledModel.table` (n, :data:`NCOL`), per joint j, SI units, link
quantities in link j's own DH frame (inertia about the frame origin):

* ``REV`` 1.0 revolute / 0.0 prismatic; ``TH``, ``D`` the DH θ [rad] and d [m] offsets;
  ``A`` a [m]; ``CA``, ``SA`` cos α and sin α (values within 1e-12 of 0 or ±1 made exact);
* ``MASS`` [kg], ``HX..HZ`` first moment m·c [kg·m], ``IXX, IYY, IZZ, IXY, IYZ, IXZ``
  [kg·m²] (all 0.0 without inertial data);
* ``REFL`` G²Jm [kg·m²], ``VISC`` G²B [N·m·s/rad], ``CPOS``, ``CNEG`` |G|·Tc± [N·m];
* ``SVX..SWZ`` the joint's motion subspace [v of the frame origin; ω] per unit rate, frame j;
* ``MOD`` 1.0 in every row for modified DH (Craig); ``QLO``, ``QHI`` the limits [rad or m].

Imports numpy and ``model`` only (no numba: a kinematics-only program never compiles).
"""
from __future__ import annotations

import math
import weakref
from dataclasses import dataclass, field
from typing import Callable, TypeVar

import numpy as np
from numpy.typing import NDArray

from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams

FloatArray = NDArray[np.float64]
T = TypeVar("T")

# Columns of the table.
REV, TH, D, A, CA, SA, MASS, HX, HY, HZ = range(10)
IXX, IYY, IZZ, IXY, IYZ, IXZ, REFL, VISC, CPOS, CNEG = range(10, 20)
SVX, SVY, SVZ, SWX, SWY, SWZ = range(20, 26)
MOD = 26
QLO, QHI = 27, 28
NCOL = 29
#: Columns ``REV`` .. ``SA``: the chain's geometry (all that frames depend on besides base and tool).
GEOMETRY = SA + 1
#: cos and sin of constant angles closer than this to 0 or ±1 are made exact.
SNAP = 1e-12


def snap(x: float) -> float:
    """x, or exactly 0.0, 1.0 or −1.0 when within :data:`SNAP` of one of them."""
    for exact in (0.0, 1.0, -1.0):
        if abs(x - exact) < SNAP:
            return exact
    return float(x)


@dataclass(frozen=True, eq=False)
class CompiledModel:
    """A robot's constants for the kernels (module docstring): ``table`` (n, NCOL),
    ``modified`` its DH convention, ``base`` frame 0 in the world and ``tool`` the tool
    frame in frame n (4, 4).  Nothing writes into its arrays."""

    n: int
    table: FloatArray
    modified: bool
    base: FloatArray
    tool: FloatArray
    _derived: dict = field(default_factory=dict, repr=False)  # per_robot's store


_MODELS: "weakref.WeakKeyDictionary[RobotParams, CompiledModel]" = weakref.WeakKeyDictionary()


#: The robot asked for last (a weak reference) and its model: one call after another for
#: the same robot skips the weak dictionary's lookup (a new weak reference each time).
_last: tuple[Callable[[], RobotParams | None], CompiledModel | None] = (lambda: None, None)


def compiled_model(robot: RobotParams) -> CompiledModel:
    """The compiled model of ``robot`` (built on first use, then shared)."""
    global _last
    ref, model = _last
    if ref() is robot:
        return model
    model = _MODELS.get(robot)
    if model is None:
        model = _MODELS[robot] = _build(robot)
    _last = (weakref.ref(robot), model)
    return model


def per_robot(robot: RobotParams, key: str, build: Callable[[RobotParams], T]) -> T:
    """Per-robot data of a layer, ``build(robot)`` once, kept with the robot's compiled
    model (``build``'s result must not hold the robot)."""
    ref, model = _last  # (compiled_model written out: this is on every dynamics call's path)
    if ref() is not robot:
        model = compiled_model(robot)
    found = model._derived.get(key)
    if found is None:
        found = model._derived[key] = build(robot)
    return found


def _contiguous(a: FloatArray) -> FloatArray:
    # not flagged read only: numba types read-only arrays apart, and the kernels' explicit
    # signatures take writeable ones
    return np.ascontiguousarray(a, dtype=float)


def _subspace(table: FloatArray, modified: bool, j: int) -> tuple[float, ...]:
    """Joint j's motion [v of origin j; ω] per unit rate, in frame j."""
    rev = table[j, REV] != 0.0
    if modified:
        return (0.0, 0.0, 0.0, 0.0, 0.0, 1.0) if rev else (0.0, 0.0, 1.0, 0.0, 0.0, 0.0)
    sa, ca = table[j, SA], table[j, CA]
    if rev:  # v = axis × (o_j − o_{j−1})
        d = table[j, D]
        return sa * (ca * d) - ca * (sa * d), ca * table[j, A], -(sa * table[j, A]), 0.0, sa, ca
    return 0.0, sa, ca, 0.0, 0.0, 0.0


def _build(robot: RobotParams) -> CompiledModel:
    # Built for kinematics and collision too: a robot of absurd size (inf inertia terms)
    # warns nowhere here; dynamics, which reads those columns, says what is wrong.
    with np.errstate(over="ignore", invalid="ignore"):
        return _table_model(robot)


def _table_model(robot: RobotParams) -> CompiledModel:
    n = robot.n_dofs
    P = np.zeros((n, NCOL))
    P[:, REV] = (robot.jtype == JTYPE_REVOLUTE).astype(float)
    P[:, TH], P[:, D], P[:, A] = robot.dh_th, robot.dh_d, robot.dh_a
    P[:, CA] = [snap(math.cos(al)) for al in robot.dh_alpha]
    P[:, SA] = [snap(math.sin(al)) for al in robot.dh_alpha]
    li = robot.inertials
    if li is not None:
        for j, (m, com, ic) in enumerate(zip(li.mass, li.com, li.inertia)):
            P[j, MASS] = float(m)
            P[j, HX : HZ + 1] = [float(m) * float(c) for c in com]
            io = ic + m * (com @ com * np.eye(3) - np.outer(com, com))  # about the frame origin
            P[j, IXX : IXZ + 1] = [float(io[r, c]) for r, c in ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))]
    dr = robot.drives
    if dr is not None:
        P[:, REFL] = dr.reflected_inertia
        P[:, VISC] = dr.gear_ratio**2 * dr.viscous
        P[:, CPOS] = np.abs(dr.gear_ratio) * dr.coulomb[:, 0]
        P[:, CNEG] = np.abs(dr.gear_ratio) * dr.coulomb[:, 1]
    modified = bool(robot.is_modified)
    for j in range(n):
        P[j, SVX : SWZ + 1] = _subspace(P, modified, j)
    P[:, MOD] = 1.0 if modified else 0.0
    P[:, QLO], P[:, QHI] = robot.q_min, robot.q_max
    return CompiledModel(
        n=n, table=_contiguous(P), modified=modified, base=_contiguous(robot.base_tf.mat),
        tool=_contiguous(robot.tool_tf.mat),
    )


def kernel_array(a: NDArray) -> FloatArray:
    """``a`` in the one layout every kernel is compiled for: float64, C-contiguous and
    writeable (numba compiles a kernel again for a read-only array such as a robot's
    ``q_home``, or a strided one); ``a`` itself when it is so already (a cheaper test
    than ``np.require``'s, which costs a microsecond a call)."""
    if a.flags.carray and a.dtype == np.float64:  # C-contiguous, aligned and writeable
        return a
    return np.array(a, dtype=np.float64, order="C")
