"""UDP console listener (udp-debug.md §2, §3)."""


def test_first_registration_gets_the_boot_log(mcemu_start):
    drive = mcemu_start("--ip", "10.1.2.3").drive(1)
    console = drive.udp()
    answer = console.register()
    assert answer.startswith(b"SYS_Initialize: The MPFS2 File System is mounted\r\n")
    assert answer.endswith(b"\r>\r\n")
    assert "IP Address: 10.1.2.3 " in console.lines()
    assert console.wait_line(r"^REFGO - opening server$") == "REFGO - opening server"
    assert console.register() == b"\r>\r\n"  # the backlog went to the first registration
    other = drive.udp()
    assert other.register(b"\r\n") == b"\r\n>\r\n"


def test_emulator_notes_reach_every_listener(mcemu_start):
    drive = mcemu_start(config={"settings": {"udpEmulatorNotes": True}}).drive(1)
    a, b = drive.udp(), drive.udp()
    a.register()
    b.register()
    assert not [line for line in a.lines() + b.lines() if "refgo client" in line]
    drive.refgo().tp()  # a RefGo connection is announced as an emulator note (udp-debug.md §4.7)
    assert "refgo client 127.0.0.1" in a.wait_line(r"refgo client .* connected")
    assert "refgo client 127.0.0.1" in b.wait_line(r"refgo client .* connected")
