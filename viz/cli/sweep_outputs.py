"""What a sweep writes when its table is complete (viz/cli/sweep.py): the summary,
best.json, the Pareto picture and the results page, and the command that regenerates it."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from viz.cli.common import EXIT_CHECK_FAILED, EXIT_OK


def xacro_defaults(robot: str | None, xacro_names: list[str]) -> dict[str, float]:
    """Default values of the swept xacro arguments (the reference design of the page)."""
    from silo4kin.robot import DEFAULT_XACRO
    from silo4kin.xacro_files import declared_xacro_args

    if not xacro_names:
        return {}
    declared = declared_xacro_args(Path(robot) if robot else DEFAULT_XACRO)
    out = {}
    for name in xacro_names:
        try:
            out[name] = float(declared.get(name) or "nan")
        except ValueError:
            continue
    return out


#: What a sweep writes into its folder beside the table (silo4sweep.table's files).
SUMMARY_NAMES = ("best.json", "pareto.png")


def page_image(page_path: Path) -> Path:
    """The Pareto picture beside a --results-md page (docs/sweep_results_pareto.png)."""
    return page_path.with_name(page_path.stem + "_pareto.png")


def finish_sweep(
    args: argparse.Namespace,
    table,
    configs,
    xacro_names,
    n_run: int,  # noqa: ANN001
    wall_s: float,
) -> int:
    from planner.outputs.files import record_written, write_text_atomically
    from silo4sweep.report import render_sweep_page
    from silo4sweep.summary import best_heights, write_best_json, write_pareto_png

    best_name, pareto_name = SUMMARY_NAMES
    written = table.finish(configs)
    rows = table.typed_rows(configs)
    written.append(write_best_json(table.folder / best_name, rows, xacro_names))
    record_written(written[-1:])  # each recorded as silo4's at once: a rerun may replace it
    written.append(write_pareto_png(table.folder / pareto_name, rows, xacro_names))
    record_written(written[-1:])
    if args.results_md:
        page_path = Path(args.results_md)
        image = page_image(page_path)
        written.append(write_pareto_png(image, rows, xacro_names))
        record_written(written[-1:])
        page = render_sweep_page(
            rows,
            xacro_names,
            command=regenerate_command(args),
            reference=xacro_defaults(args.robot, xacro_names),
            pareto_image=image.name,
        )
        written.append(write_text_atomically(page_path, page))
        record_written(written[-1:])
    counts = {s: sum(r["status"] == s for r in rows) for s in ("ok", "refused", "error")}
    if n_run:
        print(
            f"planned {n_run} configurations in {wall_s:.1f} s "
            f"({n_run / max(wall_s, 1e-9):.2f} per s)"
        )
    print(
        f"{len(rows)} rows: {counts['ok']} planned, {counts['refused']} refused, "
        f"{counts['error']} errors"
    )
    for entry in best_heights(rows, xacro_names):
        design = " ".join(f"{k}={v:g}" for k, v in entry["design"].items())
        best = entry["best"]
        what = (
            f"best h = {best['height_m']:g} m: {best['normalized_time']:g} units, E_n "
            f"{best['normalized_error_m']:.3f} m, peak torque {best['tau_peak_Nm']:.1f} N m"
            if best
            else "no height planned"
        )
        print(f"  {entry['path']:14s} {entry['preset']:8s} {design:24s} {what}")
    print("wrote " + ", ".join(str(p) for p in written))
    if counts["error"]:
        print(
            f"{counts['error']} configuration(s) failed with an error (not a refusal): see "
            "the reason column",
            file=sys.stderr,
        )
        return EXIT_CHECK_FAILED
    return EXIT_OK


def regenerate_command(args: argparse.Namespace) -> str:
    """The command line that regenerates the results page."""
    parts = ["silo4 sweep", "--paths", args.paths, "--heights", args.heights]
    for item in args.xacro_arg:
        parts += ["--xacro-arg", item]
    parts += ["--workspaces", args.workspaces]
    if args.samples_per_unit != 100:
        parts += ["--samples-per-unit", str(args.samples_per_unit)]
    if args.load:
        parts += ["--load", args.load]
    parts += ["--out", str(args.out)]
    if args.results_md:
        parts += ["--results-md", str(args.results_md)]
    return " ".join(parts)
