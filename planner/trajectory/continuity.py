"""Whether the joint accelerations q̈ [rad/s²] of a sampled plan are continuous, measured on
the samples (planner/path/at_height.py holds the default to it: no degraded fallback).

Within a step every profile is smooth (the quintic of eq 5.16 or the thesis's cosine blend
of eq 5.13-5.15 through the closed-form joint map of eq 3.10-3.36), so q̈ can jump only where
one step hands over to the next. At such a boundary sample i the right value q̈_i is exact
(the later step at τ = 0, planner/trajectory/sampling.py) and the left limit is extrapolated
from the two samples before it, L = 2 q̈_{i-1} - q̈_{i-2}; for a q̈ whose third derivative
(snap) is bounded by s on the step before, |q̈_i - L| <= s Δt² up to higher orders, with Δt
the sample interval. The same second difference q̈_j - 2 q̈_{j-1} + q̈_{j-2} taken inside the
steps measures s Δt² on the plan's own samples, so a boundary whose mismatch exceeds
JUMP_FACTOR times the largest interior one near it (of that joint) is a jump of q̈, not the
curvature of a continuous q̈. A cosine blend stops with q̈ at its peak, π² A / (2 T²), and a
quintic with q̈ = 0: the plain creeping and spinning gait (cosine blends) jumps by ~N² / π²
times the interior second difference with N samples per step, the gaits with quintic
profiles stay near 1. Measured (the factor JUMP_FACTOR would need to pass the plan; 3
waypoints, SILO4 h 0.4, solo12 0.22, mantis 0.3, anymal 0.5 m; every boundary judged): gait
auto (creep or crawl) 1.07-1.21 at 100 samples per unit, 1.46-2.02 at 20, 2.99-3.81 at 10
(hence MIN_STEP_SAMPLES); cosine blends (facing the path before it took the quintic too)
2.2e4-3.0e5 at 100, 426-1590 at 20, 51-76 at 10.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from planner.gaits.steps import Step
from planner.trajectory.samples import Trajectory

#: A boundary's q̈ mismatch counts as a jump above this many times the largest second
#: difference of q̈ inside the steps (module docstring; the Taylor remainder of the linear
#: extrapolation is at most half a second difference, and the snap may differ from step to
#: step: 4 leaves room for both, three orders of magnitude below a cosine blend's jump).
JUMP_FACTOR = 4.0
#: Samples each side of a boundary whose interior second differences set its scale: the
#: Taylor remainder is the snap there, not the plan's sharpest feature elsewhere.
WINDOW_SAMPLES = 5
#: Samples a step needs on each side of a boundary for the boundary to be judged: with
#: fewer the samples do not resolve q̈'s curvature (at 2 samples per unit, 3 per step, a
#: quintic's q̈ cannot be told from a jump; at 20 per unit SILO4's creep at the top of its
#: feasible range needed a factor of 4.01, at 100 per unit 1.04-1.39 over 6 directions at
#: h 0.2 and 0.606 m). The default's 100 samples per unit judge every step (0.5 unit and up).
MIN_STEP_SAMPLES = 40
#: Mismatches below this [rad/s²] are rounding (the joint map's IK at rest, ~1e-9).
QDD_FLOOR = 1e-6


@dataclass(frozen=True)
class QddJump:
    """The worst jump of q̈ found (:func:`qdd_jump`): ``jump`` [rad/s²] of joint ``joint`` at
    ``sample`` (``t_units`` [units]), the start of step ``step_index`` (``label``), where a
    continuous q̈ allows ``allowed`` [rad/s²]."""

    jump: float
    joint: str
    sample: int
    t_units: float
    step_index: int
    label: str
    allowed: float

    @property
    def reason(self) -> str:
        return (
            f"q'' of {self.joint} jumps by {self.jump:.3g} rad/s^2 at sample {self.sample} "
            f"(t = {self.t_units:.2f} units, start of step {self.step_index}, {self.label}), "
            f"above the {self.allowed:.3g} rad/s^2 a continuous q'' allows there"
        )


def still(step: Step) -> bool:
    """Whether nothing moves in ``step``: a body step whose base pose ends where it starts
    (a four-foot stand)."""
    return (
        step.leg is None
        and step.yaw_base_start == step.yaw_base_end
        and bool(np.array_equal(step.position_base_start_in_world, step.position_base_end_in_world))
    )


def qdd_jump(trajectory: Trajectory, steps: Sequence[Step]) -> QddJump | None:
    """None when q̈ is continuous at every step boundary of ``trajectory`` (module
    docstring), else the worst jump. Boundaries next to a moving step with fewer than
    MIN_STEP_SAMPLES samples are not judged (a coarse sampling does not resolve q̈); a
    still step (:func:`still`) resolves it at any length."""
    qdd = np.asarray(trajectory.qdd, float)
    n = len(qdd)
    if n < 3 or not len(steps):
        return None
    units = np.asarray(trajectory.time_units, float)
    per_unit = (n - 1) / units[-1] if units[-1] > 0 else 0.0
    if per_unit <= 0:
        return None
    starts = np.array([int(round(s.t_start * per_unit)) for s in steps] + [n - 1])
    # a step resolves its q'' when it has MIN_STEP_SAMPLES samples or nothing moves in it
    # (a four-foot stand: q'' is 0 on every sample, exactly what a jump is told from)
    resolved = [
        starts[k + 1] - starts[k] >= MIN_STEP_SAMPLES or still(s) for k, s in enumerate(steps)
    ]
    bounds = [
        (k, int(starts[k]))
        for k in range(1, len(steps))
        if resolved[k - 1] and resolved[k] and starts[k] < n
    ]
    if not bounds:
        return None
    second = np.abs(qdd[2:] - 2.0 * qdd[1:-1] + qdd[:-2])  # row j - 2: sample j
    interior = np.ones(n, bool)
    interior[:2] = False
    for i in starts[:-1][starts[:-1] < n]:
        interior[int(i) : int(i) + 2] = False  # a difference that spans a boundary
    worst: tuple[float, int, int, int, float] | None = None  # (jump, joint, sample, step, allowed)
    for k, i in bounds:
        window = np.arange(max(2, i - WINDOW_SAMPLES), min(n, i + WINDOW_SAMPLES + 2))
        window = window[interior[window]]
        scale = second[window - 2].max(axis=0) if len(window) else np.zeros(qdd.shape[1])
        allowed = JUMP_FACTOR * scale + QDD_FLOOR
        mismatch = np.abs(qdd[i] - (2.0 * qdd[i - 1] - qdd[i - 2]))
        j = int(np.argmax(mismatch - allowed))
        if mismatch[j] > allowed[j] and (worst is None or mismatch[j] > worst[0]):
            worst = (float(mismatch[j]), j, i, k, float(allowed[j]))
    if worst is None:
        return None
    jump, j, i, k, limit = worst
    return QddJump(jump, trajectory.joint_names[j], i, float(units[i]), k, steps[k].label, limit)
