"""Thesis-style plots: the right files, deterministic bytes, peaks kept, clear errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_animation import synthetic_trajectory  # tests/ is on sys.path (pytest rootdir)

from planner.trajectory.samples import Trajectory
from silo4kin import Robot, Silo4Error
from viz.plots.figure_names import figure_stems, parse_window
from viz.plots.run_plots import write_plots
from viz.plots.time_series import PhaseSpans, envelope_indices, phase_spans
from viz.report.page import write_report

BASE_STEMS = [
    "joint_positions",
    "joint_velocities",
    "joint_accelerations",
    "path",
    "stability_margin",
    "cycle_cartesian",
]


@pytest.fixture(scope="module")
def walk(silo4: Robot) -> Trajectory:
    return synthetic_trajectory(silo4, n_units=8.0, samples_per_unit=50)


def test_files_per_figure_and_format(walk: Trajectory, tmp_path: Path) -> None:
    """One PNG per figure by default; SVG too on request; no torque figures without
    torques; folder created; figure_stems() announces exactly what is written."""
    out = tmp_path / "new" / "plots"
    paths = write_plots(out, walk, waypoints_in_world=[[1.0, 1.0], [0.0, 2.0]])
    assert [p.name for p in paths] == [f"{s}.png" for s in BASE_STEMS]
    assert figure_stems(walk) == BASE_STEMS
    paths = write_plots(out, walk, formats=("png", "svg"))
    assert [p.name for p in paths] == [f"{s}.{f}" for s in BASE_STEMS for f in ("png", "svg")]
    for p in paths:
        head = p.read_bytes()[:8]
        assert head.startswith(b"\x89PNG") if p.suffix == ".png" else b"<?xml" in head
    # no temps; the manifest lists what was written, so the second call could replace it
    assert sorted(x.name for x in out.iterdir()) == sorted(
        [*(p.name for p in paths), ".silo4-files"]
    )


def test_torque_figures_when_present(walk: Trajectory, tmp_path: Path) -> None:
    """tau adds a torque figure, and each tau part (motion, support) one more."""
    tau_motion, tau_support = 0.3 * walk.q, 2.0 * np.sin(walk.q)
    with_tau = walk.with_torques(
        tau_motion + tau_support, {"motion": tau_motion, "support": tau_support}
    )
    names = [p.name for p in write_plots(tmp_path, with_tau, formats=("png",))]
    assert names[-3:] == ["torques.png", "torques_motion.png", "torques_support.png"]


def test_same_input_same_bytes(walk: Trajectory, tmp_path: Path) -> None:
    """PNG and SVG output is byte-identical for the same trajectory."""
    a = write_plots(tmp_path / "a", walk, formats=("png", "svg"))
    b = write_plots(tmp_path / "b", walk, formats=("png", "svg"))
    for pa, pb in zip(a, b, strict=True):
        assert pa.read_bytes() == pb.read_bytes(), pa.name


@settings(max_examples=40, deadline=None, derandomize=True)
@given(n=st.integers(2, 20000), max_points=st.integers(4, 3000), seed=st.integers(0, 2**16))
def test_envelope_keeps_extremes(n: int, max_points: int, seed: int) -> None:
    """The drawn envelope has at most max_points vertices, starts and ends with the data,
    and contains the global minimum and maximum (peaks are never decimated away)."""
    y = np.random.default_rng(seed).standard_normal(n).cumsum()
    idx = envelope_indices(n, max_points, y)
    assert len(idx) <= max(max_points, 2)
    assert idx[0] == 0 and idx[-1] == n - 1 and np.all(np.diff(idx) > 0)
    assert y[idx].min() == y.min() and y[idx].max() == y.max()


def test_phase_spans_match_words() -> None:
    """Transfer spans of a leg cover exactly the samples labelled with that leg's transfer."""
    t = np.arange(10.0)
    phase = np.array(
        ["body"] * 2 + ["creep transfer LF"] * 3 + ["transfer RF"] * 2 + ["spin rotate"] * 3
    )
    assert phase_spans(t, phase, "transfer", "LF") == [(2.0, 3.0)]
    assert phase_spans(t, phase, "transfer") == [(2.0, 5.0)]
    assert phase_spans(t, phase, "rotate") == [(7.0, 2.0)]
    assert phase_spans(t, phase, "transfer", "LH") == []


def test_bad_inputs(walk: Trajectory, tmp_path: Path) -> None:
    """Unknown format, bad waypoints, a file where the folder should be: Silo4Error."""
    with pytest.raises(Silo4Error, match="choose from"):
        write_plots(tmp_path, walk, formats=("jpg",))
    with pytest.raises(Silo4Error, match="waypoints_in_world"):
        write_plots(tmp_path, walk, waypoints_in_world=[1.0, 2.0, 3.0])
    (tmp_path / "file").write_text("x")
    with pytest.raises(Silo4Error, match="cannot create plot folder"):
        write_plots(tmp_path / "file" / "plots", walk)


def test_report_links_animation_plots_and_metrics(walk: Trajectory, tmp_path: Path) -> None:
    """report.html frames animation.html, shows each PNG by relative path, links the SVGs,
    lists every metric (nested names dotted), and names no network URL."""
    import re

    plots = write_plots(tmp_path, walk, formats=("png", "svg"))
    metrics = {"distance_m": 1.23456, "E_n": 0.0123, "peak": {"qd_rad_s": [1.0, 2.5]}}
    page = write_report(tmp_path, metrics=metrics, plots=plots).read_text()
    assert '<iframe src="animation.html"' in page
    for p in plots:
        assert (f'src="{p.name}"' if p.suffix == ".png" else f'href="{p.name}"') in page
    assert "<td>qd [rad/s]</td><td>1, 2.5</td>" in page  # nested: its own table, with unit
    assert "<td>distance travelled [m]</td><td>1.235</td>" in page
    assert not re.search(r"(?:https?|wss?)://", page)
    inline = write_report(
        tmp_path, metrics={}, plots=plots[:1], animation=None, inline_images=True
    ).read_text()
    assert 'src="data:image/png;base64,' in inline and "<iframe" not in inline
    with pytest.raises(Silo4Error, match="does not exist"):
        write_report(tmp_path / "missing", metrics=metrics)


def test_phase_spans_computed_once_agree_with_a_loop(walk: Trajectory) -> None:
    """PhaseSpans (unique labels once) gives the runs a plain per-sample loop finds."""
    spans = PhaseSpans(walk.time_units, walk.phase)
    for leg in (None, "LF", "RH"):
        got = spans.spans("transfer", leg)
        labels = [str(p).split() for p in walk.phase]
        hit = [("transfer" in w and (leg is None or leg in w)) for w in labels]
        runs, k = [], 0
        while k < len(hit):
            if hit[k]:
                start = k
                while k < len(hit) and hit[k]:
                    k += 1
                end = min(k, len(hit) - 1)
                runs.append((walk.time_units[start], walk.time_units[end] - walk.time_units[start]))
            else:
                k += 1
        assert got == [(float(a), float(b)) for a, b in runs]
        assert got  # the synthetic walk transfers every leg


def test_window_figures(walk: Trajectory, tmp_path: Path) -> None:
    """--window T0:T1 adds joint histories over that window; bad windows are refused."""
    names = [p.name for p in write_plots(tmp_path, walk, window_s=(1.0, 3.0))]
    assert names[-3:] == [
        "joint_positions_window.png",
        "joint_velocities_window.png",
        "joint_accelerations_window.png",
    ]
    assert [n.removesuffix(".png") for n in names] == figure_stems(walk, window=True)
    assert parse_window("10:20.5") == (10.0, 20.5)
    for bad in ("20:10", "a:b", "5", "-1:2"):
        with pytest.raises(Silo4Error, match="--window"):
            parse_window(bad)
    with pytest.raises(Silo4Error, match="outside the plan"):
        write_plots(tmp_path, walk, window_s=(1000.0, 2000.0))


def test_plot_workers_write_the_same_bytes(walk: Trajectory, tmp_path: Path) -> None:
    """Figures drawn by worker processes are byte-identical to in-process ones, in the
    same order; a worker's Silo4Error comes back with its message."""
    from viz.plots.workers import plot_job

    options = {"waypoints_in_world": [[1.0, 1.0]], "formats": ("png",), "window_s": None}
    job = plot_job(walk, workers=2, **options)
    (tmp_path / "w").mkdir()
    job.start(tmp_path / "w")
    assert job.workers == 2 and len(job.running) == 2  # fork is available on Linux
    forked = job.finish(tmp_path / "w")
    local = write_plots(tmp_path / "l", walk, **options)
    assert [p.name for p in forked] == [p.name for p in local]
    for a, b in zip(forked, local, strict=True):
        assert a.read_bytes() == b.read_bytes(), a.name
    bad = plot_job(
        walk, workers=2, waypoints_in_world=np.zeros((2, 5)), formats=("png",), window_s=None
    )
    bad.start(tmp_path / "w")
    with pytest.raises(Silo4Error, match="waypoints_in_world must be finite points of shape"):
        bad.finish(tmp_path / "w")
    assert not bad.running


def test_plot_workers_report_each_figure(walk: Trajectory, tmp_path: Path) -> None:
    """While waiting for a worker, the parent reports every figure once (progress bar)."""
    from viz.plots.workers import plot_job

    job = plot_job(walk, workers=1, waypoints_in_world=None, formats=("png",), window_s=None)
    job.start(tmp_path)
    seen: list[str] = []
    job.finish(tmp_path, on_figure=seen.append)
    assert sorted(seen) == sorted(job.stems) and len(seen) == len(set(seen))


def test_prewarmed_worker_draws_the_same_bytes(
    walk: Trajectory, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """silo4 plan's pre-warmed worker (matplotlib imported while the parent plans) is the one
    given the job and draws the same bytes; a pre-warmed worker that died meanwhile is
    replaced by a fresh fork; one never given a job ends when the parent's pipe closes."""
    from viz.plots import prewarm as plot_prewarm
    from viz.plots.workers import plot_job

    monkeypatch.delenv("SILO4_PLOT_WORKERS", raising=False)
    options = {"waypoints_in_world": [[1.0, 1.0]], "formats": ("png",), "window_s": None}
    local = write_plots(tmp_path / "l", walk, **options)
    plot_prewarm.discard_warm()  # none left by an earlier in-process run
    assert not plot_prewarm._WARM

    plot_prewarm.prewarm()
    assert len(plot_prewarm._WARM) == 1
    warm_proc = plot_prewarm._WARM[0][0]
    job = plot_job(walk, workers=1, **options)
    (tmp_path / "w").mkdir()
    job.start(tmp_path / "w")
    assert job.running[0][0] is warm_proc and not plot_prewarm._WARM
    drawn = job.finish(tmp_path / "w")
    assert [p.name for p in drawn] == [p.name for p in local]
    for a, b in zip(drawn, local, strict=True):
        assert a.read_bytes() == b.read_bytes(), a.name
    assert not warm_proc.is_alive()

    plot_prewarm.prewarm()
    dead = plot_prewarm._WARM[0][0]
    dead.kill()
    dead.join()
    job = plot_job(walk, workers=1, **options)
    (tmp_path / "d").mkdir()
    job.start(tmp_path / "d")
    assert job.running and job.running[0][0] is not dead
    assert [p.name for p in job.finish(tmp_path / "d")] == [p.name for p in local]

    plot_prewarm.prewarm()
    idle, conn = plot_prewarm._WARM.pop()
    conn.close()  # what the parent's exit does to the pipe
    idle.join(timeout=60)
    assert idle.exitcode == 0


@pytest.mark.skipif(not Path("/proc/self/task").exists(), reason="Linux /proc")
def test_a_worker_killed_takes_its_drawing_copy_with_it(walk: Trajectory, tmp_path: Path) -> None:
    """A worker forks a copy of itself drawing every other figure; stopping the run kills the
    worker (SIGKILL), and the copy dies with it (PR_SET_PDEATHSIG): no figure appears in the
    folder after the stop (an orphaned copy would go on drawing into it)."""
    import time

    from viz.plots.workers import plot_job

    job = plot_job(walk, workers=1, waypoints_in_world=None, formats=("png",), window_s=None)
    job.start(tmp_path)
    worker = job.running[0][0].pid
    children: list[int] = []
    deadline = time.monotonic() + 30.0
    while not children and time.monotonic() < deadline:
        children = [
            int(p) for p in Path(f"/proc/{worker}/task/{worker}/children").read_text().split()
        ]
    assert children, "the worker forked no drawing copy"
    job.stop()
    before = sorted(p.name for p in tmp_path.glob("*.png"))

    def running(pid: int) -> bool:
        stat = Path(f"/proc/{pid}/stat")
        try:
            return stat.read_text().split(") ")[1].split()[0] not in ("Z", "X")
        except (OSError, IndexError):
            return False

    deadline = time.monotonic() + 20.0  # an orphan would finish its share meanwhile
    while running(children[0]) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not running(children[0])
    assert sorted(p.name for p in tmp_path.glob("*.png")) == before


def test_per_leg_figure_names_the_robot_s_own_legs_and_joints(walk: Trajectory) -> None:
    """With go2's joint names the axes read FL, FR, RL, RR and the lines hip, thigh, calf;
    SILO4's read LF, ... and hip yaw, hip pitch, knee."""
    from planner.outputs.leg_labels import LegLabels
    from viz.plots.per_leg import PerLegFigure

    spans = PhaseSpans(walk.time_units, walk.phase)
    go2 = tuple(
        f"{leg}_{j}_joint" for leg in ("FL", "FR", "RL", "RR") for j in ("hip", "thigh", "calf")
    )
    for names, legs, joints in (
        (walk.joint_names, ("LF", "RF", "LH", "RH"), ["hip yaw", "hip pitch", "knee"]),
        (go2, ("FL", "FR", "RL", "RR"), ["hip", "thigh", "calf"]),
    ):
        figure = PerLegFigure(walk.time_units, spans, LegLabels.from_joint_names(names))
        fig = figure.show(np.asarray(walk.q), "Joint positions", "q [rad]")
        assert [ax.get_ylabel().split("\n")[0] for ax in figure.axes] == list(legs)
        texts = [t.get_text() for t in fig.legends[0].get_texts()]
        assert [t for t in texts if t not in ("transfer", "rotate")] == joints
