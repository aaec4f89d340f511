"""A plan's run folder, written atomically: trajectory.csv, trajectory.npz, plan.json,
metrics.json, and whatever ``extra_writers`` add (viz: animation.html, PNG plots).

Folder layout (docs/design.md "Outputs and interfaces", docs/outputs.md)::

    OUT/trajectory.csv   one row per sample (planner/outputs/trajectory_csv.py)
    OUT/trajectory.npz   every Trajectory array, exact (planner/outputs/trajectory_npz.py)
    OUT/plan.json        inputs of the run, stride, the gait that walked and why a faster one
                         was not used, the step list (planner/outputs/documents.py)
    OUT/metrics.json     planner.path.metrics.compute_metrics(plan) and what the pipeline adds

Everything is written into a hidden temporary sibling folder, renamed to OUT only when every
writer has succeeded (planner/outputs/folder_swap.py). An existing OUT is replaced without
asking only when its plan.json records the same inputs (the same command run again); a
folder holding a different run needs ``force=True``; a folder holding files silo4 did not
write is never replaced.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from planner.outputs.atomic import OutputFolderError
from planner.outputs.documents import plan_document, read_run_inputs, to_jsonable, write_json
from planner.outputs.folder_swap import replace_folder_atomically
from planner.outputs.ownership import MANIFEST_NAME
from planner.outputs.root_pose import root_pose_in_world
from planner.outputs.trajectory_csv import write_trajectory_csv
from planner.outputs.trajectory_npz import write_trajectory_npz

#: The files write_run itself writes: the run. A command that reads a run (animate,
#: simulate, export) takes them as its input, so none of its outputs may replace them.
RUN_DATA_FILES = ("trajectory.npz", "plan.json", "metrics.json", "trajectory.csv")


def run_inputs(run_dir: str | Path) -> list[Path]:
    """The run a command reads (:data:`RUN_DATA_FILES` of ``run_dir``), never a target of
    that command (``planner.outputs.files.check_target(inputs=...)``)."""
    return [Path(run_dir) / name for name in RUN_DATA_FILES]


#: A writer the caller adds to the folder (e.g. viz's animation.html); gets the temp folder.
ExtraWriter = Callable[[Path], object]


def check_output_folder(out_dir: Path, inputs: Mapping[str, Any], *, force: bool) -> None:
    """Refuse to replace a folder holding something else (module docstring)."""
    if not out_dir.exists():
        return
    if not out_dir.is_dir():
        raise OutputFolderError(f"output {out_dir} exists and is not a folder", out_dir)
    if not any(out_dir.iterdir()):
        return
    recorded = read_run_inputs(out_dir)
    if recorded is None:
        raise OutputFolderError(
            f"output folder {out_dir} is not empty and is not a silo4 run folder "
            "(no plan.json of ours); choose a new or empty folder",
            out_dir,
        )
    if recorded != to_jsonable(json.loads(json.dumps(to_jsonable(inputs)))) and not force:
        raise OutputFolderError(
            f"output folder {out_dir} holds a different run (its plan.json records other "
            "inputs); use --force to replace it, or choose another folder",
            out_dir,
        )


def write_run(
    out_dir: str | Path,
    plan: Any,
    metrics: Mapping[str, Any],
    *,
    robot_name: str,
    position_body_com_in_root: np.ndarray,
    force: bool = False,
    write_csv: bool = True,
    extra_writers: Sequence[ExtraWriter] = (),
    robot_source: Mapping[str, Any] | None = None,
    options: Mapping[str, Any] | None = None,
) -> dict[str, Path]:
    """Write a plan's output folder atomically; returns file name -> final path.

    Args:
        out_dir: the run folder (created, parents too).
        plan: a ``planner.path.plan_path.Plan``.
        metrics: ``planner.path.metrics.compute_metrics(plan)``.
        robot_name: recorded in plan.json (part of the run's identity).
        position_body_com_in_root: the origin of the planner's body frame B_c in the URDF
            root frame, (3,) [m] (``planner.model.as_planning_model(robot)``): the root
            link's pose in trajectory.csv / .npz (planner/outputs/root_pose.py).
        force: replace a folder that holds a different run.
        write_csv: False skips trajectory.csv (the npz has the same data, exactly).
        extra_writers: callables ``writer(tmp_folder)`` run after our files and before the
            rename (viz adds animation.html / PNGs here); any exception aborts the whole write.
            A writer with ``start(tmp_folder)`` is started before our files (work in the
            background) and one with ``stop()`` is stopped if the write fails.
        robot_source: where the robot came from (file, xacro_args, package_dirs), recorded
            in plan.json under "robot_source" so ``silo4 animate`` can load the same robot.
        options: the caller's requests the plan does not carry (keys of
            :data:`OPTION_DEFAULTS`; a missing key is its default), recorded in plan.json
            "inputs": part of the run's identity.

    Raises:
        OutputFolderError: folder not writable, or holds another run (without force), or
            holds files that are not a run.
    """
    out_dir = Path(out_dir)
    root_pose = root_pose_in_world(plan.trajectory, position_body_com_in_root)
    document = plan_document(plan, robot_name, options)
    if robot_source is not None:
        document["robot_source"] = to_jsonable(robot_source)

    def fill(tmp: Path) -> None:
        try:
            # started inside the try: a signal right after a start must still stop the
            # workers, or they keep drawing into the folder being removed
            for writer in extra_writers:  # e.g. plots drawn by worker processes meanwhile
                start = getattr(writer, "start", None)
                if start is not None:
                    start(tmp)
            if write_csv:
                write_trajectory_csv(tmp / "trajectory.csv", plan.trajectory, root_pose)
            write_trajectory_npz(tmp / "trajectory.npz", plan.trajectory, root_pose)
            write_json(tmp / "plan.json", document, plain=True)  # plan_document's
            write_json(tmp / "metrics.json", metrics)
            for writer in extra_writers:
                writer(tmp)
        except BaseException:
            for writer in extra_writers:  # nothing may keep writing into a removed folder
                stop = getattr(writer, "stop", None)
                if stop is not None:
                    stop()
            raise

    final = replace_folder_atomically(  # checked under the folder lock
        out_dir, fill, check=lambda d: check_output_folder(d, document["inputs"], force=force)
    )
    return {p.name: p for p in sorted(final.iterdir()) if p.name != MANIFEST_NAME}
