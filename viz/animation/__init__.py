"""viz.animation.page."""
