"""viz.report.page."""
