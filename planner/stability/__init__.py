"""planner.stability.margin."""
