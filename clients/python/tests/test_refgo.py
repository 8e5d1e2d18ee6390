"""RefGo client against the real binary (refgo.md §3, §8, §9)."""
import pytest

from mcemu_testkit import RefGoError


def test_move_and_poll(mcemu_drive):
    with mcemu_drive.refgo() as rg:
        assert rg.tp() == 0
        assert rg.ts() == 0  # power off after start-up
        rg.go(1000)
        assert rg.ts() == 2  # the set-point is accepted in the G call (refgo.md §7.1)
        rg.wait_idle()
        assert rg.tp() == 1000
        assert rg.ts() == 1
        assert rg.tpsr() & 0x100  # bit 8: powered


def test_object_read_and_write(mcemu_drive):
    rg = mcemu_drive.refgo()
    rg.ow(0x6081, 0, 1234)
    assert rg.or_(0x6081, 0) == 1234
    assert rg.or_(0x6081, 0, hex=True) == 0x4D2
    assert rg.or_(0x1008, 0) == "MC349_ETH_RE"  # string entries answer their text
    assert mcemu_drive.api.read(0x6081, 0) == 1234  # one dictionary behind every door


def test_refusals_raise_with_the_abort_code(mcemu_drive):
    rg = mcemu_drive.refgo()
    with pytest.raises(RefGoError) as e:
        rg.ow(0x6041, 0, 5)
    assert e.value.abort_code == 0x06010002
    with pytest.raises(RefGoError) as e:
        rg.or_(0x1234, 0)
    assert e.value.abort_code == 0x06020000


def test_exchange_returns_the_raw_reply(mcemu_drive):
    rg = mcemu_drive.refgo()
    reply = rg.exchange("or6041,0,h")
    assert reply.echo == "OR6041,0,H"
    assert reply.answer.startswith("OR6041,0,") and reply.answer.endswith("h")
    assert reply.raw == f"OR6041,0,H\r\n{reply.answer}\r\n>".encode()
    unknown = rg.exchange("ZZ")
    assert (unknown.raw, unknown.echo, unknown.answer) == (b">", None, None)
    assert rg.exchange("PO500").raw == b"PO500\r\n>"  # no answer line
    with pytest.raises(ValueError):
        rg.exchange("TP\rTS")
