"""Vertical ground reactions of the stance feet carrying a load (thesis App. A.2.2).

With the stance feet at horizontal positions (x_i, y_i) relative to the load's centre of
gravity, the vertical reactions F_i balance the load W = m g:

    A = [[x_1 .. x_k], [y_1 .. y_k], [1 .. 1]]              (eq A.30)
    A F = W,   W = (0, 0, +m g)                               (eq A.32, sign corrected)
    four feet:  F = Aᵀ (A Aᵀ)⁻¹ W   (least-norm split)        (eq A.31)
    three feet: F = A⁻¹ W                                     (eq A.33)

Rows 1-2 of A F = W say the moments of the reactions about the CoG vanish, row 3 says they
sum to the weight. These are the equilibrium conditions of the reactions the ground exerts
ON the feet, so W must be +m g (up): the printed W = (0, 0, -m_b g) makes F the forces the
feet exert on the ground, and then τ = Jᵀ(-F) (A.34) has the wrong sign (docs/torques.md).

Negative reactions: a foot cannot pull. With three feet F is unique, and F_i < 0 means the
CoG projection is outside the support triangle: the sample is statically unstable and is
flagged ``unloadable``. With four feet the least-norm split can ask a foot to pull although
the CoG is inside the support polygon (near an edge); the solutions of A F = W form the line
F_ln + t n (n spans the null space of A), so by default we return the least-norm split among
the NON-NEGATIVE ones (closed form: the t of smallest |t| keeping F >= 0, which unloads one
foot). If no t works the CoG is outside the polygon and the sample is flagged ``unloadable``
(its least-norm values are returned unchanged).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import Silo4Error

#: Smallest |det A| (three feet) or det(A Aᵀ) scale (four feet) accepted, relative to the
#: square of the foot spread [dimensionless]: below it the stance feet are collinear
#: (a support "polygon" of zero area) and the split is undefined. SILO4's feet are ~0.3 m
#: apart, so 1e-9 corresponds to a triangle of ~1e-10 m^2, far below any real stance.
COLLINEAR_TOLERANCE = 1e-9

#: A reaction above -NEGATIVE_TOLERANCE * m g counts as non-negative [dimensionless]: a CoG
#: exactly on a support edge (stability margin 0, which the thesis's own gait produces) gives
#: a reaction of 0 computed as ~ -1e-16 m g.
NEGATIVE_TOLERANCE = 1e-9


class SupportError(Silo4Error):
    """Fewer than three stance feet, or collinear stance feet, at some sample.

    Attributes:
        sample: index of the first offending sample.
    """

    def __init__(self, message: str, sample: int) -> None:
        super().__init__(message)
        self.sample = sample


@dataclass(frozen=True)
class SupportReactions:
    """Vertical ground reactions on the feet.

    Attributes:
        force: upward reaction of the ground on each foot [N], shape (N, 4); 0 for swing feet.
        least_norm: the thesis's least-norm split (eq A.31 / A.33) before the non-negative
            correction [N], shape (N, 4) (equal to ``force`` where nothing was corrected).
        unloadable: samples where no non-negative split exists (CoG projection outside the
            support polygon), shape (N,), bool.
        corrected: samples where the least-norm split had a negative reaction and the
            non-negative split was used instead, shape (N,), bool.
    """

    force: np.ndarray
    least_norm: np.ndarray
    unloadable: np.ndarray
    corrected: np.ndarray


def _check_inputs(
    position_foot_rel_cog: np.ndarray, contact: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    p = np.asarray(position_foot_rel_cog, dtype=float)
    c = np.asarray(contact, dtype=bool)
    if p.ndim != 3 or p.shape[1] != 4 or p.shape[2] not in (2, 3):
        raise Silo4Error(f"foot positions have shape {p.shape}, expected (N, 4, 3) or (N, 4, 2)")
    if c.shape != p.shape[:2]:
        raise Silo4Error(f"contact has shape {c.shape}, expected {p.shape[:2]}")
    if not np.all(np.isfinite(p[c])):
        bad = int(np.argwhere(~np.isfinite(p).all(axis=2) & c)[0, 0])
        raise Silo4Error(f"stance foot position at sample {bad} is not finite")
    n_stance = c.sum(axis=1)
    few = np.flatnonzero(n_stance < 3)
    if few.size:
        k = int(few[0])
        raise SupportError(
            f"sample {k} has {int(n_stance[k])} stance feet (contact {c[k].tolist()}); "
            f"at least 3 are needed to carry the body ({few.size} such samples)",
            k,
        )
    return p[:, :, :2], c


def _matrix_a(xy: np.ndarray) -> np.ndarray:
    """A of eq A.30 for stance feet xy (n, k, 2) -> (n, 3, k)."""
    return np.concatenate([np.swapaxes(xy, 1, 2), np.ones((xy.shape[0], 1, xy.shape[1]))], axis=1)


def _collinear_error(idx: np.ndarray, bad: np.ndarray) -> SupportError:
    k = int(idx[np.flatnonzero(bad)[0]])
    return SupportError(
        f"sample {k}: the stance feet are collinear (support polygon of zero "
        "area); the vertical reactions are undefined",
        k,
    )


def support_reactions(
    position_foot_rel_cog: np.ndarray,
    contact: np.ndarray,
    weight: float | np.ndarray,
    *,
    nonnegative: bool = True,
    share: np.ndarray | None = None,
) -> SupportReactions:
    """Vertical reactions of the stance feet carrying ``weight`` at the CoG, eq A.30-A.33.

    Args:
        position_foot_rel_cog: foot positions relative to the load's CoG in a frame whose z
            is vertical (the level base frame, or the world frame) [m], shape (N, 4, 3) or
            (N, 4, 2); only x and y are used; swing feet may hold anything finite or not.
        contact: stance flags, shape (N, 4), bool; at least three per sample.
        weight: load m g > 0 [N], scalar or shape (N,).
        nonnegative: replace a four-foot least-norm split with a negative reaction by the
            least-norm non-negative split (module docstring); False returns eq A.31 as is.
        share: each foot's share of the load in [0, 1], (N, 4) (silo4kin.load_transfer):
            four feet carry the split nearest it, least Σ F_k² / s_k (a foot of share 0
            carries nothing; two or more feet of share 0: the least-norm split), then
            made non-negative as above; None: eq A.31. Three feet: their unique split.

    Returns:
        :class:`SupportReactions`.

    Raises:
        SupportError: fewer than three stance feet, or collinear stance feet, at a sample.
    """
    xy, c = _check_inputs(position_foot_rel_cog, contact)
    n = xy.shape[0]
    w = np.broadcast_to(np.asarray(weight, dtype=float), (n,))
    if not np.all(np.isfinite(w)) or np.any(w <= 0):
        raise Silo4Error(f"weight must be finite and > 0 N, got min {float(np.min(w))}")
    if share is not None:
        share = np.asarray(share, dtype=float)
        if share.shape != c.shape or not np.all((share >= 0) & (share <= 1)):
            raise Silo4Error(f"share must be (N, 4) in [0, 1], got shape {share.shape}")
    least = np.zeros((n, 4))
    force = np.zeros((n, 4))
    unloadable = np.zeros(n, dtype=bool)
    corrected = np.zeros(n, dtype=bool)
    scale = np.maximum(np.max(np.abs(np.where(c[..., None], xy, 0.0)), axis=(1, 2)), 1e-3)
    # one batched solve per contact pattern (at most 5 patterns), never per sample
    code = c @ np.array([1, 2, 4, 8])
    for pattern in np.flatnonzero(np.bincount(code, minlength=16)):
        idx = np.flatnonzero(code == pattern)
        legs = np.flatnonzero((pattern >> np.arange(4)) & 1)
        A = _matrix_a(xy[idx][:, legs])
        W = np.zeros((idx.size, 3))
        W[:, 2] = w[idx]
        if legs.size == 3:
            det = np.linalg.det(A)
            bad = np.abs(det) < COLLINEAR_TOLERANCE * scale[idx] ** 2
            if np.any(bad):
                raise _collinear_error(idx, bad)
            F = np.linalg.solve(A, W[..., None])[..., 0]  # eq A.33
            neg = np.any(F < -NEGATIVE_TOLERANCE * w[idx, None], axis=1)
            least[idx[:, None], legs] = F
            force[idx[:, None], legs] = F
            unloadable[idx] = neg
            continue
        AAt = A @ np.swapaxes(A, 1, 2)
        bad = np.abs(np.linalg.det(AAt)) < COLLINEAR_TOLERANCE * scale[idx] ** 4
        if np.any(bad):
            raise _collinear_error(idx, bad)
        F = (np.swapaxes(A, 1, 2) @ np.linalg.solve(AAt, W[..., None]))[..., 0]  # eq A.31
        least[idx] = F
        force[idx] = F
        if not nonnegative:
            unloadable[idx] = np.any(F < -NEGATIVE_TOLERANCE * w[idx, None], axis=1)
            continue
        # null space of the 3x4 A by cofactors: n_j = (-1)^j det(A without column j)
        null = np.stack(
            [(-1) ** j * np.linalg.det(np.delete(A, j, axis=2)) for j in range(4)], axis=1
        )
        null /= np.linalg.norm(null, axis=1, keepdims=True)
        tol = NEGATIVE_TOLERANCE * w[idx, None]
        target = np.zeros(idx.size) if share is None else _nearest_shares(F, null, share[idx])
        needs = np.any(F + target[:, None] * null < -tol, axis=1)
        t_strict, ok_strict = _closest_nonnegative(F, null, 0.0, target)
        t_slack, ok_slack = _closest_nonnegative(F, null, tol, target)
        t = np.where(ok_strict, t_strict, t_slack)
        t = np.where(needs & ok_slack, t, target)
        force[idx] = F + t[:, None] * null
        corrected[idx] = needs & ok_slack
        unloadable[idx] = ~ok_slack
    return SupportReactions(
        force=force, least_norm=least, unloadable=unloadable, corrected=corrected
    )


def _nearest_shares(F: np.ndarray, null: np.ndarray, share: np.ndarray) -> np.ndarray:
    """The t of F + t null (the four-foot splits, (n, 4)) with least Σ F_k² / s_k, (n,): for
    one foot of share 0 the t that zeroes it (if the null direction moves it), for none
    -Σ F_k n_k / s_k / Σ n_k² / s_k, for two or more 0 (the least-norm split)."""
    zero = share <= 0.0
    n_zero = zero.sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.where(zero, 0.0, 1.0 / share)
        weighted = -np.sum(F * null * inv, axis=1) / np.sum(null * null * inv, axis=1)
        k = np.argmax(zero, axis=1)
        rows = np.arange(len(F))
        zeroing = -F[rows, k] / null[rows, k]
    one = (n_zero == 1) & (null[rows, k] != 0.0)
    t = np.where(one, zeroing, np.where(n_zero == 0, weighted, 0.0))
    return np.where(np.isfinite(t), t, 0.0)


def _closest_nonnegative(
    F: np.ndarray, null: np.ndarray, tol: float | np.ndarray, target: np.ndarray | float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """The t nearest ``target`` with F + t null >= -tol for every foot, and whether any t
    works, (n,)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        bound = (-tol - F) / null
    t_lo = np.max(np.where(null > 0, bound, -np.inf), axis=1)
    t_hi = np.min(np.where(null < 0, bound, np.inf), axis=1)
    # a foot the null direction does not move must already be non-negative
    fixed_ok = np.all((null != 0.0) | (F >= -tol), axis=1)
    feasible = (t_lo <= t_hi) & fixed_ok
    return np.where(feasible, np.clip(target, t_lo, t_hi), 0.0), feasible


def support_moment_residual(position_foot_rel_cog: np.ndarray, force: np.ndarray) -> np.ndarray:
    """Moments of the reactions about the CoG, (Σ y_i F_i, -Σ x_i F_i) [N m], shape (N, 2).

    Zero for every valid split (rows 1-2 of eq A.30-A.31); used by the tests.
    """
    p = np.asarray(position_foot_rel_cog, dtype=float)[:, :, :2]
    f = np.asarray(force, dtype=float)
    p = np.where(f[..., None] != 0.0, p, 0.0)
    return np.stack([np.sum(p[:, :, 1] * f, axis=1), -np.sum(p[:, :, 0] * f, axis=1)], axis=1)
