"""planner.studies."""
