"""viz: Meshcat static-HTML animation, matplotlib plots, run reports, and the CLI.

Layer 3 (and the CLI composition root): imports planner and silo4kin.
"""
