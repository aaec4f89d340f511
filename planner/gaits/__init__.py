"""planner.gaits.creep_spin."""
