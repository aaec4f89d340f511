"""Drawing a plan's time histories: a min/max envelope of at most MAX_PLOT_POINTS vertices
per line (so peaks survive and SVGs stay small), and the runs of phase labels (transfers,
rotations) shaded behind the lines."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.axes import Axes

#: Most vertices drawn per line (min/max envelope beyond this).
MAX_PLOT_POINTS = 4000
SHADE_TRANSFER = "#9ecae1"
SHADE_ROTATE = "#fdd0a2"


def envelope_indices(
    n: int, max_points: int = MAX_PLOT_POINTS, y: np.ndarray | None = None
) -> np.ndarray:
    """Indices of a min/max envelope of ``y`` (N,) with at most ``max_points`` vertices.

    Each of max_points // 2 bins keeps its smallest and largest sample (so peaks are drawn);
    the first and last samples are always kept. Without ``y``, a uniform stride.
    """
    if n <= max_points:
        return np.arange(n)
    bins = max(1, max_points // 2 - 1)
    width = int(np.ceil(n / bins))
    if y is None:
        return np.unique(np.concatenate([np.arange(0, n, width), [n - 1]]))
    padded = np.concatenate([y, np.full(bins * width - n, y[-1])]).reshape(bins, width)
    base = np.arange(bins) * width
    idx = np.concatenate([base + padded.argmin(axis=1), base + padded.argmax(axis=1), [0, n - 1]])
    return np.unique(np.clip(idx, 0, n - 1))


class PhaseSpans:
    """Runs of phase labels, computed once per trajectory and shared by every figure.

    The labels are reduced to their unique values once (``np.unique`` with the inverse), so
    asking for the transfer spans of each of 4 legs on 6 figures costs 4 small lookups, not
    24 passes over N labels.

    Args:
        t: x positions of the samples (e.g. time units), shape (N,).
        phase: phase label per sample, shape (N,).
    """

    def __init__(self, t: np.ndarray, phase: np.ndarray) -> None:
        self.t = np.asarray(t, dtype=float)
        self.labels, self.inverse = np.unique(np.asarray(phase).astype(str), return_inverse=True)
        self.words = [label.split() for label in self.labels]
        self._cache: dict[tuple[str, str | None], list[tuple[float, float]]] = {}

    def spans(self, match: str, leg: str | None = None) -> list[tuple[float, float]]:
        """(start, width) of the runs whose label contains the word ``match`` (and ``leg``)."""
        key = (match, leg)
        if key not in self._cache:
            ids = [i for i, w in enumerate(self.words) if match in w and (leg is None or leg in w)]
            mask = np.isin(self.inverse, ids).astype(np.int8)
            edges = np.flatnonzero(np.diff(np.concatenate([[0], mask, [0]])))
            starts, ends = edges[::2], np.minimum(edges[1::2], len(self.t) - 1)
            self._cache[key] = [
                (float(self.t[s]), float(self.t[e] - self.t[s]))
                for s, e in zip(starts, ends, strict=True)
            ]
        return self._cache[key]


def phase_spans(
    t: np.ndarray, phase: np.ndarray, match: str, leg: str | None = None
) -> list[tuple[float, float]]:
    """(start, width) of the runs of samples whose phase label matches.

    A label matches when it contains the word ``match`` (e.g. "transfer", "rotate") and, if
    ``leg`` is given, also the word ``leg`` ("creep transfer LF" matches transfer/LF).
    """
    return PhaseSpans(t, phase).spans(match, leg)


def shade_phases(ax: Axes, spans: PhaseSpans, leg: str | None) -> None:
    """Shade transfer phases (of ``leg``, or all) blue and body rotations orange."""
    trans = ax.get_xaxis_transform()
    ax.broken_barh(
        spans.spans("transfer", leg),
        (0, 1),
        transform=trans,
        facecolor=SHADE_TRANSFER,
        alpha=0.5,
        zorder=0,
        label="transfer",
    )
    rotate = spans.spans("rotate")
    if rotate:
        ax.broken_barh(
            rotate,
            (0, 1),
            transform=trans,
            facecolor=SHADE_ROTATE,
            alpha=0.5,
            zorder=0,
            label="rotate",
        )


def plot_envelope(ax: Axes, t: np.ndarray, y: np.ndarray, **kwargs: Any) -> None:
    """Plot ``y`` (N,) against ``t`` (N,) through its min/max envelope."""
    idx = envelope_indices(len(t), MAX_PLOT_POINTS, y)
    ax.plot(t[idx], y[idx], linewidth=1.0, **kwargs)
