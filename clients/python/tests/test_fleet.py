"""Fleets: N drives or a fleet file, each with its own address, ports and clients."""
import json

import pytest
from test_slcan import eds_default


@pytest.mark.mcemu(drives=3)
def test_drives_have_their_own_addresses(mcemu_fleet):
    assert [d.number for d in mcemu_fleet] == [1, 2, 3]
    assert [d.address for d in mcemu_fleet] == ["127.0.0.1", "127.0.0.2", "127.0.0.3"]
    assert [d.ip for d in mcemu_fleet] == ["192.168.2.150", "192.168.2.151", "192.168.2.152"]
    mcemu_fleet.drive(2).refgo().ow(0x6081, 0, 2222)
    assert [d.api.read(0x6081, 0) for d in mcemu_fleet] == [1000, 2222, 1000]
    with pytest.raises(IndexError):
        mcemu_fleet.drive(4)
    console = mcemu_fleet.drive(3).udp()  # from 127.0.0.1 to drive 3's console on 127.0.0.3
    assert b"IP Address: 192.168.2.152 \r\n" in console.register()


@pytest.mark.mcemu(fleet=[{"model": "MC349"}, {"model": "MCFLAT", "objects": {"6083.00": 2000}}])
def test_fleet_list(mcemu_fleet):
    axis1, axis2 = mcemu_fleet.drive(1), mcemu_fleet.drive(2)
    assert (axis1.model, axis2.model) == ("MC349", "MCFLAT")
    assert axis2.api.read(0x6083, 0) == 2000
    assert "ProductName=MCFLAT" in axis2.eds_path.read_text()
    assert eds_default(axis2.eds_path.read_text(), "6083") == 2000
    assert eds_default(axis1.eds_path.read_text(), "6083") == axis1.api.object(0x6083, 0)["factory"]


def test_fleet_file_and_port_step(mcemu_start, tmp_path):
    fleet = tmp_path / "machine.json"
    fleet.write_text(json.dumps([{"model": "MC349", "ip": "10.0.0.5"}, {"model": "MCN23"}]))
    mc = mcemu_start(fleet=fleet)
    assert [d.model for d in mc] == ["MC349", "MCN23"]
    assert mc.drive(1).ip == "10.0.0.5"
    stepped = mcemu_start("--bind", "127.0.0.1", "--port-step", "100", drives=2)
    assert {d.address for d in stepped} == {"127.0.0.1"}
    assert stepped.drive(2).refgo().tp() == 0
