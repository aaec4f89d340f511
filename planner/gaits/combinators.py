"""Gaits made of gaits (planner/gaits/base.py): the fastest of several, one with a fallback,
and one offered by default only on some leg families.

``Plan.fallback_reason`` records why a gait preferred to the one that walked was not used:
Fastest puts there the failures of the gaits before the winner, Fallback the failure of
its first gait (and what the second recorded), each as "<gait label>: <why>".
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from planner.errors import FootholdRefused, GaitRefused, PlanningError
from planner.gaits.base import Gait, NotFaster, PlanRequest, fewest_units
from planner.plan import Plan


def _reasons(gait: Gait, exc: PlanningError) -> tuple[str, ...]:
    """``exc`` as fallback reasons: a combination's own list, else "<label>: <message>"."""
    if isinstance(exc, GaitRefused) and len(exc.reasons) > 1:
        return exc.reasons
    return (f"{gait.label}: {exc}",)


def _joined(reasons: list[str] | tuple[str, ...], then: str | None = None) -> str | None:
    parts = [*reasons, *([then] if then else [])]
    return "; ".join(parts) if parts else None


@dataclass(frozen=True)
class Fastest:
    """Builds each gait in order and keeps the one with the least time: a later gait is
    built only until it is as slow as the plan in hand (``slower_than``, NotFaster), so on
    a tie the earlier one is kept, and not at all when its lower bound on the time
    (base.fewest_units) reaches the plan in hand. With ``slower_than``, once a gait has
    stopped as slow as it, the last gait is not built either when its bound reaches
    ``slower_than``: it could only stop or be refused, and with no gait after it (whose plan
    would carry its reason) both end in NotFaster. A gait refused with PlanningError or
    FootholdRefused is left out (its reason kept); with ``slower_than``, NotFaster when no
    gait is faster and one is as slow (its value the least of the gaits' stops and of the
    bound of a last gait not built: a lower bound on the time of every gait's plan, so the
    same limit up to that value stops the same gaits at the same steps, planner/path/height.py);
    when all are refused, the last FootholdRefused is raised if the last gait raised one, else
    GaitRefused with every reason."""

    gaits: tuple[Gait, ...]

    @property
    def name(self) -> str:
        return "|".join(g.name for g in self.gaits)

    @property
    def label(self) -> str:
        return " or ".join(g.label for g in self.gaits)

    def plan(self, request: PlanRequest, slower_than: float | None = None) -> Plan:
        best: Plan | None = None
        reasons: list[str] = []
        last: Exception | None = None
        slow: NotFaster | None = None
        for i, gait in enumerate(self.gaits):
            limit = slower_than if best is None else _units(best)
            if best is not None and fewest_units(gait, request) >= _units(best):
                continue  # it would stop with NotFaster
            if (
                best is None
                and slow is not None
                and slower_than is not None
                and i == len(self.gaits) - 1
                and fewest_units(gait, request) >= slower_than
            ):
                # it would stop or be refused: NotFaster either way
                slow = _least_stop(slow, NotFaster(fewest_units(gait, request)))
                continue
            try:
                plan = gait.plan(request, slower_than=limit)
            except NotFaster as exc:
                if best is None:  # as slow as ``slower_than``: a later gait may be faster
                    slow = _least_stop(slow, exc)
                continue
            except FootholdRefused as exc:
                reasons.append(f"{gait.label}: {exc}")
                last = exc
                continue
            except PlanningError as exc:
                reasons.extend(_reasons(gait, exc))
                last = exc
                continue
            best = replace(plan, fallback_reason=_joined(reasons, plan.fallback_reason))
            last = None
        if best is not None:
            return best
        if slow is not None:
            raise slow
        if isinstance(last, FootholdRefused):
            raise last
        raise GaitRefused("; ".join(reasons), tuple(reasons))

    def fewest_units(self, request: PlanRequest) -> float:
        """A lower bound [units] on the duration of the plan: the least of its gaits'
        (base.fewest_units; the one it returns is one of theirs)."""
        return min((fewest_units(g, request) for g in self.gaits), default=0.0)


def stop_units(exc: NotFaster) -> float:
    """The least time [units] a NotFaster says its plan takes (0 when it carries none)."""
    return float(exc.args[0]) if exc.args else 0.0


def _least_stop(slow: NotFaster | None, exc: NotFaster) -> NotFaster:
    """Of two stops, the one with the lesser time (the earlier gait's on a tie)."""
    return exc if slow is None or stop_units(exc) < stop_units(slow) else slow


def _units(plan: Plan) -> float:
    """The plan's duration [units] (0 when it has no step)."""
    return plan.steps[-1].t_end if plan.steps else 0.0


@dataclass(frozen=True)
class Fallback:
    """``first``; where it finds no stable, reachable step (PlanningError), ``then``, with
    the reason in ``Plan.fallback_reason``. A refused foothold is not a reason to fall
    back: FootholdRefused propagates. ``all_reasons``: where ``then`` fails too, GaitRefused
    names both gaits' reasons (strict planning's refusal, planner/path/at_height.py) instead
    of ``then``'s error alone."""

    first: Gait
    then: Gait
    all_reasons: bool = False

    @property
    def name(self) -> str:
        return self.first.name

    @property
    def label(self) -> str:
        return self.first.label

    def plan(self, request: PlanRequest, slower_than: float | None = None) -> Plan:
        try:
            return self.first.plan(request, slower_than=slower_than)
        except NotFaster:
            raise
        except PlanningError as exc:
            reasons = _reasons(self.first, exc)
            first_exc = exc
        try:
            plan = self.then.plan(request, slower_than=slower_than)
        except (NotFaster, FootholdRefused):
            raise
        except PlanningError as exc:
            if not self.all_reasons:
                raise
            both = (*reasons, *_reasons(self.then, exc))
            refused = GaitRefused("; ".join(both), both)
            # the waypoint named by the fallback's error, else by the first choice's
            named = exc if exc.waypoint_index is not None else first_exc
            refused.waypoint_index, refused.waypoint = named.waypoint_index, named.waypoint
            raise refused from exc
        return replace(plan, fallback_reason=_joined(reasons, plan.fallback_reason))

    def fewest_units(self, request: PlanRequest) -> float:
        """A lower bound [units] on the duration of the plan: the lesser of the two gaits'
        (base.fewest_units; it is ``first``'s plan or ``then``'s)."""
        return min(fewest_units(self.first, request), fewest_units(self.then, request))


@dataclass(frozen=True)
class DefaultFor:
    """``gait`` on the leg ``families`` only (planner/model.py PlanningModel.family): on
    other legs it is refused with ``why`` (asked for by name, the gait itself plans)."""

    gait: Gait
    families: tuple[str, ...]
    why: str

    @property
    def name(self) -> str:
        return self.gait.name

    @property
    def label(self) -> str:
        return self.gait.label

    def plan(self, request: PlanRequest, slower_than: float | None = None) -> Plan:
        family = request.model.family
        if family not in self.families:
            raise GaitRefused(f"not the default for {family} legs ({self.why})")
        return self.gait.plan(request, slower_than=slower_than)

    def fewest_units(self, request: PlanRequest) -> float:
        """The gait's lower bound on its duration (base.fewest_units); infinite on the legs
        it is refused on (no plan at all)."""
        if request.model.family not in self.families:
            return math.inf
        return fewest_units(self.gait, request)
