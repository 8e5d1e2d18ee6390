"""CANopen over SLCAN through python-can, and the EDS for python-canopen users."""
import struct

import can
import pytest

from mcemu_testkit.slcan import heartbeat_id, recv_until


def sdo_upload_expedited(bus, index, sub, node=50):
    bus.send(can.Message(arbitration_id=0x600 + node, data=struct.pack("<BHB4x", 0x40, index, sub),
                         is_extended_id=False))
    msg = recv_until(bus, lambda m: m.arbitration_id == 0x580 + node)
    assert msg is not None, "no SDO response"
    assert msg.data[0] & 0x03 == 0x03, msg  # expedited with size
    return bytes(msg.data[4:8 - ((msg.data[0] >> 2) & 3)])


def test_sdo_and_heartbeat(mcemu_drive):
    bus = mcemu_drive.slcan()
    assert mcemu_drive.slcan_channel == f"socket://{mcemu_drive.address}:{mcemu_drive.ports['slcan']}"
    bus.send(can.Message(arbitration_id=0, data=[0x80, 50], is_extended_id=False))  # NMT pre-operational
    assert struct.unpack("<I", sdo_upload_expedited(bus, 0x1000, 0))[0] == mcemu_drive.api.read(0x1000, 0)
    mcemu_drive.refgo().ow(0x1017, 0, 50)  # heartbeat producer every 50 ms
    beat = recv_until(bus, lambda m: m.arbitration_id == heartbeat_id())
    assert beat is not None and bytes(beat.data) == b"\x7f"  # pre-operational


def eds_default(text, section):
    """DefaultValue of one [section] of an EDS (hex or decimal, as CiA 306 allows)."""
    body = text.split(f"\n[{section}]\n", 1)[1].split("\n[", 1)[0]
    return int(next(line for line in body.splitlines() if line.startswith("DefaultValue=")).split("=", 1)[1], 0)


@pytest.mark.mcemu(model="MCFLAT", config={"objects": {"6083.00": 2000}})
def test_eds_of_the_drive(mcemu_drive):
    text = mcemu_drive.eds_path.read_text()
    assert "ProductName=MCFLAT" in text
    assert eds_default(text, "6083") == 2000
    assert mcemu_drive.eds_path.name.endswith("MCFLAT.eds")
