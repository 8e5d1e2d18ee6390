"""CANopen over SLCAN (TCP 15001 on a real drive; slcan-canopen.md) through python-can.

mcemu's SLCAN port speaks the ASCII protocol of an SLCAN USB adapter over TCP, so python-can's
``slcan`` interface reaches it through pyserial's ``socket://`` URL. The drive is CANopen node 50.
"""
from __future__ import annotations

import time
from typing import Any

import can

NODE_ID = 50


def open_bus(channel: str, **kwargs: Any) -> can.BusABC:
    """``can.Bus(interface="slcan", channel="socket://host:port")``; the caller (or the kit, for a
    bus made by ``Drive.slcan()``) shuts it down."""
    kwargs.setdefault("sleep_after_open", 0)  # a TCP socket needs no adapter settling time
    return can.Bus(interface="slcan", channel=channel, **kwargs)


def heartbeat_id(node: int = NODE_ID) -> int:
    """CAN id of the node's heartbeat (and boot-up) message: 700h + node."""
    return 0x700 + node


def recv_until(bus: can.BusABC, predicate, timeout: float = 2.0) -> can.Message | None:
    """The first received frame for which ``predicate(msg)`` is true, or None after ``timeout``
    seconds."""
    deadline = time.monotonic() + timeout
    while (left := deadline - time.monotonic()) > 0:
        msg = bus.recv(timeout=left)
        if msg is not None and predicate(msg):
            return msg
    return None
