"""Regenerate the catalogue table of docs/errors.md from the hostile-input test table.

    python scripts/errors_catalogue.py > /tmp/catalogue.md   # then paste it into docs/errors.md

Runs every case of tests/test_cli_hostile.py (CASES) as the test does (a subprocess in a copy
of the test's user folder) and prints a Markdown table: case, command, exit code, and the
one line the user sees (stderr on a refusal, the last stdout line on success).
"""

from __future__ import annotations

import importlib.util
import shutil
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _load_cases():
    spec = importlib.util.spec_from_file_location("hostile", ROOT / "tests" / "test_cli_hostile.py")
    module = importlib.util.module_from_spec(spec)
    assert spec.loader is not None
    spec.loader.exec_module(module)
    return module


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def main() -> None:
    hostile = _load_cases()
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "template").mkdir()
        template = hostile.make_user_folder(Path(tmp) / "template")
        print("| case | command | exit | what the user sees |")
        print("|---|---|---|---|")
        for name, argv, code, _fragment, _created in hostile.CASES:
            cwd = Path(tmp) / "cwd"
            shutil.rmtree(cwd, ignore_errors=True)
            shutil.copytree(template, cwd)
            result = hostile.silo4(cwd, *argv)
            lines = (result.stderr if result.returncode else result.stdout).strip().splitlines()
            line = lines[0] if result.returncode else (lines[-1] if lines else "")
            line = line.replace(f"{cwd}/", "./")  # the temporary folder's name varies
            shown = " ".join(a if len(a) < 40 else a[:20] + "..." for a in argv)
            print(
                f"| {name} | `silo4 {_cell(shown)}` | {result.returncode} | {_cell(line[:220])} |"
            )
            if result.returncode != code:
                print(
                    f"warning: {name} exited {result.returncode}, expected {code}", file=sys.stderr
                )


if __name__ == "__main__":
    main()
