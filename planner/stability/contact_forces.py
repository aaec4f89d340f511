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


@dataclass(frozen=True)
class ContactForces:
    """Ground forces on the feet along a plan (module docstring).

    Attributes:
        normal_n: vertical load N_i of each foot [N] (N, 4); 0 for swing feet.
        tangential_n: horizontal load |T_i| of each foot [N] (N, 4); 0 for swing feet.
        force_in_world: total ground force F on the robot [N] (N, 3).
        weight_n: m g [N].
    """

    normal_n: np.ndarray
    tangential_n: np.ndarray
    force_in_world: np.ndarray
    weight_n: float

    @property
    def friction_demand(self) -> np.ndarray:
        """|F_xy| / F_z, the T_i / N_i of every stance foot [-] (N,)."""
        return np.hypot(self.force_in_world[:, 0], self.force_in_world[:, 1]) / np.maximum(
            self.force_in_world[:, 2], 1e-12
        )


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
    lever = (com_in_world[:, 2] - ground_z) / force[:, 2] * mass_kg
    zmp = com_in_world[:, :2] - lever[:, None] * acc[:, :2]
    rel = position_foot_in_world[..., :2] - zmp[:, None, :]
    normal = support_reactions(rel, contact, force[:, 2]).force
    demand = np.hypot(force[:, 0], force[:, 1]) / force[:, 2]
    tangential = normal * demand[:, None]
    return ContactForces(normal, tangential, force, float(mass_kg * gravity))


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
        reason = f"friction demand {demand[i]:.4g} > mu_plan {rule.friction:g}"
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

    def first_violation(self, trajectory) -> tuple[int, int, str] | None:
        """(sample, foot, reason) of the first sample breaking the rule, or None."""
        if not self.rule.active:
            return None
        return first_contact_violation(self.forces(trajectory), trajectory.contact, self.rule)
