"""A plan's output folder: the names of the modules that write and read it, in one place.

- planner/outputs/run_folder.py: ``write_run`` (the folder, atomically), ``run_inputs``;
- planner/outputs/trajectory_csv.py / trajectory_npz.py: the trajectory files;
- planner/outputs/documents.py: plan.json / metrics.json, ``to_jsonable``;
- planner/outputs/root_pose.py: the URDF root link's pose from the planner's body frame.

docs/outputs.md describes every file and column.
"""

from __future__ import annotations

from planner.outputs.documents import (
    OPTION_DEFAULTS,
    RUN_FORMAT,
    plan_document,
    plan_inputs,
    read_run_inputs,
    to_jsonable,
)
from planner.outputs.root_pose import RootPose, root_pose_in_world
from planner.outputs.run_folder import (
    RUN_DATA_FILES,
    ExtraWriter,
    check_output_folder,
    run_inputs,
    write_run,
)
from planner.outputs.trajectory_csv import (
    CSV_SIGNIFICANT_DIGITS,
    ROOT_COLUMNS,
    read_trajectory_csv,
    trajectory_columns,
    write_trajectory_csv,
)
from planner.outputs.trajectory_npz import (
    NPZ_COMPRESS_LEVEL,
    read_root_pose_npz,
    read_trajectory_npz,
    write_trajectory_npz,
)

__all__ = [
    "CSV_SIGNIFICANT_DIGITS",
    "NPZ_COMPRESS_LEVEL",
    "OPTION_DEFAULTS",
    "ROOT_COLUMNS",
    "RUN_DATA_FILES",
    "RUN_FORMAT",
    "ExtraWriter",
    "RootPose",
    "check_output_folder",
    "plan_document",
    "plan_inputs",
    "read_root_pose_npz",
    "read_run_inputs",
    "read_trajectory_csv",
    "read_trajectory_npz",
    "root_pose_in_world",
    "run_inputs",
    "trajectory_columns",
    "to_jsonable",
    "write_run",
    "write_trajectory_csv",
    "write_trajectory_npz",
]
