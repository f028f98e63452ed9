"""The one compiled step of the physics loop: a fixed step of one arm by classical RK4 or
semi-implicit Euler with its effort held, joints resting on their stops held inside it,
and, with a contact tuple (:mod:`.contact_kernels`), the contact torque of the active
pairs at every stage.  :func:`step_batch` and :func:`ct_step_batch` take it for N arms,
:func:`contact_step` for one arm in contact, :func:`run_steps` for many steps of one arm
under a sampled law (contact and resting stops inside).

The dynamics are :mod:`robot_sim.dynamics.compiled`'s (the model table ``P`` (n, NCOL),
gravity ``g0`` (3,) [m/s²] in frame 0); the RK4 stages and combine are
:mod:`robot_sim.kernels.algebra`'s.  Statuses are :mod:`robot_sim.kernels.status`'s.
Units: q in rad (revolute) and m (prismatic), rates per second, efforts in N·m and N,
time in s.
"""
from __future__ import annotations

import math

import numpy as np

from robot_sim.dynamics.compiled import all_finite, ct_one, fd_one, geometry, rnea_one
from robot_sim.kernels.algebra import euler_combine, rk4_combine, rk4_stage
from robot_sim.kernels.jit import INLINE, JIT, UNCOUNTED, njit
from robot_sim.kernels.model import MOD, QHI, QLO
from robot_sim.kernels.status import AT_STOP, BAD_ACCEL, BAD_EFFORT, BAD_STATE, CROSSED, OK, ON_LIMIT
from robot_sim.kernels.chain import frames_cs
from robot_sim.sim.contact_kernels import (O_D, contact_begin, contact_stage, contact_work, margin, moved,
                                           near_slack)


@njit(**INLINE)
def squares_finite(x):
    """True if the sum of squares of the vector x is finite (as the physics loop's check:
    a vector whose squares overflow is as diverged as one holding inf)."""
    squares = 0.0
    for v in x:
        squares += v * v
    return math.isfinite(squares)


@njit(**INLINE)
def clip_effort(command, limit, effort):
    """``effort`` = ``command`` clipped to ±``limit`` (NumPy's clip for finite values);
    True if some joint was clipped."""
    saturated = False
    for j in range(command.shape[0]):
        x = command[j]
        if abs(x) > limit[j]:
            saturated = True
        effort[j] = min(max(x, -limit[j]), limit[j])
    return saturated


@njit(**INLINE)
def step_work(n):
    """The work arrays of :func:`step_one` for n joints."""
    return (np.empty((n, 3)), np.empty((n, 2)), np.empty((n, 3)), np.empty((n, 3)), np.zeros(n), np.empty(n),
            np.empty((n, n)), np.zeros(6), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n),
            np.empty(n), np.empty(n), np.empty(n), np.empty(n))


@njit(**UNCOUNTED)
def _accel(P, modified, q, v, tau, g0, held, any_held, acc, react, O, CS, F, NM, zero, bias, M, fext, total, extra,
           world0, axis_frame, revolute, mu, out, Fc, staged):
    """q̈ at (q, v) into ``acc`` under the effort tau plus the contact torque ``extra`` at
    (q, v) of the contact points of the step: given when ``staged`` (the step's start,
    from ``contact_begin``), else computed into it (``contact_stage``: the step's contact
    frames, gains and anchors in ``out``; ``world0``, ``axis_frame``, ``revolute``,
    ``mu`` of the contact tuple; Fc room for the link frames, posed from the dynamics'
    cosines and sines of the joint angles, which ``fd_one`` then takes); the ``held``
    joints locked when ``any_held`` (their reaction into ``react``); the rest:
    :func:`step_work`'s arrays.  Compiled on its own, not inlined into the step: the
    step's machine code stays as small and as fast as without contact.  Only the arrays
    used are passed, and their references are not counted (``UNCOUNTED``): a call's
    arguments cost time."""
    if not staged:
        geometry(P, modified, q, O, CS)
        frames_cs(P, modified, world0, q, CS, Fc)
        contact_stage(Fc, v, axis_frame, revolute, mu, out, extra)
    for j in range(tau.shape[0]):
        total[j] = tau[j] + extra[j]
    fd_one(P, modified, q, v, total, g0, fext, False, held, any_held, acc, react, zero, bias, M, O, CS, F, NM, not staged)


@njit(**INLINE)
def step_one(P, modified, rk4, h, q, v, tau, a_start, use_start, g0, held, use_held, stops, q1, qd1, qdd1, reaction, at,
             work, contact, cwork):
    """One step of :func:`step_batch` for one configuration (its rules there); the status.
    ``use_start``: ``a_start`` is the start acceleration, if finite and nothing is held or
    on a stop; ``held`` (n,) the joints named held when ``use_held`` (overwritten with
    ``stops``); ``work``: :func:`step_work`.  ``contact``: None, or a contact tuple whose
    active pairs' torque enters every stage (``cwork`` its ``contact_work``)."""
    O, CS, F, NM, zero, bias, M, fext, a1, a2, a3, a4, qs, vs, react = work[:15]
    n = P.shape[0]
    any_held, on_stop = False, False
    if stops:
        for j in range(n):
            on_lo, on_hi = q[j] == P[j, QLO], q[j] == P[j, QHI]
            held[j] = False
            if on_lo or on_hi:
                on_stop = True
                if (on_lo and on_hi) or (v[j] < 0.0 if on_lo else v[j] > 0.0):
                    return AT_STOP
                if v[j] == 0.0:
                    held[j] = any_held = True
    elif use_held:
        for j in range(n):
            any_held = any_held or held[j]
    known = use_start and not (any_held or on_stop) and all_finite(a_start)
    for stage in range(4 if rk4 else 1):  # the start, then stages 2, 3, 4 of RK4
        out = a1 if stage == 0 else (a2 if stage == 1 else (a3 if stage == 2 else a4))
        if stage > 0:
            prev = a1 if stage == 1 else (a2 if stage == 2 else a3)
            rk4_stage(h if stage == 3 else 0.5 * h, q, v, prev, v if stage == 1 else vs, qs, vs)
            if not (all_finite(qs) and all_finite(vs)):
                return BAD_STATE
        if stage == 0 and known:
            a1[:] = a_start
        else:
            at_q, at_v = (q, v) if stage == 0 else (qs, vs)
            if contact is None:
                fd_one(P, modified, at_q, at_v, tau, g0, fext, False, held, any_held, out, react, zero, bias, M, O, CS, F,
                       NM, False)
            else:
                _accel(P, modified, at_q, at_v, tau, g0, held, any_held, out, react, O, CS, F, NM, zero, bias, M, fext,
                       work[15], work[16], contact[0], contact[9], contact[10], contact[15], contact[19], cwork[0],
                       False)
            if not all_finite(out):
                return BAD_ACCEL
        if stage == 0:
            if any_held:
                for j in range(n):
                    if stops and held[j] and (react[j] < 0.0 if q[j] == P[j, QLO] else react[j] > 0.0):
                        return AT_STOP  # this stop would pull: the joint may leave
                    reaction[j] = react[j] if held[j] else 0.0
            elif stops or use_held:
                reaction[:] = 0.0
            qdd1[:] = a1
    if rk4:
        rk4_combine(h, q, v, a1, a2, a3, a4, q1, qd1)
    else:
        euler_combine(h, q, v, a1, q1, qd1)
    status = OK
    if stops:
        for j in range(n):
            x, lo, hi = q1[j], P[j, QLO], P[j, QHI]
            at[j] = x == lo or x == hi
            if x < lo or x > hi:
                status = AT_STOP if any_held else CROSSED
            elif at[j] and status == OK:
                status = ON_LIMIT
    return status


@njit(**JIT)
def step_batch(P, rk4, h, Q, QD, TAU, A1, known, g0, active, HELD, use_held, stops, Q1, QD1, QDD1, REACT, AT, STATUS):
    """One step of length h [s] per configuration i with ``active[i]``, effort TAU[i] held:
    classical RK4 (``rk4``) or semi-implicit Euler.  ``known[i]``: A1[i] is the
    acceleration at the start (used when finite and no joint is held or on a stop).
    Writes the new state into Q1, QD1, the start acceleration into QDD1 and a status
    (:data:`OK` … :data:`AT_STOP`) into STATUS.

    Held joints (q̈ = 0 in every stage, see ``fd_one``): with ``use_held``, those of
    HELD[i]; with ``stops`` (the joint limits of P), those resting on a stop: exactly on
    it at zero velocity, kept there only if every reaction pushes (λ_j ≥ 0 on a min stop,
    ≤ 0 on a max stop), else :data:`AT_STOP`.  A start with a joint on a stop moving into
    it, or on a one-point range, is :data:`AT_STOP` too.  Where a joint is held, REACT[i]
    is the stops' reaction at the start (0.0 elsewhere); with ``stops``, AT[i] flags the
    joints exactly on a limit at the end, and an end beyond a limit is :data:`CROSSED`
    (from a start holding no joint; else :data:`AT_STOP`)."""
    modified = P[0, MOD] != 0.0
    n = P.shape[0]
    work = step_work(n)
    held = np.zeros(n, dtype=np.bool_)
    for i in range(Q.shape[0]):
        if not active[i]:
            continue
        if use_held:
            held[:] = HELD[i]
        STATUS[i] = step_one(P, modified, rk4, h, Q[i], QD[i], TAU[i], A1[i], known[i], g0, held, use_held, stops,
                             Q1[i], QD1[i], QDD1[i], REACT[i], AT[i], work, None, None)


@njit(**JIT)
def ct_step_batch(P, rk4, h, Q, QD, QDES, QDDES, QDDDES, KP, KD, ELIM, g0, active, stops, CMD, TAU, Q1, QD1, QDD1, REACT,
                  AT, STATUS):
    """Computed torque and one step, fused: per configuration i with ``active[i]``, the
    command CMD[i] = ID(q, q̇, q̈_ref) of ``ct_one`` (gains KP[i], KD[i]), the effort
    TAU[i] = CMD[i] clipped to ±ELIM (n,), and the step of :func:`step_batch` with that
    effort held, starting from q̈_ref when nothing saturated.  The same operations as
    ``ct_batch``, NumPy's clip and :func:`step_batch` one after the other, so the same
    bits.  A command whose sum of squares is not finite is :data:`BAD_EFFORT` (not
    stepped)."""
    modified = P[0, MOD] != 0.0
    n = P.shape[0]
    work = step_work(n)
    O, CS, F, NM = work[0], work[1], work[2], work[3]
    held = np.zeros(n, dtype=np.bool_)
    qdd_ref = np.empty(n)
    for i in range(Q.shape[0]):
        if not active[i]:
            continue
        cmd, tau = CMD[i], TAU[i]
        ct_one(P, modified, Q[i], QD[i], QDES[i], QDDES[i], QDDDES[i], KP[i], KD[i], g0, cmd, qdd_ref, O, CS, F, NM)
        if not squares_finite(cmd):
            STATUS[i] = BAD_EFFORT
            continue
        saturated = clip_effort(cmd, ELIM, tau)
        STATUS[i] = step_one(P, modified, rk4, h, Q[i], QD[i], tau, qdd_ref, not saturated, g0, held, False, stops,
                             Q1[i], QD1[i], QDD1[i], REACT[i], AT[i], work, None, None)


@njit(**JIT)
def contact_step(P, rk4, h, q, qd, tau, a_start, use_start, g0, contact, q1, qd1, qdd1):
    """One step of length h [s] of an arm in contact from (q, q̇) (n,) with the effort tau
    held: :func:`step_one` with the contact torque of the contact tuple's active pairs at
    every stage (their gains and anchors held), no joint held.  ``a_start`` is the start's
    acceleration when ``use_start`` and finite.  (q, q̇) after the step into q1, qd1, the
    start's acceleration into qdd1; returns the status (OK, BAD_STATE, BAD_ACCEL)."""
    n = P.shape[0]
    held, reaction, at = np.zeros(n, dtype=np.bool_), np.empty(n), np.zeros(n, dtype=np.bool_)
    return step_one(P, P[0, MOD] != 0.0, rk4, h, q, qd, tau, a_start, use_start, g0, held, False, False, q1, qd1, qdd1,
                    reaction, at, step_work(n), contact, contact_work(P, contact))


#: Round-off guard [m] of :func:`run_steps`' skipped near check: a pair whose distance
#: bound is within this of the margin is checked anew.
SLACK_TOL = 1e-9

#: Control laws of :func:`run_steps`: no effort, PD, PD plus gravity, computed torque.
LAW_PASSIVE, LAW_PD, LAW_PDG, LAW_CT = 0, 1, 2, 3


@njit(**INLINE)
def _command(P, modified, law, kp, kd, q_des, qd_des, qdd_des, g0, q, qd, c, a_ref, g, zero, work):
    """The sampled law's command at (q, q̇) into c (computed torque: its q̈_ref into a_ref)."""
    O, CS, F, NM = work[0], work[1], work[2], work[3]
    n = P.shape[0]
    if law == LAW_CT:
        ct_one(P, modified, q, qd, q_des, qd_des, qdd_des, kp[0], kd[0], g0, c, a_ref, O, CS, F, NM)
    elif law == LAW_PASSIVE:
        c[:] = 0.0
    else:
        for j in range(n):
            c[j] = kp[j] * (q_des[j] - q[j]) + kd[j] * (qd_des[j] - qd[j])
        if law == LAW_PDG:
            geometry(P, modified, q, O, CS)
            rnea_one(P, modified, zero, zero, g0, O[0], False, g, O, CS, F, NM)
            for j in range(n):
                c[j] += g[j]


@njit(**INLINE)
def _take_back(contact, cwork, kept, kept_anchored, refixed):
    """The contact state before a step's ``contact_begin`` (which ``refixed`` the frames or
    held them), for a caller that takes that step its own way."""
    if contact[15] > 0.0:
        contact[16][:] = kept
        contact[17][:] = kept_anchored
    if refixed:
        contact[19][:] = cwork[4]
        contact[18][:] = cwork[5]


@njit(**JIT)
def run_steps(P, rk4, h, n_steps, law, kp, kd, q_des, qd_des, qdd_des, elim, vlim, g0, stops, q, qd, qdd, cmd, tau,
              sat, vsat, any_at, at_limit, limit_torque, recorded, contact):
    """Up to ``n_steps`` steps of one arm under a sampled joint law with the desired values
    q_des, qd_des, qdd_des (n,) fixed: per step the command ``cmd`` (LAW_PASSIVE: 0;
    LAW_PD: kp (q_des − q) + kd (q̇_des − q̇), kp and kd (n,); LAW_PDG: that plus g(q);
    LAW_CT: ``ct_one`` with the gains kp[0], kd[0]), the effort ``tau`` the command
    clipped to ±elim (``sat`` flags the joints clipped), the step of :func:`step_one`
    (from q̈_ref for computed torque where nothing saturated), and q̇ clipped to ±vlim
    (``vsat`` flags the joints braked).  The operations of the physics loop's step in
    turn, so the same bits.  q, qd (n,) are advanced in place; qdd, cmd, tau, sat, vsat
    hold the last step's.

    With ``stops``, joints resting on their stops are held inside the step as the loop's
    stepper holds them: ``any_at`` says whether some joint is on a limit before the first
    step; a step that held joints or ended exactly on a limit is recorded as the loop
    records it, into ``at_limit`` (n,) bool, the joints on a limit, and ``limit_torque``
    (n,), the stops' reaction [N·m or N], and ``recorded[0]`` is set True.

    ``contact``: None, or a contact tuple (:mod:`.contact_kernels`; its ``arms`` valid at
    every q) with the active pairs of the step before: at each step's start the pairs
    within :func:`.contact_kernels.margin` must be those, their contact frames are fixed
    and the friction anchors of the touching ones moved (``contact_begin``), and the step
    takes their contact torque at every stage (``contact_stage``); with no active pair it
    is the free step.  The pairs near are found by :func:`.contact_kernels.near_slack` (the broad phase of bounding
    spheres, then the narrow phase), which also bounds the distance of all others from
    below; until the arm has moved (:func:`.contact_kernels.moved`) so far from where that
    was checked that one of them may have come within the margin (less
    :data:`SLACK_TOL`), the check is not repeated: only the active pairs' own distances
    (from the start's ``contact_begin``) are compared with the margin.  The same pairs
    either way.

    Returns the number of steps taken: it stops before a step that the caller takes its
    own way: its command or end state is not finite, a stop is met that is not resting
    (an arrival beyond a limit, an impact, a release), the pairs near contact change, or
    an arm in contact starts on a stop or ends beyond one (then the anchors are as they
    were before that step)."""
    modified = P[0, MOD] != 0.0
    n = P.shape[0]
    work = step_work(n)
    held = np.zeros(n, dtype=np.bool_)
    zero = np.zeros(n)
    a_ref, g, c, t, a_start = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    q1, qd1, qdd1, react, at = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.zeros(n, dtype=np.bool_)
    if contact is not None:
        cwork = contact_work(P, contact)
        arms, rows, mu, anchors, anchored = contact[12], contact[13], contact[15], contact[16], contact[17]
        touching = rows.shape[0] > 0
        kept, kept_anchored = anchors.copy(), anchored.copy()
        checked_at, slack = q.copy(), -math.inf  # where near_slack last ran, its bound
    for k in range(n_steps):
        _command(P, modified, law, kp, kd, q_des, qd_des, qdd_des, g0, q, qd, c, a_ref, g, zero, work)
        if not squares_finite(c):
            return k
        saturated = clip_effort(c, elim, t)
        in_contact = False
        if contact is not None:
            threshold = margin(arms, qd, h)
            posed = not slack - moved(arms, q, checked_at) > threshold + SLACK_TOL
            if posed:  # some other pair may have come near: check them all
                slack = near_slack(q, P, modified, contact, threshold, cwork)
                checked_at[:] = q
                if slack == -math.inf:
                    return k
            if touching:
                if any_at:
                    return k
                in_contact = True
                if mu > 0.0:
                    kept[:] = anchors
                    kept_anchored[:] = anchored
                # the contact frames of the step fixed and the anchors moved (near_slack's pose is at q),
                # the contact torque at the start into cwork[6]
                refixed = contact_begin(q, qd, P, modified, contact, True, posed, threshold, cwork)
                if not posed:  # the active pairs still within the margin (their distances at q just computed)
                    for p in range(rows.shape[0]):
                        if not contact[19][p, 0, O_D] < threshold:
                            _take_back(contact, cwork, kept, kept_anchored, refixed)
                            return k
                _accel(P, modified, q, qd, t, g0, held, False, a_start, react, work[0], work[1], work[2], work[3],
                       work[4], work[5], work[6], work[7], work[15], cwork[6], contact[0], contact[9], contact[10], mu,
                       contact[19], cwork[0], True)
                status = step_one(P, modified, rk4, h, q, qd, t, a_start, True, g0, held, False, False, q1, qd1, qdd1,
                                  react, at, work, contact, cwork)
                ok = status == OK
                if ok and stops:  # an end beyond a stop is the stop resolver's
                    for j in range(n):
                        ok = ok and not (q1[j] < P[j, QLO] or q1[j] > P[j, QHI])
        if not in_contact:
            status = step_one(P, modified, rk4, h, q, qd, t, a_ref, law == LAW_CT and not saturated, g0, held, False,
                              stops, q1, qd1, qdd1, react, at, work, None, None)
            ok = status == OK or status == ON_LIMIT
        if ok:
            for j in range(n):
                v = qd1[j]
                vsat[j] = abs(v) > vlim[j]
                qd1[j] = min(max(v, -vlim[j]), vlim[j])
            ok = squares_finite(q1) and squares_finite(qd1)
        if not ok:
            if contact is not None and in_contact:  # the caller takes this step from the contact state before it
                _take_back(contact, cwork, kept, kept_anchored, refixed)
            return k
        for j in range(n):
            q[j], qd[j], qdd[j], cmd[j], tau[j], sat[j] = q1[j], qd1[j], qdd1[j], c[j], t[j], abs(c[j]) > elim[j]
        if stops and not in_contact and (any_at or status == ON_LIMIT):
            for j in range(n):
                limit_torque[j] = react[j] if any_at else 0.0
                at_limit[j] = at[j]
            recorded[0] = True
            any_at = False
            for j in range(n):
                any_at = any_at or at[j]
    return n_steps
