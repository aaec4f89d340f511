"""sweep: design sweeps (paths x heights x xacro arguments x presets) on Dask.

Layer beside viz: imports silo4kin, planner (and silo4sim, when asked to simulate), never viz;
silo4kin and planner never import it. One configuration is one Dask task returning one row
(silo4sweep.task.plan_row); silo4sweep.engine runs them, silo4sweep.table stores them
(sweep.csv, Parquet), silo4sweep.summary and silo4sweep.report say what they mean. Dask
comes with the optional extra ``silo4kin[sweep]`` and is imported only by silo4sweep.engine.
"""

from .grid import SweepConfig, design_grid, parse_values, parse_xacro_sweeps
from .task import SweepSettings, plan_row

__all__ = [
    "SweepConfig",
    "SweepSettings",
    "design_grid",
    "parse_values",
    "parse_xacro_sweeps",
    "plan_row",
]
