"""Write rough.npy, the height map of rough.yaml (seeded: the same file every time)."""

import numpy as np

SEED = 22
ROWS, COLS = 41, 31  # along y, along x
MAX_HEIGHT_M = 0.03


def rough_heights(seed: int = SEED) -> np.ndarray:
    """Uniform noise smoothed by a 3 x 3 box filter, scaled to 0 .. MAX_HEIGHT_M [m]."""
    noise = np.random.default_rng(seed).uniform(size=(ROWS + 2, COLS + 2))
    smooth = sum(noise[i : i + ROWS, j : j + COLS] for i in range(3) for j in range(3)) / 9.0
    smooth -= smooth.min()
    return MAX_HEIGHT_M * smooth / smooth.max()


if __name__ == "__main__":
    from pathlib import Path

    np.save(Path(__file__).with_name("rough.npy"), rough_heights())
