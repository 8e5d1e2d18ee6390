"""pytest plugin of the mcemu test kit (registered through the ``pytest11`` entry point).

Fixtures:

- ``mcemu_drive`` — one drive (a :class:`~mcemu_testkit.Drive`) of a fresh mcemu process;
- ``mcemu_fleet`` — a fresh mcemu process (:class:`~mcemu_testkit.Mcemu`) with several drives:
  ``@pytest.mark.mcemu(drives=3)`` or ``fleet=[{...}, …]`` / a fleet file (2 drives if neither is given);
- ``mcemu_start`` — a factory, ``mcemu_start(*args, **options)``, for tests that need several
  processes or a restart.

``@pytest.mark.mcemu(*args, model=, drives=, fleet=, config=, clock=, state_dir=)`` sets the options of
``mcemu_drive`` and ``mcemu_fleet``. The binary is ``--mcemu-bin``, the ini option ``mcemu_bin``,
``$MCEMU_BIN`` or ``mcemu`` on PATH. Every process is stopped with SIGTERM when the test ends; one
that exited on its own or did not exit with status 0 fails the test's teardown. A failing test's
report carries the log of each mcemu it started.

Strict tests (docs/lint.md): with ``--mcemu-strict``, or for a test marked ``@pytest.mark.mcemu_strict``,
a test whose drives reported a warn- or error-level finding of mcemu's master lint fails, with the
findings in its report (``@pytest.mark.mcemu_strict(False)`` exempts one test from the option).
"""
from __future__ import annotations

import os
import subprocess
from typing import Any, Callable, Iterator

import pytest

from .api import ApiError
from .process import Drive, Mcemu, McemuError, find_binary

_STARTED = pytest.StashKey[list]()


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("mcemu", "mcemu drive emulator")
    group.addoption("--mcemu-bin", dest="mcemu_bin", default=None,
                    help="path of the mcemu binary (default: ini mcemu_bin, $MCEMU_BIN, mcemu on PATH)")
    group.addoption("--mcemu-log-level", dest="mcemu_log_level", default=None,
                    help="--log-level of every mcemu the fixtures start (default: mcemu's, info)")
    group.addoption("--mcemu-strict", dest="mcemu_strict", action="store_true", default=False,
                    help="fail a test whose mcemu drives reported a warn- or error-level master-lint finding "
                         "(docs/lint.md); a test can opt out with @pytest.mark.mcemu_strict(False)")
    parser.addini("mcemu_bin", "path of the mcemu binary", default="")


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers", "mcemu(*args, model=None, drives=None, fleet=None, config=None, clock=None, state_dir=None): "
        "options of the mcemu started by the mcemu_drive / mcemu_fleet fixtures")
    config.addinivalue_line(
        "markers", "mcemu_strict(on=True): fail the test when its mcemu drives reported a warn- or error-level "
        "master-lint finding (as --mcemu-strict for this test; mcemu_strict(False) exempts it)")


def _binary(config: pytest.Config) -> str | None:
    option = config.getoption("mcemu_bin")
    if option:
        return option
    ini = config.getini("mcemu_bin")
    if ini:
        return ini if os.path.isabs(ini) or os.sep not in ini else str(config.rootpath / ini)
    return None


def pytest_report_header(config: pytest.Config) -> str | None:
    try:
        binary = find_binary(_binary(config))
        version = subprocess.run([binary, "--version"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                 text=True, timeout=10).stdout.strip()
    except (McemuError, OSError, subprocess.SubprocessError):
        return "mcemu: not found (--mcemu-bin, $MCEMU_BIN or PATH)"
    return f"mcemu: {binary} ({version})"


def _strict(item: pytest.Item) -> bool:
    marker = item.get_closest_marker("mcemu_strict")
    if marker is not None:
        return bool(marker.args[0]) if marker.args else bool(marker.kwargs.get("on", True))
    return bool(item.config.getoption("mcemu_strict"))


def _lint_findings(item: pytest.Item) -> tuple[list[str], int]:
    """The warn- and error-level findings of every drive of the still running processes of the test:
    report lines, and how many occurrences there were (the rate limit may have kept some out of the
    list of recent findings)."""
    lines: list[str] = []
    count = 0
    processes = item.stash.get(_STARTED, [])
    for n, process in enumerate(processes, start=1):
        if process.returncode is not None or process.proc.poll() is not None:
            continue
        for drive in process.drives:
            where = f"mcemu {n} drive {drive.number}" if len(processes) > 1 else f"drive {drive.number}"
            try:
                report = drive.api.lint()
            except (ApiError, OSError) as e:
                lines.append(f"{where}: the master lint could not be read ({e})")
                continue
            totals = report["totals"]
            failing = totals["warn"] + totals["error"]
            if failing == 0:
                continue
            count += failing
            shown = [f for f in report["recent"] if f["severity"] in ("warn", "error")]
            for f in shown:
                lines.append(f"{where}: {f['text']} (at {f['time_ms']} ms, {f['origin']}"
                             + (f", conn {f['conn']}" if f["conn"] else "") + ")")
            if failing > len(shown):
                lines.append(f"{where}: … {failing - len(shown)} more occurrences "
                             "(over the rate limit or out of the recent list; GET /api/v1/lint counts them)")
    return lines, count


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo) -> Iterator[None]:
    outcome = yield
    report = outcome.get_result()
    if call.when == "call" and _strict(item) and item.stash.get(_STARTED, []):
        lines, count = _lint_findings(item)
        if lines:
            text = "\n".join(lines)
            report.sections.append(("mcemu master lint", text))
            if report.passed and count:
                report.outcome = "failed"
                report.longrepr = (f"mcemu strict: the drives reported {count} warn/error-level master-lint "
                                   f"finding{'s' if count != 1 else ''} (docs/lint.md):\n{text}")
    if not report.failed:
        return
    for n, process in enumerate(item.stash.get(_STARTED, []), start=1):
        exit_note = "" if process.returncode is None else f"\n(exit status {process.returncode})"
        report.sections.append((f"mcemu {n} log ({report.when})",
                                "$ " + " ".join(process.command) + "\n" + process.log() + exit_note))


def _stop_checked(process: Mcemu) -> str | None:
    """Stops a process the kit started and removes its temp folder; returns why its end was not
    clean (or None)."""
    try:
        if process.returncode is not None:
            return None  # the test stopped it itself and has seen the status
        died = process.proc.poll()
        try:
            status = process.stop()
        except McemuError as e:
            return str(e).splitlines()[0]
        if died is not None:
            return f"mcemu exited during the test with status {died}"
        if status != 0:
            return f"mcemu exited with status {status} after SIGTERM"
        return None
    finally:
        process.close()


@pytest.fixture
def mcemu_start(request: pytest.FixtureRequest) -> Iterator[Callable[..., Mcemu]]:
    """Factory: ``mcemu_start(*args, model=, drives=, fleet=, config=, clock=, state_dir=, env=)``
    starts one mcemu and returns it (:class:`~mcemu_testkit.Mcemu`); all are stopped at teardown."""
    started: list[Mcemu] = request.node.stash.setdefault(_STARTED, [])
    binary = _binary(request.config)
    log_level = request.config.getoption("mcemu_log_level")

    def start(*args: str, **options: Any) -> Mcemu:
        options.setdefault("binary", binary)
        options.setdefault("log_level", log_level)
        process = Mcemu(*args, **options)
        started.append(process)
        return process

    yield start
    problems = [p for p in (_stop_checked(process) for process in started) if p]
    if problems:
        pytest.fail("; ".join(problems), pytrace=False)


def _marker_options(request: pytest.FixtureRequest) -> tuple[tuple, dict]:
    marker = request.node.get_closest_marker("mcemu")
    if marker is None:
        return (), {}
    return tuple(marker.args), dict(marker.kwargs)


@pytest.fixture
def mcemu_drive(mcemu_start: Callable[..., Mcemu], request: pytest.FixtureRequest) -> Drive:
    """Drive 1 of a fresh mcemu (all four services on free ports); the process is
    ``mcemu_drive.process``."""
    args, options = _marker_options(request)
    return mcemu_start(*args, **options).drive(1)


@pytest.fixture
def mcemu_fleet(mcemu_start: Callable[..., Mcemu], request: pytest.FixtureRequest) -> Mcemu:
    """A fresh mcemu with several drives (``mcemu_fleet.drive(k)``, k = 1…N)."""
    args, options = _marker_options(request)
    if "drives" not in options and "fleet" not in options:
        options["drives"] = 2
    return mcemu_start(*args, **options)
