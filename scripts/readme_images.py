"""Regenerate the README's pictures from the code: plan the thesis straight path at
h = 0.4 m, screenshot animation.html at t = 19 s (the follow camera, mid-swing of a
continuous-crawl transfer: the body moves while leg LH swings) and the top of
report.html in headless Chromium, copy the path and joint plots.

    .venv/bin/python scripts/readme_images.py
    # writes docs/img/animation.png, report.png, path.png, joint_positions.png
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from viz.cli.main import main as silo4

ROOT = Path(__file__).resolve().parent.parent
IMG = ROOT / "docs" / "img"


def screenshot(
    html: Path, out: Path, t_s: float | None, size: tuple[int, int] = (1000, 640)
) -> None:
    """Headless Debian Chromium, network off, paused at ?t=t_s (stack-notes.md flags)."""
    query = "" if t_s is None else f"?t={t_s}"
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run(
            [
                "chromium",
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-quic",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                "--hide-scrollbars",
                f"--user-data-dir={profile}",
                f"--screenshot={out}",
                f"--window-size={size[0]},{size[1]}",
                "--virtual-time-budget=4000",
                f"{html.resolve().as_uri()}{query}",
            ],
            check=True,
            capture_output=True,
            timeout=120,
        )


if __name__ == "__main__":
    IMG.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        os.chdir(tmp)  # report.html shows the command: `--out out/straight`, as `./run demo`
        run = Path(tmp) / "out" / "straight"
        code = silo4(
            [
                "plan",
                "--waypoints",
                "0,1 1,1 0,2 0,3",
                "--height",
                "0.4",
                "--start-heading",
                "90",
                "--out",
                "out/straight",
            ]
        )
        if code != 0:
            sys.exit(code)
        screenshot(run / "animation.html", IMG / "animation.png", t_s=19.0)
        screenshot(run / "report.html", IMG / "report.png", t_s=None, size=(1000, 1400))
        shutil.copy(run / "path.png", IMG / "path.png")
        shutil.copy(run / "joint_positions.png", IMG / "joint_positions.png")
    print(f"wrote {IMG}/animation.png, report.png, path.png, joint_positions.png")
