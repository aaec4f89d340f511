"""No degraded fallback (issue 21 item 6; planner/path/at_height.py, ``strict=True``): the
default meets its tolerance (E_n, eq 6.1) with q'' continuous, or fails naming the reason;
q'' continuity measured on the samples (planner/trajectory/continuity.py); a swing the
samples refuse gets a foothold from the reach set (planner/gaits/foothold_replacement.py)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from planner import plan_path
from planner.errors import PlanningError
from planner.gaits.foothold_replacement import OFFSETS_M, FootholdReplacements
from planner.path.at_height import check_continuous_qdd, check_tolerance
from planner.path.metrics import compute_metrics
from planner.trajectory.continuity import MIN_STEP_SAMPLES, qdd_jump, still

PATH = [(0.5, 0.3), (0.2, 0.8)]


@pytest.fixture(scope="module")
def default_and_plain(silo4):
    return (
        plan_path(silo4, PATH, 0.4),
        plan_path(silo4, PATH, 0.4, gait="plain"),
    )


def test_qdd_continuity_is_measured_on_the_samples(default_and_plain):
    """The default's quintic profiles pass; the plain creeping and spinning gait (the
    thesis's cosine blends, q'' at its peak where a step ends) is found jumping at a step
    boundary, named with joint and step."""
    default, plain = default_and_plain
    assert default.gait in ("crawl", "creep")
    assert qdd_jump(default.trajectory, default.steps) is None
    check_continuous_qdd(default)
    jump = qdd_jump(plain.trajectory, plain.steps)
    assert jump is not None and jump.jump > 10 * jump.allowed
    boundary = int(round(plain.steps[jump.step_index].t_start * 100))
    assert jump.sample == boundary
    with pytest.raises(PlanningError, match=r"q'' of \w+ jumps by .* start of step \d+"):
        check_continuous_qdd(plain)


def test_a_qdd_step_inserted_into_a_smooth_plan_is_found(default_and_plain):
    """A jump of a quarter of a joint's peak |q''| from a step boundary on (a cosine blend
    stops with q'' at its peak) is found at that boundary, at every boundary (steps of
    MIN_STEP_SAMPLES samples or still ones, the stands: every step at 100 samples per unit);
    the same size reached over the step by a quintic (q'' continuous) is not."""
    plan = default_and_plain[0]
    tr = plan.trajectory
    j = 4
    size = 0.25 * float(np.abs(tr.qdd[:, j]).max())
    judged = [
        k
        for k in range(1, len(plan.steps))
        if all(s.duration * 100 >= MIN_STEP_SAMPLES or still(s) for s in plan.steps[k - 1 : k + 1])
    ]
    assert len(judged) == len(plan.steps) - 1
    assert sum(still(s) for s in plan.steps) >= 2  # the start stand and a swap stand
    for k in judged:
        i = int(round(plan.steps[k].t_start * 100))
        qdd = tr.qdd.copy()
        qdd[i:, j] += size
        jump = qdd_jump(replace(tr, qdd=qdd), plan.steps)
        assert jump is not None and (jump.sample, jump.joint) == (i, tr.joint_names[j]), k
        ramp = tr.qdd.copy()  # the same size reached smoothly over the step, then held
        n = int(round(plan.steps[k].t_end * 100)) - i
        tau = np.linspace(0.0, 1.0, n + 1)
        ramp[i : i + n + 1, j] += size * (10 * tau**3 - 15 * tau**4 + 6 * tau**5)
        ramp[i + n + 1 :, j] += size
        assert qdd_jump(replace(tr, qdd=ramp), plan.steps) is None, k


def test_a_plan_off_its_tolerance_is_refused_naming_the_waypoint(default_and_plain):
    plan = default_and_plain[0]
    moved = plan.position_walked_in_world + np.array([[0.0, 0.0], [0.03, 0.0]])
    check_tolerance(plan)
    with pytest.raises(PlanningError, match=r"E_n 15.0 mm > 10 mm \(waypoint 1 .* 30.0 mm"):
        check_tolerance(replace(plan, position_walked_in_world=moved))


def test_the_thesis_preset_is_not_held_to_the_tolerance(silo4):
    """§5.5 creeps round(d / λ) cycles and misses by design: strict planning leaves
    the thesis preset's plans as they were."""
    wp = [(0.0, 0.7)]
    strict = plan_path(silo4, wp, 0.4, workspace="thesis", strict=True)
    loose = plan_path(silo4, wp, 0.4, workspace="thesis")
    assert strict.gait == "thesis"
    np.testing.assert_array_equal(strict.trajectory.q, loose.trajectory.q)


def test_a_replacement_is_only_for_a_recorded_swing_and_runs_out():
    r = FootholdReplacements()
    assert not r.replace_at(None, None) and not r.replace_at(3.0, None)
    assert np.all(np.diff(np.hypot(*OFFSETS_M.T)) >= 0)  # nearest first
    assert np.allclose(r.offset(0), 0.0)


#: Corpus case #22 of benchmarks/bench_corpus.py (--cases 30, seed 20261202): solo12. Before
#: the foothold replacement the creep was refused by its samples (whole-body CoM margin
#: 19.797 mm under the 20 mm threshold less the 0.2 mm slack, swing of RF at t 1.98 units) and
#: "auto" fell back to facing the path, E_n 12.2 mm over the 10 mm tolerance.
SOLO12_22 = dict(
    waypoints=[
        (0.5478493317152604, 0.18212379107410584),
        (0.8032990033065246, -0.0001909756561920828),
        (0.7775412871655839, -0.5145344556352075),
        (1.4836936196614636, -0.16429402162922468),
    ],
    height=0.2803,
    start_heading=2.442989100116886,
)


def test_corpus_case_that_fell_back_now_meets_its_tolerance_with_continuous_qdd(solo12):
    robot = solo12
    plan = plan_path(
        robot,
        SOLO12_22["waypoints"],
        SOLO12_22["height"],
        start_heading=SOLO12_22["start_heading"],
    )
    assert plan.gait == "creep"
    assert compute_metrics(plan)["normalized_error_m"] <= plan.tolerance
    assert qdd_jump(plan.trajectory, plan.steps) is None
    assert not any(s.label.startswith("spin") for s in plan.steps)


def test_facing_the_path_as_the_fallback_keeps_qdd_continuous(mantis):
    """Where neither gait without turning finds a step (mantis at 0.47 m has no sideways
    stride), strict planning faces the path on the quintic profiles: q'' continuous, within the
    tolerance, and the plan says why (the cosine blends of "facing" by name jump, above)."""
    plan = plan_path(
        mantis, [(0.16, -0.71), (-0.78, -0.25)], 0.47, start_heading=-1.36, strict=True
    )
    assert plan.gait == "facing"
    assert "no stride along a body axis" in plan.fallback_reason
    assert qdd_jump(plan.trajectory, plan.steps) is None
    assert compute_metrics(plan)["normalized_error_m"] <= plan.tolerance
    by_name = plan_path(
        mantis, [(0.16, -0.71), (-0.78, -0.25)], 0.47, start_heading=-1.36, gait="facing"
    )
    assert qdd_jump(by_name.trajectory, by_name.steps) is not None
