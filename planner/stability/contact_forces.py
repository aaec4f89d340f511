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

from dataclasses import dataclass
from typing import Any

import numpy as np

from planner.stability.contact_rule import ContactForceRule
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
    """

    normal_n: np.ndarray
    tangential_n: np.ndarray
    force_in_world: np.ndarray
    weight_n: float
    upright: np.ndarray

    @property
    def friction_demand(self) -> np.ndarray:
        """|F_xy| / F_z, the T_i / N_i of every stance foot [-] (N,); inf where F_z <= 0
        (the feet would leave the ground)."""
        fz = self.force_in_world[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.hypot(self.force_in_world[:, 0], self.force_in_world[:, 1]) / fz
        return np.where(self.upright, ratio, np.inf)


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
) -> ContactForces:
    """Ground forces of a plan (module docstring): feet (N, 4, 3) [m] and contact (N, 4),
    CoM (N, 3) [m] at times t_s (N,) [s], mass [kg], gravity [m/s²], ground height [m]."""
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
        normal[upright] = support_reactions(rel, contact[upright], f[:, 2]).force
        demand[upright] = np.hypot(f[:, 0], f[:, 1]) / f[:, 2]
    tangential = np.where(
        np.isfinite(demand)[:, None],
        normal * np.where(np.isfinite(demand), demand, 0.0)[:, None],
        0.0,
    )
    return ContactForces(normal, tangential, force, float(mass_kg * gravity), upright)


def first_contact_violation(
    forces: ContactForces, contact: np.ndarray, rule: ContactForceRule
) -> tuple[int, int, str] | None:
    """(sample, foot, reason) of the first sample breaking ``rule``, or None."""
    bad = np.zeros(contact.shape, dtype=bool)
    low = np.zeros(contact.shape, dtype=bool)
    least_n = (
        0.0 if rule.min_normal_fraction is None else rule.min_normal_fraction * forces.weight_n
    )
    if rule.min_normal_fraction is not None:
        low = contact & (forces.normal_n < least_n)
        bad |= low
    demand = forces.friction_demand
    if rule.friction is not None:
        bad |= contact & (demand[:, None] > rule.friction)
    rows = np.flatnonzero(bad.any(axis=1))
    if not rows.size:
        return None
    i = int(rows[0])
    j = int(np.flatnonzero(bad[i])[0])
    if low[i, j]:
        reason = (
            f"normal load {forces.normal_n[i, j]:.2f} N < {rule.min_normal_fraction:g} of "
            f"the weight ({least_n:.2f} N)"
        )
    else:
        reason = (
            f"friction demand {demand[i]:.4g} > mu_plan {rule.friction:g}"
            if np.isfinite(demand[i])
            else f"the feet would leave the ground or tip (F_z {forces.force_in_world[i, 2]:.1f} N)"
        )
    return i, j, reason


@dataclass(frozen=True)
class ContactForceCheck:
    """A rule and the robot it is checked on: ``model`` a PlanningModel (total_mass,
    com_in_world), ``gravity`` [m/s²]."""

    rule: ContactForceRule
    model: Any
    gravity: float

    def forces(self, trajectory) -> ContactForces:
        """The ContactForces of a Trajectory; the ground under the CoM is the mean height
        of the stance feet's contact points."""
        com = self.model.com_in_world(
            trajectory.q, trajectory.position_base_in_world, trajectory.yaw_base_in_world
        )
        feet, contact = trajectory.position_foot_in_world, trajectory.contact
        ground = np.sum(np.where(contact, feet[..., 2], 0.0), axis=1) / contact.sum(axis=1)
        return contact_forces(
            feet, contact, com, trajectory.t, self.model.total_mass, self.gravity, ground
        )

    def unit_time_for_friction(self, trajectory, resolution_s: float = 1e-4) -> float:
        """Shortest unit time [s], rounded up to ``resolution_s``, whose friction demand is
        <= mu_plan (0 without a friction rule). Retimed to T, the CoM's acceleration is
        c̈₁ / T² (c̈₁ at T = 1 s), so |c̈₁_xy| <= mu (g T² + c̈₁_z) needs
        T² >= (|c̈₁_xy| - mu c̈₁_z) / (mu g) at every sample."""
        mu = self.rule.friction
        if mu is None or len(trajectory.t) < 3:
            return 0.0
        com = self.model.com_in_world(
            trajectory.q, trajectory.position_base_in_world, trajectory.yaw_base_in_world
        )
        acc_1s = com_acceleration(com, trajectory.t) * trajectory.unit_time_s**2
        need = (np.hypot(acc_1s[:, 0], acc_1s[:, 1]) - mu * acc_1s[:, 2]) / (mu * self.gravity)
        t_s = float(np.sqrt(max(float(need.max()), 0.0)))
        return float(np.ceil(t_s / resolution_s)) * resolution_s

    def first_violation(self, trajectory) -> tuple[int, int, str] | None:
        """(sample, foot, reason) of the first sample breaking the rule, or None."""
        if not self.rule.active:
            return None
        return first_contact_violation(self.forces(trajectory), trajectory.contact, self.rule)
