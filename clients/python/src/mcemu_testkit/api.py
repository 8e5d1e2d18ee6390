"""A client of mcemu's JSON API (web.md §8, §9) on the drive's HTTP port, standard library only.

Errors come back as :class:`ApiError` with the HTTP status and the body's ``error`` object
(``code``, ``abortCode``, ``message``).
"""
from __future__ import annotations

import json
import urllib.error
import urllib.request
from typing import Any, Iterable


class ApiError(Exception):
    def __init__(self, method: str, path: str, status: int, body: bytes) -> None:
        self.method, self.path, self.status, self.body = method, path, status, body
        try:
            error = json.loads(body).get("error", {})
        except (ValueError, AttributeError):
            error = {}
        self.code: str | None = error.get("code")
        self.message: str | None = error.get("message")
        abort = error.get("abortCode")
        self.abort_code: int | None = int(abort.rstrip("hH"), 16) if isinstance(abort, str) else None
        super().__init__(f"{method} {path}: HTTP {status} {body[:300]!r}")


def _index(i: int | str) -> str:
    return i if isinstance(i, str) else f"{i:04X}"


def _sub(s: int | str) -> str:
    return s if isinstance(s, str) else f"{s:02X}h"


class Api:
    """One drive's JSON API at ``base_url`` (``http://127.0.0.1:8080``)."""

    def __init__(self, base_url: str, timeout: float = 10.0) -> None:
        self.base_url = base_url.rstrip("/")
        self.timeout = timeout

    def request(self, method: str, path: str, body: Any = None) -> Any:
        """One request; returns the decoded JSON answer (None for an empty body)."""
        data = None if body is None else json.dumps(body).encode()
        req = urllib.request.Request(self.base_url + path, data=data, method=method)
        if data is not None:
            req.add_header("Content-Type", "application/json")
        try:
            with urllib.request.urlopen(req, timeout=self.timeout) as resp:
                raw = resp.read()
        except urllib.error.HTTPError as e:
            raise ApiError(method, path, e.code, e.read()) from None
        return json.loads(raw) if raw else None

    # --- §8.1, §8.2 -----------------------------------------------------------------------------
    def info(self) -> dict:
        """``GET /api/v1/info``: model, identity, ip, bind, ports, stateDir, clock."""
        return self.request("GET", "/api/v1/info")

    def status(self) -> dict:
        """``GET /api/v1/status``: a fresh status snapshot (state, ts, statusword, posUser, …)."""
        return self.request("GET", "/api/v1/status")

    # --- §8.3 objects -----------------------------------------------------------------------------
    def objects(self) -> list[dict]:
        """``GET /api/v1/objects``: every entry of the dictionary with value and factory value."""
        return self.request("GET", "/api/v1/objects")

    def object(self, index: int | str, sub: int | str) -> dict:
        """``GET /api/v1/objects/{index}/{sub}``: one entry (name, type, access, value, factory)."""
        return self.request("GET", f"/api/v1/objects/{_index(index)}/{_sub(sub)}")

    def read(self, index: int | str, sub: int | str) -> int | str:
        """The value of one object."""
        return self.object(index, sub)["value"]

    def write(self, index: int | str, sub: int | str, value: int | str) -> int | str:
        """``PUT /api/v1/objects/{index}/{sub}``; returns the value read back."""
        return self.request("PUT", f"/api/v1/objects/{_index(index)}/{_sub(sub)}", {"value": value})["value"]

    def read_many(self, refs: Iterable[tuple[int | str, int | str]]) -> list[Any]:
        """``POST /api/v1/objects/read``: several objects read in one loop iteration (consistent)."""
        objects = [[_index(i), s if isinstance(s, str) else s] for i, s in refs]
        return self.request("POST", "/api/v1/objects/read", {"objects": objects})["values"]

    # --- §8.8 drive-level actions -------------------------------------------------------------------
    def store(self) -> None:
        """Store Permanently (1010h.01 "save")."""
        self.request("POST", "/api/v1/store", {})

    def factory_reset(self) -> None:
        """Restore factory defaults (1011h.01 "load")."""
        self.request("POST", "/api/v1/factory-reset", {})

    # --- §9 fault injection -------------------------------------------------------------------------
    def faults(self) -> list[dict]:
        """``GET /api/v1/faults``: the active injections."""
        answer = self.request("GET", "/api/v1/faults")
        return answer["faults"] if isinstance(answer, dict) and "faults" in answer else answer

    def inject(self, kind: str, **fields: Any) -> str:
        """``POST /api/v1/faults`` with ``{"kind": kind, **fields}``; returns the injection's id.
        ``inject("drive.inject", cause="under_voltage")``, ``inject("drive.load", value=50, durationMs=200)``."""
        return self.request("POST", "/api/v1/faults", {"kind": kind, **fields})["id"]

    def clear_fault(self, fault_id: str) -> None:
        self.request("DELETE", f"/api/v1/faults/{fault_id}")

    def clear_faults(self) -> None:
        self.request("DELETE", "/api/v1/faults")

    # --- docs/lint.md §5 master lint ----------------------------------------------------------------
    def lint(self) -> dict:
        """``GET /api/v1/lint``: ``mode``, ``timing``, ``totals`` (info, warn, error, suppressed, failing),
        every rule with its counts, explanation and reference, and the ``recent`` findings (oldest first)."""
        return self.request("GET", "/api/v1/lint")

    def lint_reset(self) -> dict:
        """``DELETE /api/v1/lint``: counts and findings cleared; returns the empty report."""
        return self.request("DELETE", "/api/v1/lint")

    # --- §8.10 clock -------------------------------------------------------------------------------
    def clock(self) -> dict:
        """``GET /api/v1/clock``: ``{"mode": "manual", "scale": 0, "timeMs": 1234}``."""
        return self.request("GET", "/api/v1/clock")

    def advance(self, ms: int) -> int:
        """``POST /api/v1/clock/advance`` (``--clock manual`` only): runs ``ms`` steps of 1 ms and
        returns the drive time after the last one."""
        return self.request("POST", "/api/v1/clock/advance", {"ms": int(ms)})["timeMs"]
