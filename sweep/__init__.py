"""sweep: design sweeps (paths x heights x xacro arguments x presets) on Dask.

Layer beside viz: imports silo4kin, planner (and sim, when asked to simulate), never viz;
silo4kin and planner never import it. One configuration is one Dask task returning one row
(sweep.task.plan_row); sweep.engine runs them, sweep.table stores them (sweep.csv, Parquet),
sweep.summary and sweep.report say what they mean. Dask comes with the optional extra
``silo4kin[sweep]`` and is imported only by sweep.engine.
"""

from .grid import SweepConfig, design_grid, parse_values, parse_xacro_sweeps
from .task import SweepSettings, plan_row

__all__ = ["SweepConfig", "SweepSettings", "design_grid", "parse_values", "parse_xacro_sweeps",
           "plan_row"]
