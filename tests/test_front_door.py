"""plan_path's typed inputs: the Preset registry, the gait names (one vocabulary from
plan_path(gait=) to Plan.gait), Height, and the Terrain hook (planner/terrain/)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from planner.errors import FootholdRefused, PlannerInputError, PlanningError
from planner.gaits.registry import gait_for
from planner.path.plan_path import plan_path
from planner.presets import PRESETS, gait_choices, preset_for
from planner.request import Height, as_height
from planner.terrain import CheckedFootholds, FlatGround, ForbiddenPolygons, Terrain

ONE = [[0.0, 0.8]]


def test_every_offered_gait_has_a_gait_object_named_as_asked():
    """Every name a preset offers gives a gait whose name is that name ("auto": the
    preset's default); the CLI's --gait choices are those names."""
    for preset in PRESETS.values():
        assert preset.default_gait in preset.gaits
        for name in preset.gaits:
            gait = gait_for(preset, name)
            if name != "auto":
                assert gait.name == name
    assert set(gait_choices()) == {"auto", "thesis", "crawl", "creep", "facing", "plain"}


@pytest.mark.parametrize(
    "options,fragment",
    [
        (dict(workspace="thesis", gait="crawl"), "does not offer gait 'crawl'"),
        (dict(workspace="thesis", face_path=True), "face_path"),
        (dict(face_path=True, gait="crawl"), "face_path walks the gait 'facing'"),
        (dict(gait="sideways"), "choose one of"),
        (dict(gait=3), "gait must be one of"),
        (dict(workspace="square"), "unknown workspace preset"),
    ],
)
def test_invalid_combinations_are_refused(silo4, options, fragment):
    with pytest.raises(PlannerInputError, match=fragment):
        plan_path(silo4, ONE, 0.4, samples_per_unit=2, **options)


def test_plan_gait_is_the_name_asked_for(silo4):
    """The gait asked for by name is the one Plan.gait reports; thesis's "auto" is "thesis"."""
    for name in ("crawl", "creep", "facing", "plain"):
        assert plan_path(silo4, ONE, 0.4, samples_per_unit=2, gait=name).gait == name
    assert plan_path(silo4, ONE, 0.4, samples_per_unit=2, workspace="thesis").gait == "thesis"


def test_a_crawl_asked_for_fails_with_its_reason_never_a_creep(silo4, monkeypatch):
    """gait="crawl" whose plan breaks a limit raises that reason; "auto" then creeps and
    records why the crawl was not used."""
    import planner.gaits.without_turning as wt

    monkeypatch.setattr(wt, "limit_violation", lambda *a: "LF_knee too fast (test)")
    with pytest.raises(PlanningError, match="LF_knee too fast"):
        plan_path(silo4, ONE, 0.4, samples_per_unit=2, gait="crawl")
    plan = plan_path(silo4, ONE, 0.4, samples_per_unit=2)
    assert plan.gait == "creep"
    assert plan.fallback_reason == "continuous crawl: LF_knee too fast (test)"


def test_a_preset_object_and_a_height_object_are_accepted(silo4):
    by_name = plan_path(silo4, ONE, 0.4, samples_per_unit=2, workspace="thesis")
    typed = plan_path(
        silo4, ONE, Height.fixed(0.4), samples_per_unit=2, workspace=preset_for("thesis")
    )
    assert typed.preset is PRESETS["thesis"]
    assert np.array_equal(by_name.trajectory.q, typed.trajectory.q)


def test_height_is_fixed_or_auto():
    assert as_height("auto").is_auto and as_height(Height.auto()).is_auto
    assert as_height(0.3) == Height.fixed(0.3) and as_height(np.float32(0.5)).fixed_m == 0.5
    for bad in ("high", True, None, float("nan"), 1j):
        with pytest.raises(PlannerInputError, match="height"):
            as_height(bad)


def test_flat_ground_and_forbidden_polygons():
    """FlatGround: height z, normal +z, every foothold allowed; ForbiddenPolygons refuses a
    foothold inside a polygon or nearer than the clearance to it, keeps the ground's
    height."""
    xy = np.array([[0.0, 0.0], [3.0, -2.0]])
    ground = FlatGround(0.1)
    assert isinstance(ground, Terrain)
    assert ground.height_at(xy).tolist() == [0.1, 0.1]
    assert ground.normal_at(xy).tolist() == [[0.0, 0.0, 1.0]] * 2
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    hole = ForbiddenPolygons((square[::-1],), clearance_m=0.05, ground=ground)  # clockwise too
    assert hole.height_at(xy).tolist() == [0.1, 0.1]
    assert not hole.allows_foothold(np.array([0.5, 0.5, 0.0]))
    assert not hole.allows_foothold(np.array([1.04, 0.5, 0.0]))
    assert hole.allows_foothold(np.array([1.06, 0.5, 0.0]))
    assert hole.clearance(np.array([0.5, 0.2, 0.0])) == pytest.approx(-0.2, abs=1e-12)
    with pytest.raises(PlannerInputError, match="polygon"):
        ForbiddenPolygons((square[:2],))


def test_the_ditch_terrain_refuses_what_the_ditch_clearance_refuses():
    """A foothold is refused by the ditch's terrain exactly when Ditch.clearance (rounded to
    1 nm as sampled footholds are) is below the foot clearance."""
    from planner.studies.ditch import FOOT_CLEARANCE_M, Ditch

    ditch = Ditch(1.5, 0.15)
    terrain = ditch.terrain(FOOT_CLEARANCE_M)
    rng = np.random.default_rng(3)
    ys = np.concatenate([rng.uniform(1.3, 1.9, 400), [1.49, 1.66, 1.5 - FOOT_CLEARANCE_M]])
    for y in ys:
        foot = np.array([rng.uniform(-2, 2), y, 0.0])
        expected = ditch.clearance(np.round(foot[None, :2], 9))[0] >= FOOT_CLEARANCE_M
        assert terrain.allows_foothold(foot) == expected, y


def test_foothold_check_is_a_terrain_and_a_refusal_is_named(silo4):
    """foothold_check= is CheckedFootholds: a check refusing every foothold makes every gait
    fail with FootholdRefused, its exception kept as the cause."""

    def refuse(foot):
        raise ValueError("no")

    with pytest.raises(FootholdRefused, match="refused") as info:
        plan_path(silo4, ONE, 0.4, samples_per_unit=2, foothold_check=refuse)
    assert isinstance(info.value.__cause__, ValueError)
    with pytest.raises(FootholdRefused):
        plan_path(silo4, ONE, 0.4, samples_per_unit=2, terrain=CheckedFootholds(refuse))
    with pytest.raises(PlannerInputError, match="terrain"):
        plan_path(silo4, ONE, 0.4, samples_per_unit=2, terrain="flat")


def test_flat_ground_gives_the_plan_of_no_terrain(silo4):
    plain = plan_path(silo4, ONE, 0.4, samples_per_unit=2)
    flat = plan_path(silo4, ONE, 0.4, samples_per_unit=2, terrain=FlatGround())
    assert np.array_equal(plain.trajectory.q, flat.trajectory.q)


class _Step:
    def __init__(self, t_end: float) -> None:
        self.t_end = t_end


@dataclass(frozen=True)
class _FakePlan:
    gait: str
    steps: tuple
    fallback_reason: str | None = None


class _FakeGait:
    """A gait taking ``units`` (or failing with ``error``), recording the limits it got."""

    def __init__(self, name: str, units: float | None = None, error: Exception | None = None):
        self.name, self.label, self.units, self.error, self.limits = name, name, units, error, []

    def plan(self, request, slower_than=None):
        from planner.gaits.base import NotFaster

        self.limits.append(slower_than)
        if self.error is not None:
            raise self.error
        if slower_than is not None and self.units >= slower_than:
            raise NotFaster(self.units)
        return _FakePlan(self.name, (_Step(self.units),))


def test_fastest_keeps_the_least_time_the_first_on_a_tie_and_says_why():
    """Fastest builds each gait with the time in hand as its limit; a tie keeps the earlier
    gait; the failures of gaits before the winner are its fallback_reason; when all fail,
    GaitRefused lists every reason (a FootholdRefused of the last one propagates)."""
    from planner.errors import GaitRefused
    from planner.gaits.combinators import Fallback, Fastest

    crawl, creep = _FakeGait("crawl", 10.0), _FakeGait("creep", 10.0)
    assert Fastest((crawl, creep)).plan(None).gait == "crawl" and creep.limits == [10.0]
    faster = _FakeGait("creep", 8.0)
    assert Fastest((_FakeGait("crawl", 10.0), faster)).plan(None).gait == "creep"
    failed = _FakeGait("crawl", error=PlanningError("no step"))
    plan = Fastest((failed, _FakeGait("creep", 8.0))).plan(None)
    assert plan.gait == "creep" and plan.fallback_reason == "crawl: planning: no step"
    both = Fastest((failed, _FakeGait("creep", error=PlanningError("stuck"))))
    with pytest.raises(GaitRefused) as info:
        both.plan(None)
    assert info.value.reasons == ("crawl: planning: no step", "creep: planning: stuck")
    refused = _FakeGait("creep", error=FootholdRefused((0.0, 1.0, 0.0)))
    with pytest.raises(FootholdRefused):
        Fastest((failed, refused)).plan(None)
    plan = Fallback(both, _FakeGait("facing", 30.0)).plan(None)
    assert plan.gait == "facing"
    assert plan.fallback_reason == "crawl: planning: no step; creep: planning: stuck"
    with pytest.raises(FootholdRefused):
        Fallback(refused, _FakeGait("facing", 30.0)).plan(None)


class _BoundedGait(_FakeGait):
    """A _FakeGait with a lower bound ``bound`` [units] on its time (base.fewest_units)."""

    def __init__(self, name: str, bound: float, units=None, error=None):
        super().__init__(name, units, error)
        self.bound = bound

    def fewest_units(self, request) -> float:
        return self.bound


def test_fastest_skips_a_last_gait_that_could_only_end_in_not_faster():
    """With ``slower_than``, once a gait stopped as slow as it, a last gait whose bound
    reaches ``slower_than`` is not built: building it (NotFaster, or refused) ends in the
    same NotFaster, so Fallback does not fall back either way. It is still built when its
    bound is below the limit, when no earlier gait stopped (a refusal then lets Fallback
    fall back), and with no limit."""
    from planner.gaits.base import NotFaster
    from planner.gaits.combinators import Fallback, Fastest

    for error in (None, PlanningError("stuck"), FootholdRefused((0.0, 1.0, 0.0))):
        last = _BoundedGait("creep", 12.0, units=12.0, error=error)
        facing = _FakeGait("facing", 5.0)
        with pytest.raises(NotFaster):
            Fallback(Fastest((_FakeGait("crawl", 13.0), last)), facing).plan(None, slower_than=12.0)
        assert last.limits == [] and facing.limits == []
    below = _BoundedGait("creep", 11.0, units=11.5)
    assert Fastest((_FakeGait("crawl", 13.0), below)).plan(None, slower_than=12.0).gait == "creep"
    refused_first = _BoundedGait("creep", 12.0, error=PlanningError("stuck"))
    crawl_refused = _FakeGait("crawl", error=PlanningError("no step"))
    plan = Fallback(Fastest((crawl_refused, refused_first)), _FakeGait("facing", 5.0)).plan(
        None, slower_than=12.0
    )
    assert plan.gait == "facing" and refused_first.limits == [12.0]
    unlimited = _BoundedGait("creep", 12.0, units=12.0)
    assert Fastest((_FakeGait("crawl", 13.0), unlimited)).plan(None).gait == "creep"
    assert unlimited.limits == [13.0]


def test_fastest_stops_with_the_least_of_its_gaits_stops():
    """With ``slower_than``, the NotFaster of Fastest carries the least time any of its
    gaits stopped at, or the bound of a last gait it did not build: a lower bound on every
    gait's time (the height search plans a stopped height again only below it)."""
    from planner.gaits.base import NotFaster
    from planner.gaits.combinators import Fastest

    with pytest.raises(NotFaster) as info:
        Fastest((_FakeGait("crawl", 12.5), _FakeGait("creep", 13.0))).plan(None, slower_than=12.0)
    assert info.value.args == (12.5,)
    skipped = _BoundedGait("creep", 12.2, units=14.0)
    with pytest.raises(NotFaster) as info:
        Fastest((_FakeGait("crawl", 13.0), skipped)).plan(None, slower_than=12.0)
    assert info.value.args == (12.2,) and skipped.limits == []
