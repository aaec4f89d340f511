"""report.html: one page per run: the inputs, the animation, metric tables, the plots.

    write_report("out/run", metrics=metrics, plots=plot_paths, animation="animation.html",
                 inputs={"robot": "silo4", "waypoints_in_world": [(0, 1)], "height_m": 0.4,
                         "workspace": "default", "command": "silo4 plan ..."})

Header: the inputs of the run (robot, waypoints, height, preset, the exact command), then
the run's warnings (none: no list). Tables with labels and units (viz/report/tables.py):
metrics, joint peaks, motor sizing, spins; no raw key, Python dict or list reaches the page.
When the folder holds a physics replay (sim.json, ``silo4 simulate`` or ``plan --simulate``)
the page shows its verdict and links sim.html; ``silo4 simulate`` on a finished run puts that
section into the existing page (:func:`add_physics_section`).

The page sits in the run folder and links its neighbours by relative path (iframe for
``animation.html``, ``<img>`` for the PNGs), so the folder can be moved or mailed as a whole
and opens offline; ``inline_images=True`` embeds the PNGs as data URIs instead. No network
request; the same inputs give the same bytes.
"""

from __future__ import annotations

import base64
import html
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from planner.outputs.files import record_written, write_text_atomically
from silo4kin.errors import Silo4Error
from viz.report.tables import inputs_table, metric_tables, warning_lines

#: The physics section sits between these two comments, so a later replay can replace it.
PHYSICS_START, PHYSICS_END = "<!-- physics -->", "<!-- /physics -->"


def _image_src(path: Path, folder: Path, inline: bool) -> str:
    if inline:
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise Silo4Error(f"cannot read plot {path}: {exc.strerror or exc}") from exc
        return "data:image/png;base64," + base64.b64encode(data).decode("ascii")
    try:
        return path.resolve().relative_to(folder.resolve()).as_posix()
    except ValueError:
        raise Silo4Error(
            f"plot {path} is not inside the report folder {folder}; pass "
            "inline_images=True to embed it"
        ) from None


def write_report(
    out_dir: str | Path,
    *,
    metrics: Mapping[str, Any],
    plots: Sequence[str | Path] = (),
    animation: str | None = "animation.html",
    title: str = "SILO4 plan",
    inline_images: bool = False,
    inputs: Mapping[str, Any] | None = None,
) -> Path:
    """Write ``out_dir/report.html`` (atomically).

    Args:
        out_dir: the run folder (must exist).
        metrics: name -> value, e.g. metrics.json's content (mappings and lists of records
            become tables).
        plots: plot files; PNGs are shown (other formats are linked), in the given order.
        animation: file name of the animation inside out_dir, or None for no animation.
        title: page title.
        inline_images: embed PNGs as data URIs instead of linking them.
        inputs: the run's inputs for the header (robot, waypoints_in_world [m], height_m,
            workspace, unit_time_s, command); None: no inputs table.

    Returns:
        the report path.
    """
    folder = Path(out_dir)
    if not folder.is_dir():
        raise Silo4Error(f"cannot write the report: folder {folder} does not exist")
    parts = [f"<header><h1>{html.escape(title)}</h1>"]
    if inputs:
        parts.append(inputs_table(inputs))
    parts.append("</header>")
    warnings = warning_lines(metrics)
    if warnings:
        parts.append(
            '<h2>Warnings</h2><ul class="warnings">'
            + "".join(f"<li>{html.escape(w)}</li>" for w in warnings)
            + "</ul>"
        )
    parts.append(physics_section(folder))
    if animation is not None:
        src = html.escape(animation, quote=True)
        parts.append(
            f'<h2>Animation</h2><iframe src="{src}" title="animation"></iframe>'
            f'<p class="note">Open <a href="{src}">{html.escape(animation)}</a> full screen; '
            f"add <code>?t=SECONDS</code> to its address to pause at an instant.</p>"
        )
    for section, table in metric_tables(metrics):
        parts.append(f"<h2>{section}</h2>{table}")
    figures, links = [], []
    for plot in map(Path, plots):
        if plot.suffix.lower() == ".png":
            src = html.escape(_image_src(plot, folder, inline_images), quote=True)
            figures.append(
                f'<figure><img src="{src}" alt="{html.escape(plot.stem)}">'
                f"<figcaption>{html.escape(plot.stem.replace('_', ' '))}"
                "</figcaption></figure>"
            )
        else:
            rel = html.escape(_image_src(plot, folder, False), quote=True)
            links.append(f'<a href="{rel}">{html.escape(plot.name)}</a>')
    if figures or links:
        parts.append("<h2>Plots</h2>" + "".join(figures))
        if links:
            parts.append(f'<p class="note">Vector versions: {" · ".join(links)}</p>')
    page = _PAGE.format(title=html.escape(title), body="\n".join(parts))
    path = write_text_atomically(folder / "report.html", page, make_parents=False)
    record_written([path])  # so the same call may replace it (check_target)
    return path


def physics_section(folder: Path) -> str:
    """The physics replay's verdict and a link to sim.html (between PHYSICS_START and
    PHYSICS_END), from ``folder/sim.json``; only the two markers when there is none."""
    try:
        doc = json.loads((folder / "sim.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return PHYSICS_START + PHYSICS_END
    if not isinstance(doc, dict):
        return PHYSICS_START + PHYSICS_END
    reasons = doc.get("reasons") or []
    verdict = (
        "walks"
        if doc.get("walks")
        else "does not walk" + (": " + "; ".join(map(str, reasons)) if reasons else "")
    )
    body = f"<p>MuJoCo physics replay: <strong>{html.escape(verdict)}</strong>"
    if isinstance(doc.get("drift_max_m"), (int, float)):
        body += (
            f" (CoG error vs plan at most {1e3 * doc['drift_max_m']:.1f} mm, "
            f"falls {html.escape(str(doc.get('falls', 0)))})"
        )
    body += ".</p>"
    if (folder / "sim.html").is_file():
        body += (
            '<p class="note">The simulated robot with the plan as a ghost: '
            '<a href="sim.html">sim.html</a>.</p>'
        )
    return f"{PHYSICS_START}<h2>Physics</h2>{body}{PHYSICS_END}"


def add_physics_section(out_dir: str | Path) -> Path | None:
    """Put the physics section (:func:`physics_section`) into ``out_dir/report.html`` when
    the page exists and has its markers; returns the page, or None when there is none."""
    folder = Path(out_dir)
    path = folder / "report.html"
    try:
        page = path.read_text(encoding="utf-8")
    except OSError:
        return None
    start, end = page.find(PHYSICS_START), page.find(PHYSICS_END)
    if start < 0 or end < start:
        return None
    page = page[:start] + physics_section(folder) + page[end + len(PHYSICS_END) :]
    path = write_text_atomically(path, page, make_parents=False)
    record_written([path])
    return path


_PAGE = """<!DOCTYPE html>
<html>
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>
body {{ font: 15px/1.5 sans-serif; margin: 1.5em auto; padding: 0 16px; max-width: 1100px;
        color: #222; }}
iframe {{ width: 100%; height: 560px; border: 1px solid #ccc; box-sizing: border-box; }}
header {{ border-bottom: 2px solid #1f3a93; margin-bottom: 1em; padding-bottom: 0.5em; }}
table {{ border-collapse: collapse; margin: 0.3em 0 1em; }}
th, td {{ border-bottom: 1px solid #ddd; padding: 2px 12px; text-align: left; }}
thead th {{ background: #eef1f8; font-weight: 600; }}
td {{ font-variant-numeric: tabular-nums; }}
table.records td, table.joints td {{ text-align: right; }}
table.records td:first-child, table.joints td:first-child {{ text-align: left; }}
.inputs th {{ width: 16em; color: #444; font-weight: normal; }}
code {{ background: #f4f4f4; padding: 1px 4px; }}
figure {{ margin: 1em 0; }}
img {{ max-width: 100%; }}
.note {{ color: #555; font-size: 13px; }}
ul.warnings {{ color: #8a4b00; }}
</style>
</head>
<body>
{body}
</body>
</html>
"""
