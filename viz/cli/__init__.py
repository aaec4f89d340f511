"""The ``silo4`` command (viz/cli/main.py): one module per subcommand.

Importing this package first makes sure the packages the command is built of are the ones
installed beside it: a folder of the user's named ``planner/`` (or ``silo4kin/``,
``silo4sim/``, ``silo4sweep/``) on ``sys.path`` before ours (PYTHONPATH, or ``python -m viz``
run from that folder's parent) would otherwise be imported in their place, and fail somewhere
deep inside. The command then stops at once with one line naming the folder, exit 2.
"""

from __future__ import annotations

import sys
from importlib.util import find_spec
from pathlib import Path

#: The top-level packages of silo4kin besides viz, each installed beside it.
OWN_PACKAGES = ("silo4kin", "planner", "silo4sim", "silo4sweep")


def foreign_packages() -> list[tuple[str, str]]:
    """(name, origin) of each of OWN_PACKAGES that Python would import from elsewhere than
    the folder holding this viz package (not imported here: found only)."""
    ours = Path(__file__).resolve().parents[2]
    found = []
    for name in OWN_PACKAGES:
        module = sys.modules.get(name)
        origin = getattr(module, "__file__", None) if module is not None else None
        if origin is None:
            spec = find_spec(name)
            origin = None if spec is None else spec.origin
        if origin is not None and Path(origin).resolve().parents[1] != ours:
            found.append((name, str(origin)))
    return found


def _refuse_foreign_packages() -> None:
    foreign = foreign_packages()
    if foreign:
        name, origin = foreign[0]
        sys.stderr.write(
            f"silo4: error: {origin} is not silo4's {name!r} package: a folder named {name}/ "
            f"in {Path(origin).resolve().parents[1]} comes first on the module path; run "
            f"silo4 from another folder or rename that folder\n"
        )
        raise SystemExit(2)


_refuse_foreign_packages()
