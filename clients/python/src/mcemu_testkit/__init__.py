"""mcemu test kit: start the mcemu emulator of a Fullmo MovingCap Ethernet drive from Python tests
and talk to it over RefGo, CANopen/SLCAN, the JSON API and the UDP console.

The pytest plugin (fixtures ``mcemu_drive``, ``mcemu_fleet``, ``mcemu_start``) is registered
through the ``pytest11`` entry point; see docs/testkit.md.
"""
from .api import Api, ApiError
from .process import Drive, Mcemu, McemuError, find_binary, wait_for
from .refgo import RefGo, RefGoError, RefGoReply
from .udp import UdpConsole

__all__ = ["Api", "ApiError", "Drive", "Mcemu", "McemuError", "RefGo", "RefGoError", "RefGoReply", "UdpConsole",
           "find_binary", "wait_for"]
__version__ = "0.1.0"
