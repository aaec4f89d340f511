"""The FollowJointTrajectory goal: checked against the action's goal definition, resampled
exactly, and sendable without silo4 (send_goal.py beside it); the CLI's refusals.

rosbags' typestores have no control_msgs, so the goal definition is registered from the
official text (:data:`FOLLOW_JOINT_TRAJECTORY_GOAL`) and the YAML is built into that message
field by field: an unknown key, a missing or mistyped value fails.
"""

from __future__ import annotations

import ast
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from test_ros2_export import run, walk  # noqa: F401  (module fixtures: one tiny plan)

from planner.trajectory.samples import Trajectory
from viz.cli.main import main
from viz.export.goal import (
    DEFAULT_GOAL_RATE_HZ,
    INTERPOLATION_TOLERANCE_RAD,
    GoalFields,
    resampled_indices,
    sender_path,
    write_joint_trajectory_goal,
)
from viz.export.ros2_messages import typestore

pytest.importorskip("rosbags.typesys")

#: The goal of control_msgs/action/FollowJointTrajectory.action (ros-controls/control_msgs,
#: commit 800dd36, the ROS 2 definition with multi-DoF and component tolerances), with
#: JointTolerance.msg (as in Humble; later versions add ``float64 effort``, a field the goal
#: leaves out either way) and JointComponentTolerance.msg; comments and constants left out.
FOLLOW_JOINT_TRAJECTORY_GOAL = {
    "control_msgs/msg/JointTolerance": (
        "string name\nfloat64 position\nfloat64 velocity\nfloat64 acceleration\n"
    ),
    "control_msgs/msg/JointComponentTolerance": (
        "string joint_name\nuint16 component\nfloat64 position\nfloat64 velocity\n"
        "float64 acceleration\n"
    ),
    "control_msgs/action/FollowJointTrajectory_Goal": "trajectory_msgs/JointTrajectory trajectory\n"
    "trajectory_msgs/MultiDOFJointTrajectory multi_dof_trajectory\n"
    "control_msgs/JointTolerance[] path_tolerance\n"
    "control_msgs/JointComponentTolerance[] component_path_tolerance\n"
    "control_msgs/JointTolerance[] goal_tolerance\n"
    "control_msgs/JointComponentTolerance[] component_goal_tolerance\n"
    "builtin_interfaces/Duration goal_time_tolerance\n",
}
GOAL = "control_msgs/action/FollowJointTrajectory_Goal"


@pytest.fixture(scope="module")
def store() -> Any:
    from rosbags.typesys import get_types_from_msg

    store = typestore()
    for name, text in FOLLOW_JOINT_TRAJECTORY_GOAL.items():
        store.register(get_types_from_msg(text, name))
    return store


def build(store: Any, msgtype: str, value: Any) -> Any:
    """The message ``msgtype`` from a YAML mapping, refusing unknown keys and wrong types
    (missing fields take the ROS default: 0, '', [] or a default message)."""
    from rosbags.interfaces import Nodetype

    assert isinstance(value, dict), (msgtype, value)
    fields = dict(store.fielddefs[msgtype][1])
    assert set(value) <= set(fields), f"{msgtype}: unknown keys {set(value) - set(fields)}"
    kwargs = {}
    for name, (kind, spec) in fields.items():
        if name not in value:
            kwargs[name] = default(store, kind, spec)
        elif kind == Nodetype.NAME:
            kwargs[name] = build(store, spec, value[name])
        elif kind == Nodetype.BASE:
            kwargs[name] = base(spec[0], value[name])
        else:  # a sequence or an array
            inner_kind, inner = spec[0]
            items = value[name]
            assert isinstance(items, list), (msgtype, name)
            if inner_kind == Nodetype.BASE and inner[0] == "float64":
                kwargs[name] = np.array([base("float64", v) for v in items], dtype=np.float64)
            elif inner_kind == Nodetype.BASE:
                kwargs[name] = [base(inner[0], v) for v in items]
            else:
                kwargs[name] = [build(store, inner, v) for v in items]
    return store.types[msgtype](**kwargs)


def base(kind: str, value: Any) -> Any:
    if kind == "string":
        assert isinstance(value, str), value
    elif kind.startswith(("int", "uint")):
        assert isinstance(value, int) and not isinstance(value, bool), value
    elif kind == "float64":
        assert isinstance(value, float), value
    return value


def default(store: Any, kind: Any, spec: Any) -> Any:
    from rosbags.interfaces import Nodetype

    if kind == Nodetype.NAME:
        return build(store, spec, {})
    if kind == Nodetype.BASE:
        return "" if spec[0] == "string" else 0
    return np.array([], dtype=np.float64) if spec[0][0] == Nodetype.BASE else []


def goal_of(store: Any, path: Path) -> Any:
    """The goal message built from the YAML file, serialised to CDR and back."""
    message = build(store, GOAL, yaml.safe_load(path.read_text()))
    return store.deserialize_cdr(store.serialize_cdr(message, GOAL), GOAL)


def test_goal_is_a_follow_joint_trajectory_goal(
    walk: Trajectory,
    store: Any,  # noqa: F811
    tmp_path: Path,
) -> None:
    """By default: positions, velocities, accelerations and no effort, every point a plan
    sample bit for bit at its own time, time_from_start increasing; --with-effort adds the
    torques."""
    goal = goal_of(store, write_joint_trajectory_goal(tmp_path / "goal.yaml", walk))
    points = goal.trajectory.points
    keep = resampled_indices(walk.t, DEFAULT_GOAL_RATE_HZ)
    assert list(goal.trajectory.joint_names) == list(walk.joint_names)
    assert len(points) == len(keep) < len(walk)
    np.testing.assert_array_equal([p.positions for p in points], walk.q[keep])
    np.testing.assert_array_equal([p.velocities for p in points], walk.qd[keep])
    np.testing.assert_array_equal([p.accelerations for p in points], walk.qdd[keep])
    assert all(len(p.effort) == 0 for p in points)
    t = np.array([p.time_from_start.sec + 1e-9 * p.time_from_start.nanosec for p in points])
    np.testing.assert_allclose(t, walk.t[keep] - walk.t[0], rtol=0, atol=0.5e-9)
    assert np.all(np.diff(t) > 0)
    assert walk.tau is not None
    with_effort = goal_of(
        store,
        write_joint_trajectory_goal(tmp_path / "goal.yaml", walk, GoalFields(with_effort=True)),
    )
    np.testing.assert_array_equal([p.effort for p in with_effort.trajectory.points], walk.tau[keep])


@pytest.mark.parametrize("rate_hz", [10.0, 50.0, 1000.0])
def test_resampling_keeps_the_nearest_samples(walk: Trajectory, rate_hz: float) -> None:  # noqa: F811
    """The kept samples: first and last, each grid time's nearest (within half the plan's
    sample spacing), none twice; a rate above the plan's keeps every sample."""
    keep = resampled_indices(walk.t, rate_hz)
    t = walk.t - walk.t[0]
    assert keep[0] == 0 and keep[-1] == len(t) - 1 and np.all(np.diff(keep) > 0)
    grid = np.arange(int(t[-1] * rate_hz + 1e-9) + 1) / rate_hz
    nearest = np.min(np.abs(t[keep][None, :] - grid[:, None]), axis=1)
    assert np.all(nearest <= np.max(np.diff(t)) / 2 + 1e-12)
    if rate_hz >= 1 / np.min(np.diff(t)):
        assert len(keep) == len(t)


def test_kept_points_interpolate_to_the_plan(walk: Trajectory) -> None:  # noqa: F811
    """A cubic Hermite of the kept points' (t, q, qd) at 50 Hz meets every plan sample
    within INTERPOLATION_TOLERANCE_RAD: the points a controller spline through are enough."""
    from scipy.interpolate import CubicHermiteSpline

    keep = resampled_indices(walk.t, 50.0)
    spline = CubicHermiteSpline(walk.t[keep], walk.q[keep], walk.qd[keep], axis=0)
    assert np.max(np.abs(spline(walk.t) - walk.q)) < INTERPOLATION_TOLERANCE_RAD


def test_sender_is_written_beside_and_standalone(walk: Trajectory, tmp_path: Path) -> None:  # noqa: F811
    """send_goal.py goes beside the goal, is valid Python, and imports only the standard
    library, PyYAML and ROS 2 packages (no silo4 on the robot)."""
    goal = write_joint_trajectory_goal(tmp_path / "robot" / "goal.yaml", walk)
    script = sender_path(goal)
    assert script.parent == goal.parent and script.name == "send_goal.py"
    tree = ast.parse(script.read_text())
    modules = {
        a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names
    }
    modules |= {
        n.module.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module
    }
    assert modules == {"sys", "rclpy", "yaml", "control_msgs", "rosidl_runtime_py"}
    assert "silo4-files" not in script.read_text()


def test_cli_export_and_refusals(
    run: Path,
    tmp_path: Path,  # noqa: F811
    capsys: pytest.CaptureFixture[str],
) -> None:
    """silo4 export writes bag, goal and sender; an existing bag is kept unless --force; no
    output asked for, a bad --goal-rate or --start-time, or a missing run is exit 2 with one
    line, nothing written."""
    bag, goal = tmp_path / "b.bag", tmp_path / "goal.yaml"
    assert (
        main(
            [
                "export",
                str(run),
                "--ros2",
                str(bag),
                "--goal-yaml",
                str(goal),
                "--goal-rate",
                "20",
                "--with-effort",
            ]
        )
        == 0
    )
    assert "effort" in goal.read_text() and (tmp_path / "send_goal.py").is_file()
    before = sorted(p.name for p in bag.iterdir())
    capsys.readouterr()
    for argv, words in (
        ([str(run), "--ros2", str(bag)], "--force"),
        ([str(run)], "nothing to export"),
        ([str(run), "--goal-yaml", str(tmp_path / "g.yaml"), "--goal-rate", "0"], "--goal-rate"),
        ([str(run), "--ros2", str(tmp_path / "x"), "--start-time", "0"], "--start-time"),
        ([str(tmp_path / "missing"), "--ros2", str(tmp_path / "x")], "missing"),
    ):
        assert main(["export", *argv]) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and words in err, err
    assert sorted(p.name for p in bag.iterdir()) == before
    assert not (tmp_path / "x").exists() and not (tmp_path / "g.yaml").exists()
    assert main(["export", str(run), "--ros2", str(bag), "--force"]) == 0
    # no temp left; .silo4-files records goal.yaml and send_goal.py as silo4's
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == [".silo4-files"]


def test_the_goal_check_catches_a_wrong_goal(store: Any) -> None:
    """The definition check is not vacuous: an unknown key, or a position as text, fails."""
    with pytest.raises(AssertionError, match="unknown keys"):
        build(store, GOAL, {"trajectory": {"point": []}})
    with pytest.raises(AssertionError):
        build(store, GOAL, {"trajectory": {"points": [{"positions": ["0.1"]}]}})


def test_a_users_send_goal_py_is_never_replaced(walk: Trajectory, tmp_path: Path) -> None:  # noqa: F811
    """A send_goal.py of the user's beside the goal refuses the export: neither file written."""
    from silo4kin.errors import Silo4Error

    (tmp_path / "send_goal.py").write_text("mine\n")
    with pytest.raises(Silo4Error, match="send_goal.py"):
        write_joint_trajectory_goal(tmp_path / "goal.yaml", walk)
    assert (tmp_path / "send_goal.py").read_text() == "mine\n"
    assert not (tmp_path / "goal.yaml").exists()


def test_sender_sends_every_point(
    walk: Trajectory,
    tmp_path: Path,  # noqa: F811
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """send_goal.py, run against stand-ins of rclpy, control_msgs and rosidl_runtime_py (no
    ROS here), fills the goal from the YAML, sends it once and exits 0 on SUCCESSFUL."""
    import importlib.util
    import sys
    import types

    sent: list[Any] = []

    def future(value: Any) -> Any:
        return types.SimpleNamespace(result=lambda: value)

    class Client:
        def __init__(self, node: Any, action_type: Any, name: str) -> None:
            self.name = name

        def wait_for_server(self, timeout_sec: float) -> bool:
            return True

        def send_goal_async(self, goal: Any) -> Any:
            sent.append((self.name, goal))
            result = types.SimpleNamespace(
                result=types.SimpleNamespace(error_code=0, error_string="")
            )
            return future(
                types.SimpleNamespace(accepted=True, get_result_async=lambda: future(result))
            )

    class FollowJointTrajectory:
        Goal = types.SimpleNamespace
        Result = types.SimpleNamespace(SUCCESSFUL=0)

    def set_message_fields(message: Any, values: dict) -> None:
        message.trajectory = types.SimpleNamespace(**values["trajectory"])

    node = types.SimpleNamespace(destroy_node=lambda: None)
    stubs = {
        "rclpy": types.SimpleNamespace(
            init=lambda: None,
            create_node=lambda name: node,
            spin_until_future_complete=lambda n, f: None,
            shutdown=lambda: None,
        ),
        "rclpy.action": types.SimpleNamespace(ActionClient=Client),
        "control_msgs": types.SimpleNamespace(),
        "control_msgs.action": types.SimpleNamespace(FollowJointTrajectory=FollowJointTrajectory),
        "rosidl_runtime_py": types.SimpleNamespace(),
        "rosidl_runtime_py.set_message": types.SimpleNamespace(
            set_message_fields=set_message_fields
        ),
    }
    for name, module in stubs.items():
        monkeypatch.setitem(sys.modules, name, module)
    goal = write_joint_trajectory_goal(tmp_path / "goal.yaml", walk)
    spec = importlib.util.spec_from_file_location("send_goal", sender_path(goal))
    assert spec is not None and spec.loader is not None
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    assert script.main(["send_goal.py", str(goal), "/arm/follow_joint_trajectory"]) == 0
    [(action, message)] = sent
    assert action == "/arm/follow_joint_trajectory"
    assert len(message.trajectory.points) == len(resampled_indices(walk.t, DEFAULT_GOAL_RATE_HZ))
    assert script.main(["send_goal.py"]) == 2  # usage
