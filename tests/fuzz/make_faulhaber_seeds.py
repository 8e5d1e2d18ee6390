#!/usr/bin/env python3
"""Writes the seed corpora of tests/fuzz/faulhaber_receiver and tests/fuzz/faulhaber_port from the
frames of faulhaber.md §3/§5 (the byte-exact example table and the reference frames), encoded in
each target's record format. Standalone (no mcemu binary needed); the files are committed, this
script is how they were made.

Usage: tests/fuzz/make_faulhaber_seeds.py
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))

# faulhaber.md §5 table and §3 reference frames: (name, host→drive?, hex)
SPEC = [
    ("read_6041", True, "53 07 01 01 41 60 00 73 45"),
    ("resp_6041_0040", False, "53 09 01 01 41 60 00 40 00 C2 45"),
    ("resp_6041_0427", False, "53 09 01 01 41 60 00 27 04 F4 45"),
    ("write_6040_0006", True, "53 09 01 02 40 60 00 06 00 2C 45"),
    ("resp_write_6040", False, "53 07 01 02 40 60 00 DB 45"),
    ("write_6040_000F", True, "53 09 01 02 40 60 00 0F 00 25 45"),
    ("write_6060_3", True, "53 08 01 02 60 60 00 03 A2 45"),
    ("resp_write_6060", False, "53 07 01 02 60 60 00 FB 45"),
    ("write_60FF_100", True, "53 0B 01 02 FF 60 00 64 00 00 00 59 45"),
    ("read_3005_09", True, "53 07 01 01 05 30 09 3B 45"),
    ("resp_3005_09", False, "53 0B 01 01 05 30 09 FF FF FF FF 9D 45"),
    ("read_1234", True, "53 07 01 01 34 12 00 8B 45"),
    ("error_1234", False, "53 0B 01 03 34 12 00 00 00 02 06 2B 45"),
    ("write_6041", True, "53 09 01 02 41 60 00 00 00 2B 45"),
    ("error_6041", False, "53 0B 01 03 41 60 00 02 00 01 06 78 45"),
    ("sw_0040", False, "53 06 01 05 40 00 17 45"),
    ("sw_0021", False, "53 06 01 05 21 00 23 45"),
    ("sw_0027", False, "53 06 01 05 27 00 8F 45"),
    ("sw_0427", False, "53 06 01 05 27 04 21 45"),
    ("emcy_3210", False, "53 0C 01 07 10 32 05 04 00 00 00 00 83 45"),
    ("emcy_reset", False, "53 0C 01 07 00 00 00 00 00 00 00 00 A0 45"),
    ("boot_mc5005", False, "53 0B 01 00 4D 43 20 35 30 30 35 8E 45"),
    ("boot_mcs", False, "53 13 01 00 4D 43 53 20 33 32 34 32 20 42 58 34 20 45 54 A8 45"),
    ("reset_node", True, "53 04 01 00 50 45"),
    ("cw_0006", True, "53 06 01 04 06 00 50 45"),
    ("cw_000F", True, "53 06 01 04 0F 00 59 45"),
    ("cw_ok", False, "53 05 01 04 00 55 45"),
    ("write_2400_04", True, "53 0B 01 02 00 24 04 00 00 01 00 29 45"),
    ("resp_write_2400_04", False, "53 07 01 02 00 24 04 8E 45"),
    ("emcy_8611", False, "53 0C 01 07 11 86 21 02 00 00 00 00 14 45"),
    ("abort_answer_1234", False, "53 07 01 03 34 12 00 DC 45"),
    ("read_6064", True, "53 07 01 01 64 60 00 56 45"),
    ("resp_6064_9", False, "53 0B 01 01 64 60 00 09 00 00 00 53 45"),
    ("resp_6041_0440", False, "53 09 01 01 41 60 00 40 04 6C 45"),
]


def b(text):
    return bytes.fromhex(text)


def crc8(data):
    crc = 0xFF
    for x in data:
        crc ^= x
        for _ in range(8):
            crc = (crc >> 1) ^ 0xD5 if crc & 1 else crc >> 1
    return crc


def frame(node, cmd, data=b""):
    body = bytes([len(data) + 4, node, cmd]) + data
    return b"S" + body + bytes([crc8(body)]) + b"E"


def write(target, name, data):
    d = os.path.join(HERE, target, "corpus")
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


# ---- faulhaber_receiver: [flags: bit 0 CRC on] then records [gap ms][len][bytes]
def rx_records(data, gap=1):
    out = b""
    while True:
        part, data = data[:255], data[255:]
        out += bytes([gap, len(part)]) + part
        if not data:
            return out


def receiver_seeds():
    for name, _, text in SPEC:
        write("faulhaber_receiver", name, b"\x01" + rx_records(b(text)))
    every = b"".join(b(t) for _, _, t in SPEC)
    write("faulhaber_receiver", "all_frames", b"\x01" + rx_records(every))
    read = b(SPEC[0][2])
    write("faulhaber_receiver", "garbage", b"\x01" + rx_records(b"\x00\x11\r\nE" + read))
    write("faulhaber_receiver", "stray_s", b"\x01" + rx_records(b"S" + read * 10))
    write("faulhaber_receiver", "stray_s_short_l", b"\x01" + rx_records(b"S\x05" + read))
    write("faulhaber_receiver", "wrong_e", b"\x01" + rx_records(read[:-1] + b"F" + read))
    bad_crc = read[:-2] + b"\x00E"
    write("faulhaber_receiver", "bad_crc_on", b"\x01" + rx_records(bad_crc + read))
    write("faulhaber_receiver", "bad_crc_off", b"\x00" + rx_records(bad_crc + read))
    write("faulhaber_receiver", "l_below_4", b"\x01" + rx_records(b"S\x00S\x01S\x02S\x03\x01\x00PE" + read))
    write("faulhaber_receiver", "timeout", b"\x01" + rx_records(read[:4]) + rx_records(read[4:], 51) +
          rx_records(read, 60))
    write("faulhaber_receiver", "slow_bytes", b"\x01" + b"".join(rx_records(read[i:i + 1], 50) for i in range(len(read))))
    write("faulhaber_receiver", "longest", b"\x01" + rx_records(frame(1, 0x42, b"S" * 251)))


# ---- faulhaber_port: [flags: bits 0-1 delay 0/1/5/20 ms, bit 2 output limit 1024] then records
#      op (& 0x7F) % 10: 0 bytes, 1 request, 2 statusword, 3 EMCY, 4 boot, 5 time, 6 Store done,
#      7 reconnect, 8 FIN, 9 0x2400 setting; bit 7 = connection B
def raw(data, client_b=False):
    out = b""
    while True:
        part, data = data[:255], data[255:]
        out += bytes([0x80 if client_b else 0x00, len(part)]) + part
        if not data:
            return out


def write_req(index, sub, value, node=1):
    return frame(node, 0x02, bytes([index & 0xFF, index >> 8, sub]) + value)


def read_req(index, sub, node=1):
    return frame(node, 0x01, bytes([index & 0xFF, index >> 8, sub]))


def port_seeds():
    for name, to_drive, text in SPEC:
        if to_drive:
            write("faulhaber_port", name, b"\x00" + raw(b(text)))
    cw6, cwf = b(SPEC[24][2]), b(SPEC[25][2])
    read = b(SPEC[0][2])
    write("faulhaber_port", "enable", b"\x00" + raw(cw6 + cwf + read) + raw(read, True))
    write("faulhaber_port", "net_mode", b"\x00" + raw(write_req(0x2400, 5, b"\x01") + cw6 + b(SPEC[23][2]) + read) +
          b"\x02\x40\x00\x04")
    write("faulhaber_port", "net_mode_2", b"\x00" + raw(write_req(0x2400, 5, b"\x02")))
    write("faulhaber_port", "async_off", b"\x00" + raw(b(SPEC[27][2]) + cw6) + b"\x02\x27\x04" +
          b"\x03\x10\x32\x05\x04\x00" + b"\x04")
    write("faulhaber_port", "one_byte_2400_04", b"\x00" + raw(write_req(0x2400, 4, b"\x00")))
    write("faulhaber_port", "crc_off", b"\x00" + raw(write_req(0x2400, 4, b"\x00\x00\x83\x00") + read[:-2] + b"\x00E"))
    write("faulhaber_port", "node_id", b"\x00" + raw(write_req(0x2400, 3, b"\x05") + read + read_req(0x6041, 0, 5)))
    write("faulhaber_port", "store", b"\x00" + raw(write_req(0x1010, 1, b"save") + read) + b"\x06\x01" + b"\x02\x21\x00")
    write("faulhaber_port", "store_fail_then_fin", b"\x00" + raw(write_req(0x1010, 1, b"save")) + b"\x08\x06\x00")
    write("faulhaber_port", "delay", b"\x02" + raw(cw6 + read) + raw(read, True) + b"\x05\x03\x05\x0a")
    write("faulhaber_port", "overflow", b"\x04" + raw(read * 120))
    write("faulhaber_port", "reset_node_l6", b"\x00" + raw(frame(1, 0x00, b"\xaa\xbb")))
    write("faulhaber_port", "abort", b"\x00" + raw(frame(1, 0x03, b"\x34\x12\x00\x00\x00\x00\x08")))
    write("faulhaber_port", "unsupported", b"\x00" + raw(frame(1, 0x06, b"\x41\x60\x00") + frame(1, 0x08) +
                                                         frame(1, 0x0D, b"\x08\x10\x00\x00")))
    write("faulhaber_port", "garbage_stray", b"\x00" + raw(b"\r\nS" + read * 10 + b"S\x00" + read))
    write("faulhaber_port", "other_node", b"\x00" + raw(read_req(0x6041, 0, 2)))
    write("faulhaber_port", "reconnect", b"\x00" + raw(cw6) + b"\x07" + raw(read) + b"\x87\x08" + raw(cwf))
    # structured requests: op 1 [command][node pick][u16 entry ordinal][shape][value bytes…][cut]
    write("faulhaber_port", "structured", b"\x00" + b"\x01\x02\x00\x21\x00\x82\x0f\x00\x04" +
          b"\x01\x01\x00\x22\x00\x80\x05" + b"\x01\x04\x00\x00\x00\x02\x06\x00\x03" +
          b"\x09\x01\x00\x03")


if __name__ == "__main__":
    receiver_seeds()
    port_seeds()
