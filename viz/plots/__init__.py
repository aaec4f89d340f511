"""viz.plots.run_plots."""
