"""planner.workspace.layout."""
