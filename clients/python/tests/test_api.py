"""JSON API client (web.md §8, §9). The clock and status endpoints are tested when the binary has
them (GET /api/v1/status, --clock in --help); otherwise those tests are skipped with the reason."""
import subprocess
import time

import pytest

from mcemu_testkit import ApiError


def test_info_and_objects(mcemu_drive):
    info = mcemu_drive.api.info()
    assert info["emulator"] == "mcemu"
    assert info["ports"]["refgo"] == mcemu_drive.ports["refgo"]
    assert mcemu_drive.ip == "192.168.2.150"
    entries = mcemu_drive.api.objects()
    assert {"index": "6041h", "sub": "00h"}.items() <= next(e for e in entries if e["index"] == "6041h").items()
    assert mcemu_drive.api.object(0x1008, 0)["value"] == "MC349_ETH_RE"


def test_write_read_many_and_errors(mcemu_drive):
    api = mcemu_drive.api
    assert api.write(0x6083, 0, 2500) == 2500
    assert api.read_many([(0x6083, 0), ("6041", 0), (0x1234, 0)])[0] == 2500
    assert api.read_many([(0x1234, 0)]) == [{"abortCode": "06020000h"}]
    with pytest.raises(ApiError) as e:
        api.write(0x6041, 0, 1)
    assert (e.value.status, e.value.abort_code) == (409, 0x06010002)
    with pytest.raises(ApiError) as e:
        api.read(0x1234, 0)
    assert e.value.status == 404


def test_fault_injection_round_trip(mcemu_drive):
    api = mcemu_drive.api
    fault = api.inject("drive.inject", cause="under_voltage")
    assert [f["id"] for f in api.faults()] == [fault]
    # an under-voltage is a condition cause: the drive raises it in its next steps (drive-core.md §10.11)
    deadline = time.monotonic() + 5
    while api.read(0x603F, 0) != 0x3221 and time.monotonic() < deadline:
        time.sleep(0.005)
    assert api.read(0x603F, 0) == 0x3221  # DC link under-voltage
    assert mcemu_drive.refgo().ts() == 9
    api.clear_fault(fault)
    assert api.faults() == []
    api.inject("drive.ambient", celsius=50)
    api.clear_faults()
    assert api.faults() == []


def test_store_survives_a_restart(mcemu_start, tmp_path):
    first = mcemu_start(state_dir=tmp_path)
    first.drive(1).api.write(0x6081, 0, 4321)
    first.drive(1).api.store()
    assert first.stop() == 0
    second = mcemu_start(state_dir=tmp_path)
    assert second.drive(1).api.read(0x6081, 0) == 4321
    temp = second.tmp_dir
    second.close()
    assert not temp.exists() and (tmp_path / "drive-1.json").exists()  # the kit's temp folder only


def _has_status(drive):
    try:
        drive.api.status()
    except ApiError as e:
        if e.status == 404:
            return False
        raise
    return True


def test_status(mcemu_drive):
    if not _has_status(mcemu_drive):
        pytest.skip("GET /api/v1/status is not in this mcemu (web milestone)")
    status = mcemu_drive.api.status()
    assert status["state"] == "SOD" and status["ts"] == 0
    mcemu_drive.refgo().go(100)
    assert mcemu_drive.api.status()["targetPos"] == 100


def _has_clock_flag(binary):
    return "--clock" in subprocess.run([binary, "--help"], stdout=subprocess.PIPE, text=True).stdout


def test_manual_clock(mcemu_start, request):
    from mcemu_testkit import find_binary
    from mcemu_testkit.plugin import _binary

    if not _has_clock_flag(find_binary(_binary(request.config))):
        pytest.skip("--clock is not in this mcemu (issue 13 item 2)")
    drive = mcemu_start(clock="manual").drive(1)
    t0 = drive.api.clock()["timeMs"]
    assert drive.api.clock()["mode"] == "manual"
    rg = drive.refgo()
    rg.go(1000)
    assert drive.api.clock()["timeMs"] == t0  # no drive time passes by itself
    assert drive.api.advance(5000) == t0 + 5000
    assert rg.tp() == 1000 and rg.ts() == 1
    with pytest.raises(ApiError) as e:
        mcemu_start().drive(1).api.advance(1)  # real clock
    assert e.value.status == 409
