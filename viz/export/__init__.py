"""viz.export."""
