"""planner.outputs."""
