"""The crawl with the creeping gait as its fallback, segment by segment: where the continuous
crawl (planner/gaits/crawl.py) finds no stable reachable step, one half cycle of the
omnidirectional creeping gait (planner/gaits/omni.py) and the crawl again."""

from __future__ import annotations

import math

import numpy as np

from planner.errors import FootholdRefused, PlanningError
from planner.gaits.builder import StepBuilder
from planner.gaits.crawl import FOUR_FOOT_UNITS, Crawl
from planner.gaits.foothold_ellipse import ellipse_radius
from planner.gaits.omni import MIN_STEP_M, Stall, omni_half_cycle
from planner.gaits.steps import Phase, StepKind
from planner.workspace.layout import Workspace
from silo4kin.frames import rotation_z


class CrawlOrCreep:
    """Walks each segment with the crawl; where the crawl finds no stable reachable step
    (a change of direction can leave the feet where no sway is both stable and reachable),
    one half cycle of the omnidirectional creeping gait (planner/gaits/omni.py, which puts a pair
    back at position 2) and the crawl again, until the segment is walked: the crawl's
    attempt since the last creeping half cycle is rolled back, except when the builder's
    foothold check refused a foothold (a ditch ahead): then only the step that placed it is
    undone, the swings before it stay. ``segments`` records per segment the creeping half
    cycles it needed (0: all crawl) and ``reasons`` why the crawl did not go on."""

    def __init__(self, four_foot_units: float = FOUR_FOOT_UNITS) -> None:
        self.crawl = Crawl(four_foot_units)
        self.segments: list[int] = []
        self.reasons: list[str] = []
        self.n_swings = 0

    def snapshot(self) -> tuple:
        """A copy of the fields a walk changes (a plan's first segment is replayed from a
        memo, planner/gaits/first_walk.py)."""
        c = self.crawl
        return (
            c.four_foot_units,
            c.next_index,
            c.order,
            list(self.segments),
            list(self.reasons),
            self.n_swings,
        )

    def restore(self, snapshot: tuple) -> None:
        """Set the fields saved by :meth:`snapshot` (it can be restored twice)."""
        c = self.crawl
        c.four_foot_units, c.next_index, c.order, segments, reasons, self.n_swings = snapshot
        self.segments, self.reasons = list(segments), list(reasons)
        c.resume = None

    def to(
        self, b: StepBuilder, ws: Workspace, target_xy_in_world: np.ndarray, legs=None
    ) -> tuple[int, float]:
        """Walk the nominal CoG to ``target_xy_in_world`` (2,) [m] (class docstring);
        returns the creeping half cycles made (the crawl's swings are counted in
        ``n_swings``) and the nominal distance [m]."""
        target = np.asarray(target_xy_in_world, float)
        n_done, walked, creeps = 0, 0.0, 0
        stall = Stall()
        while True:
            # nothing since the segment's start or the last creeping half cycle is rolled
            # back: the time so far and the bound on the rest hold for the plan
            b.check_time_limit()
            state = b.snapshot()
            try:
                n, w = self.crawl.to(b, ws, target, legs)
                self.segments.append(creeps)
                self.n_swings += n
                return n_done, walked + w
            except PlanningError as exc:
                b.restore(state)
                self.reasons.append(str(exc))
            except FootholdRefused as exc:
                # the swings before the refused foothold stay (their footholds were accepted):
                # the creeping gait takes over where it would have been placed
                assert self.crawl.resume is not None
                kept, n, w = self.crawl.resume
                b.restore(kept)
                self.n_swings += n
                walked += w
                self.reasons.append(str(exc))
            finally:
                self.crawl.resume = None  # (a builder state: not kept past its attempt)
            if float(np.hypot(*(b.base[:2] - b.nominal_base[:2]))) > 1e-9:
                # back from the sway to the nominal CoG: the creeping gait's reach checks
                # and shifts assume it
                b.body(
                    b.nominal_base,
                    b.nominal_yaw,
                    b.four_foot_units(b.nominal_base, self.crawl.four_foot_units),
                    StepKind.BODY,
                    "crawl arrive",
                    Phase.SHIFT,
                )
            b.fold_fence = len(b.steps)  # no fold moves a crawl step's base
            self.crawl.order = None  # the crawl restarts from the creep's stance
            rel = rotation_z(-b.nominal_yaw)[:2, :2] @ (target - b.nominal_base[:2])
            dist = float(np.hypot(*rel))
            u = rel / dist
            radius = ellipse_radius(ws, u)
            if radius < MIN_STEP_M:
                raise b.error("the omnidirectional gait has no stride along a body axis here")
            asked = dist / math.ceil(dist / radius - 1e-9)
            stall.record(omni_half_cycle(b, ws, u, asked, legs), asked, b)
            walked += stall.steps_m[-1]
            n_done += 1
            creeps += 1
            if creeps > 10_000:
                raise b.error("the crawl and the creeping gait make no progress")
