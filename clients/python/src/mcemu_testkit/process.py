"""Start and stop the real ``mcemu`` binary and find its drives.

Every service is started on port 0 (any free port); the ports are read from mcemu's start-up log
(``listening: refgo tcp 127.0.0.1:43215``, in a fleet ``drive k: listening: …``). All waits are
bounded and poll a condition; nothing sleeps for a fixed time.
"""
from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterator, Sequence, TypeVar

from .api import Api
from .refgo import RefGo
from .udp import UdpConsole

SERVICES = ("refgo", "slcan", "http", "udp")
LISTEN_RE = re.compile(r"(?:drive (\d+): )?listening: (\w+) (tcp|udp) (\S+):(\d+)")
READY_RE = re.compile(r"\bmcemu \S+ ready(?:: (\d+) drives?)?")

T = TypeVar("T")


class McemuError(RuntimeError):
    """mcemu did not start, or did not stop cleanly. The message ends with mcemu's log."""


def wait_for(predicate: Callable[[], T], timeout: float = 10.0, interval: float = 0.01,
             what: str = "condition") -> T:
    """Polls ``predicate`` until it returns a true value and returns that value; raises
    ``TimeoutError`` after ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() >= deadline:
            raise TimeoutError(f"timed out after {timeout} s waiting for {what}")
        time.sleep(interval)


def find_binary(binary: str | os.PathLike[str] | None = None) -> str:
    """The mcemu binary: ``binary`` if given, else ``$MCEMU_BIN``, else ``mcemu`` on ``PATH``."""
    candidate = os.fspath(binary) if binary else os.environ.get("MCEMU_BIN") or "mcemu"
    if os.sep in candidate:
        if not os.access(candidate, os.X_OK):
            raise McemuError(f"mcemu binary {candidate!r} does not exist or is not executable")
        return candidate
    found = shutil.which(candidate)
    if not found:
        raise McemuError(f"{candidate!r} is not on PATH: pass --mcemu-bin or set MCEMU_BIN")
    return found


@dataclass
class Drive:
    """One drive of a running mcemu: its number k (1…N), the address its services listen on and
    the four ports. Clients made here are closed when the process stops."""

    process: "Mcemu"
    number: int
    address: str
    ports: dict[str, int]
    _api: Api | None = field(default=None, repr=False)
    _eds: Path | None = field(default=None, repr=False)

    @property
    def api(self) -> Api:
        """The JSON API (web.md §8) of this drive."""
        if self._api is None:
            self._api = Api(f"http://{self.address}:{self.ports['http']}")
        return self._api

    @property
    def ip(self) -> str:
        """The drive's own IP address as it reports it (``--ip``, 5007h) — not the bind address."""
        return self.api.info()["ip"]

    @property
    def model(self) -> str:
        return self.api.info()["model"]

    def refgo(self, timeout: float = 5.0) -> RefGo:
        """A new RefGo connection (TCP) to this drive."""
        return self.process._track(RefGo(self.address, self.ports["refgo"], timeout=timeout))

    def udp(self, timeout: float = 5.0) -> UdpConsole:
        """A new UDP console listener for this drive (call ``register()`` on it)."""
        return self.process._track(UdpConsole(self.address, self.ports["udp"], timeout=timeout))

    @property
    def slcan_channel(self) -> str:
        """The python-can channel of this drive's SLCAN port: ``socket://address:port``."""
        return f"socket://{self.address}:{self.ports['slcan']}"

    def slcan(self, **kwargs: Any):
        """A python-can ``slcan`` bus on this drive's SLCAN port (CANopen node 50). Needs python-can
        (Debian: python3-can)."""
        from .slcan import open_bus  # python-can is needed only here

        return self.process._track(open_bus(self.slcan_channel, **kwargs))

    def lint(self, reset: bool = False) -> list[dict]:
        """The master lint's recent findings of this drive (docs/lint.md §5), oldest first: each with
        ``rule``, ``severity``, ``time_ms``, ``conn``, ``origin``, ``detail``, ``advice``, ``reference``
        and ``text``. ``reset=True`` clears them afterwards. Counts per rule: ``drive.api.lint()``."""
        findings = self.api.lint()["recent"]
        if reset:
            self.api.lint_reset()
        return findings

    @property
    def eds_path(self) -> Path:
        """An EDS of this drive's model from ``mcemu --dump-eds`` (for python-canopen's
        ``network.add_node(50, drive.eds_path)``), written once to the process's temp folder."""
        if self._eds is None:
            self._eds = self.process._dump_eds(self)
        return self._eds


class Mcemu:
    """One running mcemu process with one or more drives. Use as a context manager, or call
    ``stop()``.

    ``drives=N`` starts N drives (``--drives``), ``fleet=`` a fleet (``--fleet``: a path, or a list of
    entries that is written to a JSON file); ``config=`` is a path or a dict (``--config``);
    ``clock=`` is passed as ``--clock``; ``args`` are further command-line arguments, appended last
    (so ``"--http-port", "8080"`` overrides the port 0 the kit chooses).
    """

    def __init__(self, *args: str, binary: str | os.PathLike[str] | None = None, model: str | None = None,
                 drives: int | None = None, fleet: str | os.PathLike[str] | Sequence[dict] | None = None,
                 config: str | os.PathLike[str] | dict | None = None, clock: str | None = None,
                 state_dir: str | os.PathLike[str] | None = None, log_level: str | None = None,
                 env: dict[str, str] | None = None, startup_timeout: float = 20.0,
                 stop_timeout: float = 10.0) -> None:
        self.binary = find_binary(binary)
        self._tmp = tempfile.TemporaryDirectory(prefix="mcemu-testkit-")
        self.tmp_dir = Path(self._tmp.name)
        self.state_dir = Path(state_dir) if state_dir is not None else self.tmp_dir / "state"
        self.stop_timeout = stop_timeout
        self.config_path = self._json_file(config, "config.json")
        self.fleet_path = self._json_file(fleet, "fleet.json")
        self.model = model
        cmd = [self.binary, "--state-dir", str(self.state_dir)]
        for service in SERVICES:
            cmd += [f"--{service}-port", "0"]
        if model:
            cmd += ["--model", model]
        if drives is not None:
            cmd += ["--drives", str(drives)]
        if self.fleet_path:
            cmd += ["--fleet", str(self.fleet_path)]
        if self.config_path:
            cmd += ["--config", str(self.config_path)]
        if clock:
            cmd += ["--clock", clock]
        if log_level:
            cmd += ["--log-level", log_level]
        cmd += [str(a) for a in args]
        self.command = cmd
        self._lines: list[str] = []
        self._listeners: dict[int, dict[str, tuple[str, int]]] = {}
        self._ready_count: int | None = None
        self._ready = False
        self._lock = threading.Lock()
        self._clients: list[Any] = []
        self._stopping = False
        self.returncode: int | None = None
        self.drives: list[Drive] = []
        full_env = dict(os.environ)
        full_env.update(env or {})
        self.proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, env=full_env, text=True, errors="replace")
        self._reader = threading.Thread(target=self._read_log, name="mcemu-log", daemon=True)
        self._reader.start()
        try:
            wait_for(lambda: self._ready or self.proc.poll() is not None, timeout=startup_timeout,
                     what="mcemu's 'ready' line")
            if not self._ready:
                self._reader.join(timeout=2)
                raise McemuError(f"mcemu exited at start-up with status {self.proc.returncode}\n"
                                 f"command: {' '.join(cmd)}\n{self.log()}")
            self.drives = self._collect_drives()
        except BaseException as e:
            self._kill()
            self._tmp.cleanup()
            if isinstance(e, TimeoutError):
                raise McemuError(f"{e}\ncommand: {' '.join(cmd)}\n{self.log()}") from None
            raise

    # --- start-up ------------------------------------------------------------------------------
    def _json_file(self, value: Any, name: str) -> Path | None:
        if value is None:
            return None
        if isinstance(value, (str, os.PathLike)):
            return Path(value)
        path = self.tmp_dir / name
        path.write_text(json.dumps(value))
        return path

    def _read_log(self) -> None:
        assert self.proc.stdout is not None
        for raw in self.proc.stdout:
            line = raw.rstrip("\n")
            with self._lock:
                self._lines.append(line)
                m = LISTEN_RE.search(line)
                if m:
                    k = int(m.group(1) or 1)
                    self._listeners.setdefault(k, {})[m.group(2)] = (m.group(4), int(m.group(5)))
                r = READY_RE.search(line)
                if r and not self._ready:
                    self._ready_count = int(r.group(1)) if r.group(1) else None
                    self._ready = True

    def _collect_drives(self) -> list[Drive]:
        def complete():
            with self._lock:
                n = self._ready_count or max(self._listeners, default=1)
                if all(len(self._listeners.get(k, {})) == len(SERVICES) for k in range(1, n + 1)):
                    return {k: dict(self._listeners[k]) for k in range(1, n + 1)}
            return None

        found = wait_for(complete, timeout=5.0, what="the four listeners of every drive in the log")
        drives = []
        for k, services in sorted(found.items()):
            address = services["refgo"][0]
            if address in ("0.0.0.0", "::", "[::]"):
                address = "127.0.0.1"
            drives.append(Drive(self, k, address.strip("[]"), {s: services[s][1] for s in SERVICES}))
        return drives

    def _track(self, client: T) -> T:
        with self._lock:
            self._clients.append(client)
        return client

    def _dump_eds(self, drive: Drive) -> Path:
        cmd = [self.binary, "--dump-eds", "--model", drive.model]
        config = self._eds_config(drive.number)
        if config is not None:
            path = self.tmp_dir / f"eds-config-{drive.number}.json"
            path.write_text(json.dumps(config))
            cmd += ["--config", str(path)]
        out = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=30)
        if out.returncode != 0:
            raise McemuError(f"{' '.join(cmd)} failed ({out.returncode}): {out.stderr.strip()}")
        path = self.tmp_dir / f"drive-{drive.number}-{drive.model}.eds"
        path.write_text(out.stdout)
        return path

    def _eds_config(self, k: int) -> dict | None:
        """The config sections that give drive k's EDS defaults: the process's --config with the
        sections of fleet entry k replacing those of the same name (docs/fleet.md)."""
        config: dict = {}
        if self.config_path:
            config.update(json.loads(self.config_path.read_text()))
        if self.fleet_path:
            entries = json.loads(self.fleet_path.read_text())
            if 0 < k <= len(entries):
                config.update(entries[k - 1])
        sections = ("objects", "model_overrides", "plant", "homing", "canopen")
        config = {key: value for key, value in config.items() if key in sections}
        return config or None

    # --- while running ----------------------------------------------------------------------------
    def drive(self, k: int = 1) -> Drive:
        """Drive k, counted from 1 as in mcemu's log (``drive k: …``)."""
        if not 1 <= k <= len(self.drives):
            raise IndexError(f"drive {k}: this mcemu has drives 1…{len(self.drives)}")
        return self.drives[k - 1]

    def __iter__(self) -> Iterator[Drive]:
        return iter(self.drives)

    def __len__(self) -> int:
        return len(self.drives)

    def log(self) -> str:
        """mcemu's log so far (stdout and stderr), one line per line."""
        with self._lock:
            return "\n".join(self._lines)

    def log_lines(self) -> list[str]:
        with self._lock:
            return list(self._lines)

    def wait_log(self, pattern: str | re.Pattern[str], timeout: float = 10.0) -> str:
        """Waits for a log line matching ``pattern`` (a regex) and returns it."""
        rx = re.compile(pattern) if isinstance(pattern, str) else pattern

        def match():
            with self._lock:
                return next((line for line in self._lines if rx.search(line)), None)

        return wait_for(match, timeout=timeout, what=f"a log line matching {rx.pattern!r}")

    @property
    def running(self) -> bool:
        return self.proc.poll() is None

    # --- shutdown ---------------------------------------------------------------------------------
    def _close_clients(self) -> None:
        with self._lock:
            clients, self._clients = self._clients, []
        for client in reversed(clients):
            try:
                if hasattr(client, "shutdown"):
                    client.shutdown()  # python-can bus
                else:
                    client.close()
            except Exception:  # a client that is already broken must not hide the shutdown
                pass

    def _kill(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
        self.proc.wait()
        self._reader.join(timeout=2)

    def stop(self, sig: int = signal.SIGTERM) -> int:
        """Closes the kit's clients, sends ``sig`` (SIGTERM: mcemu's clean shutdown) and waits;
        returns the exit status. A process that does not end within ``stop_timeout`` is killed
        and ``McemuError`` is raised."""
        if self.returncode is not None:
            return self.returncode
        self._stopping = True
        self._close_clients()
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
            try:
                self.proc.wait(timeout=self.stop_timeout)
            except subprocess.TimeoutExpired:
                self._kill()
                self.returncode = self.proc.returncode
                raise McemuError(f"mcemu did not stop within {self.stop_timeout} s of signal {sig}; killed\n"
                                 f"{self.log()}") from None
        self._reader.join(timeout=2)
        self.returncode = self.proc.returncode
        return self.returncode

    def close(self) -> None:
        """Stops the process (if running) and removes the temp folder (state, EDS, config files)."""
        try:
            self.stop()
        finally:
            self._tmp.cleanup()

    def __enter__(self) -> "Mcemu":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()
