"""How much of the load each stance foot is given over time: the load transfer at contact
changes.

The thesis's split of the load over the stance feet (eq A.31 / A.33, silo4kin.support) is
quasi-static per sample: when a fourth foot touches down the least-norm split over four feet
takes over at once from the unique three-foot one, and at a lift-off the reverse. Both splits
carry the same load, but they differ foot by foot, so every contact change steps the
reactions and the support torques Jᵀ(-F) (measured on anymal's corpus case 5: up to 0.645 of
the weight and 45.9 N m in one 10 ms sample, against 0.037 W and 3.3 N m elsewhere;
docs/physics.md). A real foot is loaded from zero after it touches down and unloaded to zero
before it lifts: its *share* s_k(t) in [0, 1]

    s_k = smoothstep(min(1, (t - t_down) / T, (t_up - t) / T))     (stance), 0 in swing,

with t_down its last touchdown, t_up its next lift-off (a stance that starts with the plan or
lasts to its end is not ramped at that end) and T the transfer time. silo4kin.support then
picks, among the four-foot reactions that carry the load, the one nearest the shares
(least Σ F_k² / s_k): a foot of share 0 carries nothing, so at the first and last sample of a
stance the four-foot split is the three-foot split of the other feet, and the reactions are
continuous through every contact change. smoothstep(x) = 3x² - 2x³ has zero slope at both
ends: the rate of load change is continuous too.

The transfer is bounded by the four-foot time the gait leaves: a foot lifting 0.1 s after
another touched down gives its load away within those 0.1 s whatever T is (at the lift-off
sample its share is 0). Where one foot lands on the sample another lifts (swings back to
back: the crawl's pairs, the creep's two transfers) there is no four-foot time and the load
jumps from one three-foot split to the other (up to 0.64 W in one sample on SILO4 and
anymal); the default preset's plans stand on four feet between two such swings for the
transfer (planner/gaits/walk.py swap_stand_units), the thesis preset's do not.
"""

from __future__ import annotations

import numpy as np

from .errors import Silo4Error

#: Transfer time T of the whole-robot load [s]: within the default gaits' four-foot phases
#: at their unit time of 1 s (0.5 unit after each crawl pair, the creep's 1-unit body
#: phases), long against the 10 ms sample in which the sim's servos saw the steps.
LOAD_TRANSFER_S = 0.2


def _smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def load_shares(contact: np.ndarray, t_s: np.ndarray, transfer_s: float) -> np.ndarray:
    """The share s_k in [0, 1] of each foot at each sample (module docstring), (N, 4).

    Args:
        contact: stance flags (N, 4), bool.
        t_s: sample times [s], (N,), increasing.
        transfer_s: transfer time T [s] >= 0; 0 gives every stance foot share 1 (the
            thesis's instant split).
    """
    c = np.asarray(contact, dtype=bool)
    t = np.asarray(t_s, dtype=float)
    if c.ndim != 2 or c.shape[1] != 4 or t.shape != (c.shape[0],):
        raise Silo4Error(f"contact {c.shape} and times {t.shape} must be (N, 4) and (N,)")
    if not np.isfinite(transfer_s) or transfer_s < 0:
        raise Silo4Error(f"the load transfer time must be >= 0 s, got {transfer_s}")
    if transfer_s == 0 or len(t) == 0:
        return c.astype(float)
    n = len(t)
    idx = np.arange(n)
    shares = np.zeros(c.shape)
    for k in range(4):
        stance = c[:, k]
        # the first sample of each stance run (touchdown) and the last (lift-off)
        start = stance & ~np.r_[False, stance[:-1]]
        end = stance & ~np.r_[stance[1:], False]
        down = np.maximum.accumulate(np.where(start, idx, -1))
        up = np.minimum.accumulate(np.where(end, idx, n)[::-1])[::-1]
        since = np.where(down > 0, t - t[np.maximum(down, 0)], np.inf)
        until = np.where(up < n - 1, t[np.minimum(up, n - 1)] - t, np.inf)
        ramp = _smoothstep(np.minimum(since, until) / transfer_s)
        shares[:, k] = np.where(stance, ramp, 0.0)
    return shares
