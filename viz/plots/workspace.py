"""Top view of the default workspace at one body height (like thesis Figs 3.4 and 4.7).

Each leg's reachable ground set (planner/workspace/reach_insect.py: annular sector within
the joint limits and the knee margin, intersected over the swing heights) is shaded, the set
shrunk by the stability-shift reserve is outlined dashed, and the footholds of the creeping
gait along the body x axis (rear, position 2, front) are drawn with the stride. The title
says whether the height is feasible and why not: below or above the feasible range, or a
stride shorter than the minimum; and, where it is feasible but the stride across the body is
short and the stance cannot turn, that the robot walks there only along its body
(planner/workspace/heights.py walks_any_direction).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from planner.outputs.files import write_atomic

#: Colours of the legs LF, RF, LH, RH.
LEG_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red")


def _eroded_outline(s, erosion_m: float, n: int = 48) -> np.ndarray:
    """Boundary (x, y) [m] of the set shrunk by ``erosion_m``: points of the set's polar grid
    that :meth:`ReachableSet.contains` keeps, traced as the outer/inner radius per angle.
    A mammal leg's grid set (planner/workspace/reach_mammal.py) traces its own."""
    if hasattr(s, "eroded_outline"):
        return s.eroded_outline(erosion_m)
    phi = np.linspace(s.yaw_lower_rad, s.yaw_upper_rad, n)
    r = np.linspace(max(s.radius_lower_m, 0.0), max(s.radius_upper_m, 0.0), 200)
    rr, pp = np.meshgrid(r, phi)
    pts = s.position_hip_in_base + np.stack([rr * np.cos(pp), rr * np.sin(pp)], axis=-1)
    inside = s.contains(pts.reshape(-1, 2), erosion_m).reshape(rr.shape)
    rows = np.flatnonzero(inside.any(axis=1))
    if rows.size == 0:
        return np.zeros((0, 2))
    outer = np.array([pts[i, np.flatnonzero(inside[i])[-1]] for i in rows])
    inner = np.array([pts[i, np.flatnonzero(inside[i])[0]] for i in rows[::-1]])
    return np.vstack([outer, inner, outer[:1]])


def workspace_figure(robot, height: float):  # noqa: ANN201 (matplotlib Figure)
    """The figure for body height ``height`` [m] (module docstring)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from planner.workspace.layout import planning_robot, reach_layout, walks_any_direction

    layout = reach_layout(robot, height)
    robot = planning_robot(robot)
    lam_x, lam_y = layout.stride_m
    rng = layout.feasible_range
    fig, ax = plt.subplots(figsize=(7.5, 7.5))
    hips = np.array([leg.position_hip_in_base[:2] for leg in robot.legs])
    body = np.vstack([hips[[0, 1, 3, 2]], hips[:1]])
    ax.plot(body[:, 0], body[:, 1], color="0.3", lw=1.5, label="hips")
    ax.plot(0.0, 0.0, "k+", ms=12, mew=2, label="body CoG")
    for k, (leg, s) in enumerate(zip(robot.legs, layout.sets)):
        colour = LEG_COLOURS[k]
        ring = s.outline()
        if ring.size:
            ax.fill(ring[:, 0], ring[:, 1], color=colour, alpha=0.15, lw=0)
            ax.plot(ring[:, 0], ring[:, 1], color=colour, lw=1.0, label=f"{leg.name} reachable set")
        eroded = _eroded_outline(s, layout.erosion_m)
        if eroded.size:
            ax.plot(eroded[:, 0], eroded[:, 1], color=colour, lw=1.0, ls="--")
        mid = layout.position_mid_in_base[k, :2]
        feet = mid + np.array([[-lam_x / 2, 0.0], [0.0, 0.0], [lam_x / 2, 0.0]])
        if lam_x > 0:
            ax.plot(feet[:, 0], feet[:, 1], "o-", color=colour, ms=5, lw=2)
            ax.annotate(
                "",
                xy=feet[2],
                xytext=feet[0],
                arrowprops=dict(arrowstyle="->", color=colour, lw=1.5),
            )
        ax.plot(*mid, "s", color=colour, ms=6)
    verdict = "feasible"
    if rng is None:
        verdict = "no feasible height for this robot"
    elif not rng[0] <= height <= rng[1]:
        verdict = f"outside the feasible range [{rng[0]:.4g}, {rng[1]:.4g}] m"
    if layout.hip_clearance_m < layout.min_hip_clearance_m - 1e-9:
        verdict += (
            f"; hips {layout.hip_clearance_m:.3f} m above the ground "
            f"< {layout.min_hip_clearance_m:.2f} m"
        )
    if lam_x < layout.min_stride_m:
        verdict += f"; stride {lam_x:.3f} m < {layout.min_stride_m:.2f} m"
    elif not walks_any_direction(robot, height):
        verdict += (
            f"; along the body only: stride y {lam_y:.3f} m < {layout.min_stride_m:.2f} m and "
            f"spin {np.degrees(layout.psi_max_rad):.1f}° per cycle "
            f"< {np.degrees(layout.min_spin_rad):.0f}° (a path across the body is refused)"
        )
    rng_text = "" if rng is None else f", range [{rng[0]:.4g}, {rng[1]:.4g}] m"
    ax.set_title(
        f"{robot.name}: h = {height:.3g} m, stride x {lam_x:.3f} m, y {lam_y:.3f} m, "
        f"spin {np.degrees(layout.psi_max_rad):.1f}° per cycle{rng_text}\n"
        f"{verdict}\n(dashed: set shrunk by the {layout.erosion_m:.2f} m shift "
        f"reserve; dots: footholds rear, 2, front)",
        fontsize=9,
    )
    ax.set_xlabel("x in base frame B [m] (forward)")
    ax.set_ylabel("y in base frame B [m] (left)")
    ax.set_aspect("equal")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=7)
    fig.tight_layout()
    return fig


def write_workspace_png(path: str | Path, robot, height: float) -> Path:
    """Draw the workspace at ``height`` [m] into ``path`` (PNG, written atomically)."""
    import matplotlib.pyplot as plt

    fig = workspace_figure(robot, height)
    try:
        write_atomic(path, lambda tmp: fig.savefig(tmp, format="png", dpi=110))
    finally:
        plt.close(fig)
    return Path(path)
