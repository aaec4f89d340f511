"""viz.cli.main."""
