"""planner.trajectory.samples."""
