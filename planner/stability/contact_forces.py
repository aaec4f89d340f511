"""Contact forces with headroom: every stance foot pressed down enough, none asked to slide.

The support margin (margin.py) says the CoM projection is inside the support polygon; it
does not say a foot carries enough load to hold, nor that friction can carry the horizontal
force that accelerates the robot. Per sample, with m the whole robot's mass, c its CoM and
c̈ the CoM's acceleration (central differences of the sampled c, which the plan's base and
joint samples give: planner/model.py):

    total ground force     F = m (c̈ + g ẑ)                           (Newton, exact)
    normal loads N_i       vertical reactions (eq A.30-A.33, silo4kin/support.py) of the
                           stance feet carrying F_z about the zero-moment point
                           z = c_xy - (c_z - ground) c̈_xy / (c̈_z + g)
                           (the body's acceleration moves load between the feet)
    tangential loads T_i   F_xy shared in proportion to N_i: the split that asks least
                           of the most demanding foot, so T_i / N_i = |F_xy| / F_z

Every foot's force is then N_i F / F_z, parallel to F. On a sloped stance surface of unit
normal n_i (a terrain file's ramp or height map) the friction demand is taken in the
surface's frame: |F - (F . n_i) n_i| / (F . n_i), the tangent of the angle between F and
n_i (standing still on a slope of angle a: m g sin a / m g cos a = tan a); with n_i = z it
is |F_xy| / F_z, bit for bit.

Two rules (:class:`ContactForceRule`):

- **minimum normal load**: N_i >= min_normal_fraction m g for every stance foot. A foot
  that carries almost nothing holds only |T_i| <= mu N_i ~ 0: any servo error, vibration or
  internal force between the legs makes it slide (the sim's slips start on such feet). 5 %
  of the weight is a few servo-error forces: on SILO4 (~45 kg) 22 N, where a 1 mrad error
  of a 2000 N m/rad servo across a 0.4 m leg gives ~5 N.
- **friction demand**: T_i / N_i <= friction (mu_plan, default 0.5): half of a rubber foot on
  concrete or of the sim's 1.0, so a plan keeps a factor 2 to real floors.

A plan that breaks one is refused (planner/trajectory/verify.py names the step, time and
foot); ``min_normal_fraction=None`` or ``friction=None`` turns a rule off. The default
(contact_rule.py) checks the friction demand at mu_plan = 0.5 and not the normal load:
5 % refuses all 18 Chapter 6 cases (docs/physics.md, "Contact forces").
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from planner.stability.contact_rule import ContactForceRule
from planner.stability.margin import support_margin
from silo4kin.load_transfer import load_shares
from silo4kin.support import support_reactions

#: A zero-moment point farther from the stance feet's centroid than this many times their
#: largest distance from it is far outside the support polygon: the robot tips [-].
TIPPING_EXTENT_RATIO = 2.0


@dataclass(frozen=True)
class ContactForces:
    """Ground forces on the feet along a plan (module docstring).

    Attributes:
        normal_n: vertical load N_i of each foot [N] (N, 4); 0 for swing feet, and for every
            foot where F_z <= 0 or the robot tips (``upright`` False).
        tangential_n: horizontal load |T_i| of each foot [N] (N, 4); 0 for swing feet.
        force_in_world: total ground force F on the robot [N] (N, 3).
        weight_n: m g [N].
        upright: F_z > 0 and the zero-moment point near the support (N,), bool.
        normal_in_world: the unit normal of the ground under each foot (N, 4, 3); None:
            level ground (z).
        zmp_in_world: the zero-moment point (x, y) [m] (N, 2); the CoM's projection where
            F_z <= 0.
    """

    normal_n: np.ndarray
    tangential_n: np.ndarray
    force_in_world: np.ndarray
    weight_n: float
    upright: np.ndarray
    normal_in_world: np.ndarray | None = None
    zmp_in_world: np.ndarray | None = None

    def zmp_margin_m(self, position_foot_in_world: np.ndarray, contact: np.ndarray) -> np.ndarray:
        """Signed distance [m] (N,) of the zero-moment point inside the support polygon of
        the stance feet (margin.support_margin); -inf where F_z <= 0."""
        pressed = self.force_in_world[:, 2] > 0.0
        margin = np.full(len(pressed), -np.inf)
        if self.zmp_in_world is not None and pressed.any():
            feet = position_foot_in_world[pressed][..., :2]
            margin[pressed] = support_margin(feet, contact[pressed], self.zmp_in_world[pressed])
        return margin

    @property
    def friction_demand(self) -> np.ndarray:
        """|F_xy| / F_z, the T_i / N_i of every stance foot [-] (N,); inf where F_z <= 0
        (the feet would leave the ground)."""
        fz = self.force_in_world[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.hypot(self.force_in_world[:, 0], self.force_in_world[:, 1]) / fz
        return np.where(self.upright, ratio, np.inf)

    @property
    def foot_friction_demand(self) -> np.ndarray:
        """Tangential / normal force of each foot in its surface's frame [-] (N, 4)
        (module docstring): :attr:`friction_demand` on level ground; inf where F_z <= 0 or
        the force leaves the surface (F . n_i <= 0)."""
        if self.normal_in_world is None:
            return np.repeat(self.friction_demand[:, None], 4, axis=1)
        return surface_friction_demand(self.force_in_world, self.normal_in_world, self.upright)


def surface_friction_demand(
    force_in_world: np.ndarray, normal_in_world: np.ndarray, upright: np.ndarray
) -> np.ndarray:
    """|F - (F . n) n| / (F . n) [-] (N, 4) of forces F (N, 3) [N] on surfaces of unit
    normals n (N, 4, 3) (module docstring); inf where not ``upright`` (N,) or F . n <= 0."""
    f = force_in_world[:, None, :]
    n = normal_in_world
    pressed = f[..., 0] * n[..., 0] + f[..., 1] * n[..., 1] + f[..., 2] * n[..., 2]
    tangent = f - pressed[..., None] * n
    along = np.hypot(np.hypot(tangent[..., 0], tangent[..., 1]), tangent[..., 2])
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = along / pressed
    return np.where(upright[:, None] & (pressed > 0.0), ratio, np.inf)


def _unit_time(t_squared_s2: np.ndarray, resolution_s: float) -> float:
    """sqrt of the largest T² [s²] (0 if none is positive), rounded up to resolution_s."""
    t_s = float(np.sqrt(max(float(np.max(t_squared_s2)), 0.0)))
    return float(np.ceil(t_s / resolution_s)) * resolution_s


def com_acceleration(com_in_world: np.ndarray, t_s: np.ndarray) -> np.ndarray:
    """c̈ [m/s²] (N, 3) of CoM samples (N, 3) [m] at times t_s (N,) [s]: second-order
    central differences (one-sided at the ends); zeros for fewer than three samples."""
    if len(t_s) < 3:
        return np.zeros_like(com_in_world)
    velocity = np.gradient(com_in_world, t_s, axis=0)
    return np.gradient(velocity, t_s, axis=0)


def contact_forces(
    position_foot_in_world: np.ndarray,
    contact: np.ndarray,
    com_in_world: np.ndarray,
    t_s: np.ndarray,
    mass_kg: float,
    gravity: float,
    ground_z: float | np.ndarray = 0.0,
    normal_in_world: np.ndarray | None = None,
    share: np.ndarray | None = None,
) -> ContactForces:
    """Ground forces of a plan (module docstring): feet (N, 4, 3) [m] and contact (N, 4),
    CoM (N, 3) [m] at times t_s (N,) [s], mass [kg], gravity [m/s²], ground height [m],
    the ground's unit normal under each foot (N, 4, 3) (None: level ground), each foot's
    share of the load (N, 4) (silo4kin/load_transfer.py; None: each sample on its own)."""
    acc = com_acceleration(com_in_world, t_s)
    force = mass_kg * (acc + np.array([0.0, 0.0, gravity]))
    pressed = force[:, 2] > 0.0  # else the ground would have to pull the robot down
    lever = np.zeros(len(force))
    lever[pressed] = (
        (com_in_world[pressed, 2] - np.broadcast_to(ground_z, len(force))[pressed])
        * mass_kg
        / force[pressed, 2]
    )
    zmp = com_in_world[:, :2] - lever[:, None] * acc[:, :2]
    # a zero-moment point far outside the stance feet tips the robot (the reactions of
    # eq A.30-A.33 would be hugely negative; their collinearity test scales with the lever)
    weights = contact / contact.sum(axis=1, keepdims=True)
    centre = np.einsum("nk,nkd->nd", weights, position_foot_in_world[..., :2])
    extent = np.max(
        np.where(
            contact, np.linalg.norm(position_foot_in_world[..., :2] - centre[:, None], axis=2), 0
        ),
        axis=1,
    )
    upright = pressed & (np.linalg.norm(zmp - centre, axis=1) <= TIPPING_EXTENT_RATIO * extent)
    normal = np.zeros(contact.shape)
    demand = np.full(len(force), np.inf)
    if upright.any():
        f = force[upright]
        rel = position_foot_in_world[upright][..., :2] - zmp[upright][:, None, :]
        shares = None if share is None else share[upright]
        normal[upright] = support_reactions(rel, contact[upright], f[:, 2], share=shares).force
        demand[upright] = np.hypot(f[:, 0], f[:, 1]) / f[:, 2]
    tangential = np.where(
        np.isfinite(demand)[:, None],
        normal * np.where(np.isfinite(demand), demand, 0.0)[:, None],
        0.0,
    )
    return ContactForces(
        normal, tangential, force, float(mass_kg * gravity), upright, normal_in_world, zmp
    )


def first_contact_violation(
    forces: ContactForces,
    contact: np.ndarray,
    rule: ContactForceRule,
    position_foot_in_world: np.ndarray | None = None,
) -> tuple[int, int, str] | None:
    """(sample, foot, reason) of the first sample breaking ``rule``, or None; the
    zero-moment point is checked where the feet (N, 4, 3) [m] are given."""
    bad = np.zeros(contact.shape, dtype=bool)
    low = np.zeros(contact.shape, dtype=bool)
    least_n = (
        0.0 if rule.min_normal_fraction is None else rule.min_normal_fraction * forces.weight_n
    )
    if rule.min_normal_fraction is not None:
        low = contact & (forces.normal_n < least_n)
        bad |= low
    demand = forces.foot_friction_demand
    if rule.friction is not None:
        bad |= contact & (demand > rule.friction)
    tips = np.zeros(len(contact), dtype=bool)
    zmp_margin = np.zeros(len(contact))
    if rule.min_zmp_margin_m is not None and position_foot_in_world is not None:
        # a three-foot (or four-foot) support: the ZMP must lie inside it
        zmp_margin = forces.zmp_margin_m(position_foot_in_world, contact)
        tips = (contact.sum(axis=1) >= 3) & (zmp_margin < rule.min_zmp_margin_m)
        bad |= tips[:, None] & contact
    rows = np.flatnonzero(bad.any(axis=1))
    if not rows.size:
        return None
    i = int(rows[0])
    j = int(np.flatnonzero(bad[i])[0])
    slides = rule.friction is not None and demand[i, j] > rule.friction
    if tips[i] and not low[i, j] and not slides:
        assert rule.min_zmp_margin_m is not None
        reason = (
            f"the zero-moment point is {1e3 * zmp_margin[i]:.1f} mm inside the "
            f"support polygon, under the {1e3 * rule.min_zmp_margin_m:.0f} mm that keep the "
            f"robot from tipping (the body accelerates too hard there)"
        )
    elif low[i, j]:
        reason = (
            f"normal load {forces.normal_n[i, j]:.2f} N < {rule.min_normal_fraction:g} of "
            f"the weight ({least_n:.2f} N)"
        )
    else:
        reason = (
            f"friction demand {demand[i, j]:.4g} > mu_plan {rule.friction:g}"
            if np.isfinite(demand[i, j])
            else f"the feet would leave the ground or tip (F_z {forces.force_in_world[i, 2]:.1f} N)"
        )
    return i, j, reason


def friction_unit_time_squared(
    acc_1s: np.ndarray, normal_in_world: np.ndarray, mu: float, gravity: float
) -> np.ndarray:
    """The least T² [s²] (N, 4) for which a foot on a surface of unit normal n (N, 4, 3)
    keeps |F_t| <= mu F_n when the CoM's acceleration at T = 1 s is c̈₁ (N, 3) [m/s²]:
    retimed to T the acceleration is c̈₁ / T², so with s = T², a = c̈₁ and a_t, a_n (g_t,
    g_n) the tangential part and normal component of a (of g z) the rule is
    |a_t + s g_t| <= mu (a_n + s g_n). On a level surface (g_t = 0) that is
    s >= (|a_t| - mu a_n) / (mu g); on a slope |a_t + s g_t|² - mu² (a_n + s g_n)² is a
    concave quadratic in s (the slope within atan(mu)), <= 0 beyond its larger root. A
    surface steeper than atan(mu) gives 0: no unit time helps, the check refuses it."""
    a = acc_1s[:, None, :]
    n = normal_in_world
    a_n = a[..., 0] * n[..., 0] + a[..., 1] * n[..., 1] + a[..., 2] * n[..., 2]
    a_t = a - a_n[..., None] * n
    g_n = gravity * n[..., 2]
    g_t = -g_n[..., None] * n
    g_t[..., 2] += gravity
    g_t_norm = np.hypot(np.hypot(g_t[..., 0], g_t[..., 1]), g_t[..., 2])
    a_t_norm = np.hypot(np.hypot(a_t[..., 0], a_t[..., 1]), a_t[..., 2])
    linear = (a_t_norm - mu * a_n) / (mu * g_n)
    alpha = g_t_norm**2 - mu**2 * g_n**2
    beta = 2.0 * (np.sum(a_t * g_t, axis=-1) - mu**2 * a_n * g_n)
    gamma = a_t_norm**2 - mu**2 * a_n**2
    disc = beta**2 - 4.0 * alpha * gamma
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.where(disc >= 0.0, (-beta - np.sqrt(np.maximum(disc, 0.0))) / (2.0 * alpha), 0.0)
        pressed = -a_n / g_n
    sloped = np.maximum(np.maximum(root, pressed), 0.0)
    return np.where(g_t_norm == 0.0, linear, np.where(alpha < 0.0, sloped, 0.0))


@dataclass(frozen=True)
class ContactForceCheck:
    """A rule and the robot it is checked on: ``model`` a PlanningModel (total_mass,
    com_in_world), ``gravity`` [m/s²], ``terrain`` the ground (a Terrain: its normal under
    every stance foot; None: level ground), ``transfer_s`` the load transfer time [s] at
    contact changes (silo4kin/load_transfer.py; 0: each sample split on its own)."""

    rule: ContactForceRule
    model: Any
    gravity: float
    terrain: Any = None
    transfer_s: float = 0.0

    def forces(self, trajectory) -> ContactForces:
        """The ContactForces of a Trajectory; the ground under the CoM is the mean height
        of the stance feet's contact points, the friction demand in the frame of the
        terrain's surface under each foot."""
        com = self.model.com_in_world(
            trajectory.q, trajectory.position_base_in_world, trajectory.yaw_base_in_world
        )
        feet, contact = trajectory.position_foot_in_world, trajectory.contact
        ground = np.sum(np.where(contact, feet[..., 2], 0.0), axis=1) / contact.sum(axis=1)
        return contact_forces(
            feet,
            contact,
            com,
            trajectory.t,
            self.model.total_mass,
            self.gravity,
            ground,
            self.surface_normals(trajectory),
            load_shares(contact, trajectory.t, self.transfer_s) if self.transfer_s > 0 else None,
        )

    def surface_normals(self, trajectory) -> np.ndarray | None:
        """The terrain's unit normal under each stance foot (N, 4, 3), z under swing feet;
        None without a terrain."""
        if self.terrain is None:
            return None
        feet, contact = trajectory.position_foot_in_world, trajectory.contact
        normals = self.terrain.normal_at(feet[..., :2].reshape(-1, 2)).reshape(feet.shape)
        return np.where(contact[..., None], normals, np.array([0.0, 0.0, 1.0]))

    def unit_time_for_friction(self, trajectory, resolution_s: float = 1e-4) -> float:
        """Shortest unit time [s], rounded up to ``resolution_s``, whose friction demand is
        <= mu_plan on every stance foot (0 without a friction rule): the largest
        :func:`friction_unit_time_squared` of the samples, on level ground without a
        terrain."""
        mu = self.rule.friction
        if mu is None or len(trajectory.t) < 3:
            return 0.0
        _, acc_1s = self._com_and_unit_acceleration(trajectory)
        normals = self.surface_normals(trajectory)
        if normals is None:
            normals = np.broadcast_to([0.0, 0.0, 1.0], (len(acc_1s), 4, 3))
        need = friction_unit_time_squared(acc_1s, normals, mu, self.gravity)
        return _unit_time(np.where(trajectory.contact, need, 0.0), resolution_s)

    def _com_and_unit_acceleration(self, trajectory) -> tuple[np.ndarray, np.ndarray]:
        """The whole-robot CoM (N, 3) [m] of a Trajectory and its acceleration retimed to a
        unit time of 1 s (N, 3) [m/s²]."""
        com = self.model.com_in_world(
            trajectory.q, trajectory.position_base_in_world, trajectory.yaw_base_in_world
        )
        return com, com_acceleration(com, trajectory.t) * trajectory.unit_time_s**2

    def unit_time_for_zmp(self, trajectory, resolution_s: float = 1e-4) -> float:
        """Shortest unit time [s], rounded up to ``resolution_s``, that keeps the zero-moment
        point ``rule.min_zmp_margin_m`` inside the support polygon on every sample with
        three or more stance feet (0 without the rule). Retimed to T the CoM's acceleration
        is c̈₁ / T², so the ZMP z = c - k c̈₁_xy with k = (c_z - ground) / (c̈₁_z + T² g)
        runs from the CoM (k = 0, T -> inf) along a line as T shrinks; the margin is
        concave along it, so the k it allows is an interval [0, k_max] (bisection, 40
        halvings) and T² >= ((c_z - ground) / k_max - c̈₁_z) / g. A sample whose CoM itself
        is under the margin has no such T: it is left to :meth:`first_violation`."""
        least = self.rule.min_zmp_margin_m
        if least is None or len(trajectory.t) < 3:
            return 0.0
        com, acc_1s = self._com_and_unit_acceleration(trajectory)
        feet, contact = trajectory.position_foot_in_world, trajectory.contact
        rows = (contact.sum(axis=1) >= 3) & (np.hypot(acc_1s[:, 0], acc_1s[:, 1]) > 0.0)
        if not rows.any():
            return 0.0
        feet_xy, on = feet[rows][..., :2], contact[rows]
        c, a = com[rows], acc_1s[rows]
        ground = np.sum(np.where(on, feet[rows][..., 2], 0.0), axis=1) / on.sum(axis=1)
        lever = c[:, 2] - ground

        def margin(k: np.ndarray) -> np.ndarray:
            return support_margin(feet_xy, on, c[:, :2] - k[:, None] * a[:, :2])

        ok = margin(np.zeros(len(c))) >= least  # the CoM itself: else no T helps
        # bisection on k [s²] between 0 (inside) and 10 s², far outside any support
        lo, hi = np.zeros(len(c)), np.full(len(c), 10.0)
        unbounded = margin(hi) >= least
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            inside = margin(mid) >= least
            lo = np.where(inside, mid, lo)
            hi = np.where(inside, hi, mid)
        k_max = np.where(unbounded, np.inf, lo)
        with np.errstate(divide="ignore", invalid="ignore"):
            need = (lever / k_max - a[:, 2]) / self.gravity
        return _unit_time(np.where(ok & np.isfinite(need), need, 0.0), resolution_s)

    def first_violation(self, trajectory) -> tuple[int, int, str] | None:
        """(sample, foot, reason) of the first sample breaking the rule, or None."""
        if not self.rule.active:
            return None
        # the rules hold each sample's own split: a foot passing its load on at a contact
        # change (transfer_s) carries less by design, which is no reason to excuse it
        forces = replace(self, transfer_s=0.0).forces(trajectory)
        return first_contact_violation(
            forces, trajectory.contact, self.rule, trajectory.position_foot_in_world
        )
