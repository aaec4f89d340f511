"""The ROS 2 bag read with the MCAP project's own reader (the ``mcap`` package, a test
dependency only): an independent implementation of the file format. Every topic's messages
come in strictly increasing log time, carry a ROS 2 message schema, and /joint_states holds
the run's joint positions bit for bit (decoded with rosbags' CDR deserialiser)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from test_ros2_export import bag, run, walk  # noqa: F401  (module fixtures: one tiny plan)

from planner.trajectory.samples import Trajectory
from viz.export.ros2_messages import typestore

mcap_reader = pytest.importorskip("mcap.reader")


def test_mcap_reader_sees_monotonic_topics_and_the_plan(bag: Path, walk: Trajectory) -> None:
    [path] = list(bag.glob("*.mcap"))
    store = typestore()
    times: dict[str, list[int]] = {}
    positions = []
    with path.open("rb") as stream:
        reader = mcap_reader.make_reader(stream)
        summary = reader.get_summary()
        assert summary is not None and summary.statistics.message_count > 2 * len(walk)
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            assert schema is not None and schema.encoding == "ros2msg", channel.topic
            assert channel.message_encoding == "cdr"
            times.setdefault(channel.topic, []).append(message.log_time)
            if channel.topic == "/joint_states":
                decoded = store.deserialize_cdr(message.data, schema.name)
                positions.append(np.asarray(decoded.position))
    assert {"/joint_states", "/tf", "/tf_static", "/robot_description"} <= set(times)
    for topic, stamps in times.items():
        assert all(b > a for a, b in zip(stamps, stamps[1:])), topic
    assert len(times["/joint_states"]) == len(walk)
    assert np.array_equal(np.vstack(positions), walk.q)
