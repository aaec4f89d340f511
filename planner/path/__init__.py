"""planner.path.plan_path."""
