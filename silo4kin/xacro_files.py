"""Expand a xacro file to URDF text with the PyPI ``xacro`` package (no ROS).

xacro silently ignores unknown arguments; :func:`expand_xacro` refuses them and lists the
valid ones, refuses non-numeric or huge values for numeric ones, and resolves ``$(find pkg)``
in the folders given. xacro evaluates Python expressions (``${9**9**9}``), so the expansion
runs in a forked child process bounded in CPU time, memory and wall time.
"""

from __future__ import annotations

import contextlib
import functools
import math
import os
import resource
import select
import signal
import sys
import time
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import NoReturn

from .errors import RobotDescriptionError, XacroArgumentError

#: Largest magnitude of a numeric xacro argument (SI units); beyond it FK overflows.
MAX_XACRO_NUMBER = 1e4
#: Bounds of one expansion (:func:`run_bounded`): CPU [s], wall clock [s], and address
#: space [bytes] beyond what the process had when it forked. SILO4's xacro expands in ~0.1 s.
XACRO_CPU_LIMIT_S = 5
XACRO_WALL_LIMIT_S = 15.0
XACRO_MEMORY_LIMIT = 2_000_000_000


def declared_xacro_args(path: Path) -> dict[str, str | None]:
    """Names and defaults of the ``<xacro:arg>`` elements a xacro file declares."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise RobotDescriptionError(f"{path}: malformed XML: {exc}") from exc
    out: dict[str, str | None] = {}
    for el in root.iter():
        tag = el.tag.split("}")[-1]
        if tag == "arg" and "name" in el.attrib:
            out[el.attrib["name"]] = el.attrib.get("default")
    return out


def _is_numeric_default(default: str | None) -> bool:
    if default is None:
        return False
    if default.startswith("${"):
        return True
    try:
        float(default)
    except ValueError:
        return False
    return True


def find_package(name: str, package_dirs: Sequence[str | Path]) -> Path:
    """The folder of ROS package ``name`` among ``package_dirs`` (for xacro's ``$(find)`` and
    ``package://``): ``DIR/name``, or ``DIR`` itself when it is named ``name``.

    Raises:
        RobotDescriptionError: not found (names the folders searched).
    """
    for folder in map(Path, package_dirs):
        for candidate in (folder / name, folder):
            if candidate.name == name and candidate.is_dir():
                return candidate.resolve()
    where = ", ".join(str(d) for d in package_dirs) or "none given"
    raise RobotDescriptionError(
        f"xacro $(find {name}): package {name!r} not found in the --package-dir folders "
        f"({where}); give the folder that holds {name}/ with --package-dir"
    )


@contextlib.contextmanager
def _xacro_find(package_dirs: Sequence[str | Path]) -> Iterator[None]:
    """Make xacro's ``$(find pkg)`` look in ``package_dirs`` (it needs ROS otherwise)."""
    from xacro import substitution_args as subst

    def eval_find(pkg: str) -> str:
        return str(find_package(pkg, package_dirs))

    saved = subst._eval_find, subst._eval_dict.get("find")
    subst._eval_find = eval_find
    subst._eval_dict["find"] = eval_find
    try:
        yield
    finally:
        subst._eval_find = saved[0]
        subst._eval_dict["find"] = saved[1]


def expand_xacro(
    path: Path,
    xacro_args: Mapping[str, object] | None = None,
    package_dirs: Sequence[str | Path] = (),
    *,
    trusted: bool = False,
) -> str:
    """Expand a xacro file to URDF text, validating the argument names and values.

    A file that is not ``trusted`` expands in the bounded child of :func:`run_bounded`; the
    shipped SILO4 xacro (trusted: its expressions are ours, its numeric arguments bounded by
    MAX_XACRO_NUMBER) expands in this process, saving the fork (~50-100 ms per load).

    Raises:
        XacroArgumentError: unknown argument name, or a non-numeric value for a numeric one.
        RobotDescriptionError: the file is missing or xacro fails on it.
    """
    import xacro  # noqa: F401 (loaded here once, inherited by every bounded child)

    declared = declared_xacro_args(path)
    mappings: dict[str, str] = {}
    for name, value in (xacro_args or {}).items():
        if name not in declared:
            raise XacroArgumentError(
                f"unknown xacro argument {name!r} for {path.name}; valid arguments: "
                f"{', '.join(sorted(declared))}",
                name,
                declared,
            )
        text = str(value)
        if _is_numeric_default(declared[name]):
            try:
                number = float(text)
            except ValueError:
                raise XacroArgumentError(
                    f"xacro argument {name}={text!r} is not a number", name, declared
                ) from None
            if not math.isfinite(number) or abs(number) > MAX_XACRO_NUMBER:
                raise XacroArgumentError(
                    f"xacro argument {name}={text!r} is not a finite number within "
                    f"±{MAX_XACRO_NUMBER:g} (SI units: m, kg, rad)",
                    name,
                    declared,
                )
        mappings[name] = text
    expand = functools.partial(_expand, path, mappings, package_dirs)
    return expand() if trusted else run_bounded(expand, path.name)


def _expand(path: Path, mappings: Mapping[str, str], package_dirs: Sequence[str | Path]) -> str:
    """xacro on ``path`` (in the bounded child process of :func:`run_bounded`)."""
    import xacro

    try:
        with _xacro_find(package_dirs):
            return str(xacro.process_file(str(path), mappings=dict(mappings)).toxml())
    except RobotDescriptionError:
        raise
    except Exception as exc:  # xacro raises XacroException, XML errors, NameError, ...
        if isinstance(exc.__context__, RobotDescriptionError):  # our $(find), re-wrapped
            raise exc.__context__ from None
        raise RobotDescriptionError(f"{path}: xacro failed: {exc}") from exc


def run_bounded(expand: Callable[[], str], what: str) -> str:
    """``expand()`` in a forked child limited to XACRO_CPU_LIMIT_S of CPU, XACRO_MEMORY_LIMIT
    bytes and XACRO_WALL_LIMIT_S of wall time: xacro evaluates Python expressions, so a file
    can hold ``${9**9**9}``. Returns its text; its RobotDescriptionError comes back as one.

    Raises:
        RobotDescriptionError: xacro failed, or the expansion broke a limit (named).
    """
    read_fd, write_fd = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: never returns, never runs the parent's cleanup
        os.close(read_fd)
        _child(expand, write_fd)
    os.close(write_fd)
    chunks: list[bytes] = []
    deadline = time.monotonic() + XACRO_WALL_LIMIT_S
    timed_out = False
    try:
        with os.fdopen(read_fd, "rb", buffering=0) as pipe:
            while True:
                left = deadline - time.monotonic()
                if left <= 0 or not select.select([pipe], [], [], left)[0]:
                    timed_out = True
                    break
                chunk = pipe.read(1 << 20)
                if not chunk:
                    break
                chunks.append(chunk)
    finally:
        if timed_out or sys.exc_info()[0] is not None:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
        _, status = os.waitpid(pid, 0)
    data = b"".join(chunks)
    if data[:1] == b"T":
        return data[1:].decode("utf-8")
    if data[:1] == b"E":
        raise RobotDescriptionError(data[1:].decode("utf-8", errors="replace"))
    if timed_out:
        raise RobotDescriptionError(
            f"{what}: xacro expansion took over {XACRO_WALL_LIMIT_S:g} s and was stopped"
        )
    if os.WIFSIGNALED(status) and os.WTERMSIG(status) in (signal.SIGXCPU, signal.SIGKILL):
        raise RobotDescriptionError(
            f"{what}: xacro expansion used over {XACRO_CPU_LIMIT_S:g} "
            "s of CPU and was stopped (an expression too costly to "
            "evaluate?)"
        )
    raise RobotDescriptionError(f"{what}: xacro expansion ended without a result (status {status})")


def _address_space_bytes() -> int:
    """This process's virtual memory size [bytes] (Linux /proc/self/statm)."""
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")


def _child(expand: Callable[[], str], write_fd: int) -> NoReturn:
    """The bounded child: limits, then ``expand()``; writes b"T" + text or b"E" + message."""
    code = 0
    try:
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        resource.setrlimit(resource.RLIMIT_CPU, (XACRO_CPU_LIMIT_S, XACRO_CPU_LIMIT_S + 1))
        with contextlib.suppress(ValueError, OSError):  # a lower hard limit already
            limit = _address_space_bytes() + XACRO_MEMORY_LIMIT
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        try:
            message = b"T" + expand().encode("utf-8")
        except RobotDescriptionError as exc:
            message = b"E" + str(exc).encode("utf-8", errors="replace")
        except MemoryError:
            message = (
                b"E"
                + f"xacro expansion needed over {XACRO_MEMORY_LIMIT / 1e9:g} GB "
                "of memory and was stopped".encode()
            )
        except BaseException as exc:  # noqa: BLE001 (reported to the parent as one line)
            message = b"E" + f"xacro failed: {type(exc).__name__}: {exc}".encode(
                "utf-8", errors="replace"
            )
        view = memoryview(message)
        while view:
            view = view[os.write(write_fd, view) :]
    except BaseException:  # noqa: BLE001 (the parent reports a child without a result)
        code = 1
    finally:
        os._exit(code)
