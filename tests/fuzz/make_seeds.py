#!/usr/bin/env python3
"""Writes the seed corpora of tests/fuzz/<target>/corpus from the readable lists below.

Usage: tests/fuzz/make_seeds.py path/to/mcemu   (the binary's --dump-od gives the entry ordinals
that the session fuzzers use to pick an entry). The seeds are the spec's own examples (refgo.md
§14, slcan-canopen.md §3.8 and §6.10, README config keys, persistence.md §9 state files) encoded in
each target's record format; the files are committed, this script is how they were made.
"""
import json
import os
import subprocess
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def write(target, name, data):
    d = os.path.join(HERE, target, "corpus")
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def entries(mcemu):
    doc = json.loads(subprocess.run([mcemu, "--dump-od", "--model", "MC349"], check=True, capture_output=True).stdout)
    keys = [(o["index"], o["sub"]) for o in doc["entries"]]
    keys.sort()
    return {k: i for i, k in enumerate(keys)}


def u16(v):
    return bytes([v & 0xFF, (v >> 8) & 0xFF])


def chunk(b):
    """[len][bytes] records of at most 255 bytes."""
    out = b""
    while True:
        part, b = b[:255], b[255:]
        out += bytes([len(part)]) + part
        if not b:
            return out


# ---- refgo_session: (op & 0x0F) % 9 (0x10: connection B): 0 A bytes, 1 B bytes, 2 command, 3 OR/OW, 4 step, 5/6 write ok/fail,
#      7 FIN of A, 8 interpreter reset
def refgo_a(text):
    return b"\x00" + chunk(text)


def refgo_b(text):
    return b"\x01" + chunk(text)


def steps(n):
    out = b""
    while n > 0:
        k = min(n, 256)
        out += b"\x04" + bytes([k - 1])
        n -= k
    return out


def refgo_seeds():
    vectors = [b"tp\r", b"TP\r\n", b"TP\n", b"  \r", b"XYZ\r", b"A" * 300 + b"\r", b"OW6041,0,5\r", b"OR1234,0\r",
               b"OR6041,9\r", b"OW6060,0,99\r", b"OW340B,1,300\r", b"OW6040,0,X\r", b"OW607C,0,-10\rOR607C,0,h\r",
               b"OR1008,0\r", b"SO7\r", b"G1000\rTS\r", b" tp\r", b"SO\t7\r", b"TP\n\r", b"OR1234,0,h\r", b"REF200\r",
               b"SP4294967296\r", b"OW6067,0,100\rOR6067,0\r", b"OW 60FE,1,65536\r", b"OW3410,1,4242\rOR3410h,1h\r",
               b"OW3510H,1H,65536\r", b"TP\xff\r", b"OR3511,8\r"]
    for i, v in enumerate(vectors):
        write("refgo_session", f"vector_{i:02d}", refgo_a(v) + steps(20))
    session_2021 = b"".join(refgo_a(l + b"\r") for l in (b"REF35", b"SP720", b"AC5000", b"DE1000", b"G360"))
    session_2021 += refgo_a(b"G-7200\rTPSR\rTP\r") + steps(3000) + refgo_a(b"TPSR\rTP\rPQ\rOW3511,8,110\rOR3511,8\r")
    write("refgo_session", "session_2021", session_2021)
    homing = refgo_a(b"PWC\r") + b"".join(refgo_a(l + b"\r") for l in (
        b"OW6091,1,1", b"OW6091,2,1", b"OW6092,1,360", b"OW6092,2,1", b"OW6099,1,200", b"OW609A,0,400",
        b"OW6073,0,200", b"OW607C,0,-10", b"REF-19")) + steps(4000) + refgo_a(b"TP\rTPSR\rG0\rTPSR\r") + steps(2000)
    write("refgo_session", "homing_2022", homing)
    write("refgo_session", "store_ok", refgo_a(b"OW6083,0,4321\rOW1010,1,1702257011\rTS\rOR6083,0\r") + b"\x05")
    write("refgo_session", "store_fail", refgo_a(b"OW1010,1,1702257011\rTP\r") + refgo_b(b"TS\r") + b"\x06")
    write("refgo_session", "restore", refgo_a(b"OW1011,1,1684107116\rOR6083,0\r") + b"\x05" + refgo_a(b"G100\r"))
    write("refgo_session", "motor_store", refgo_a(b"OW3010,1,1702257011\rOR3010,2\r") + b"\x05")
    write("refgo_session", "back_and_forth", refgo_a(b"SP3600\rAC100000\rDE100000\rG1000\r") + steps(500) +
          refgo_a(b"RW100\rWT200\rRR\r") + steps(1500) + refgo_a(b"SM\r") + steps(300) + refgo_a(b"RR-500\r") +
          steps(200) + refgo_a(b"OW6060,0,3\r"))
    write("refgo_session", "interrupted_rr", refgo_a(b"SP720\rG720000\r") + steps(200) + refgo_a(b"SM\r") +
          steps(800) + refgo_a(b"PWC\rRW100\rRR\r") + steps(800))
    write("refgo_session", "jog", refgo_a(b"SP720\rJP500\r") + steps(600) + refgo_a(b"JN2000\rSP500\rJP\rJP100\rSM\r"))
    write("refgo_session", "power", refgo_a(b"PWC\rTPSR\rPQ\rPQ1\rSM\rCM\rSO7\rCO7\rTI\rTI3\r"))
    write("refgo_session", "half_close", refgo_a(b"TP\rTS\nTP") + b"\x07" + refgo_a(b"TS\r"))
    write("refgo_session", "store_then_fin", refgo_a(b"OW1010,1,1702257011\rTS\r") + b"\x07\x05")
    write("refgo_session", "two_clients", refgo_a(b"OW340F,1,7\r") + refgo_b(b"OR340F,1\r") + refgo_a(b"TP\r") +
          refgo_b(b"G500\rTS\r") + steps(100) + b"\x08")
    write("refgo_session", "structured", b"\x02\x00\x10\x00\x00\x00\x01\x00" + b"\x03\x10\x00\x01\x05\x00\x00\x00\x01")


# ---- slcan_node: 2 config bytes, then (op & 0x3F) % 12 (op & 0x80: client B, 0x40: variant): 0 raw, 1 SDO command, 2 upload,
#      3 segmented download, 4 block download, 5 block upload, 6 NMT, 7 SYNC/RPDO/guarding, 8/9 steps,
#      10 state-file write, 11 command line
def slcan_seeds(ordinal):
    def raw(text, b=False):
        return bytes([0x80 if b else 0x00]) + chunk(text)

    def ent(index, sub):
        return u16(ordinal[(index, sub)])

    cfg = b"\x00\x00"
    examples = [b"O\r", b"C\rS4\rO\rO\r", b"C\rS4\r\rO\rO\r", b"L\r", b"C\rS5\rF\rO\r", b"V\r", b"N\r",
                b"t63284041600000000000\r", b"t6328407a600000000000\r", b"t00020132\r", b"T12ABCDEF2AA55\r",
                b"r7321\r", b"Z1\r", b"F\r", b"\r", b"O\r\n", b"t63G0\r", b"t63290000000000000000\r",
                b"t6328404160\r", b"t080000\r", b"t8000\r", b"T200000000\r", b"r732100\r", b"K\r", b"O1\r",
                b"C\rt0800\rO\r", b"L\rt0800\r", b"A" * 100 + b"\r", b"t 0800\r", b"V\nF\n", b"O\n\r", b"v\r",
                b"s031C\r", b"M00000000\r", b"m00000000\r", b"W1\r", b"X1\r", b"Q1\r", b"U1\r"]
    for i, e in enumerate(examples):
        write("slcan_node", f"example_{i:02d}", cfg + raw(e) + b"\x08\x0a")
    write("slcan_node", "ack_cr", b"\x01\x00" + raw(b"t0800\r"))
    write("slcan_node", "ack_none_serial8", b"\x02\x01" + raw(b"t0800\rN\r"))
    write("slcan_node", "two_clients", cfg + raw(b"t63284041600000000000\r") + raw(b"O\r", True))
    # SDO (§6.10): expedited and segmented uploads and downloads, block transfers, aborts, timeouts
    write("slcan_node", "upload_6041", cfg + b"\x02" + ent(0x6041, 0) + b"\x00")
    write("slcan_node", "upload_1008_segmented", cfg + b"\x02" + ent(0x1008, 0) + b"\x05")
    write("slcan_node", "download_6083", cfg + b"\x01\x00\x03" + ent(0x6083, 0) + b"\xe8\x03\x00\x00")
    write("slcan_node", "segmented_download", cfg + b"\x03" + chunk(b"\x10\x27\x00\x00") + ent(0x6083, 0))
    write("slcan_node", "segmented_bad_toggle", cfg + b"\x43" + chunk(b"abcdefghij") + ent(0x3500, 1))
    write("slcan_node", "block_download", cfg + b"\x04" + chunk(b"\x10\x27\x00\x00") + b"\x00" + ent(0x6083, 0))
    write("slcan_node", "block_download_bad_crc", cfg + b"\x04" + chunk(bytes(range(40))) + b"\x02" + ent(0x1008, 0))
    write("slcan_node", "block_upload", cfg + b"\x05" + ent(0x1008, 0) + b"\x7e\x00\x02\x01\x7f\x02\x7f")
    write("slcan_node", "store", cfg + b"\x01\x00\x03" + ent(0x1010, 1) + b"save" + b"\x0a")
    write("slcan_node", "store_fail", cfg + b"\x01\x00\x03" + ent(0x1010, 1) + b"save" + b"\x4a")
    write("slcan_node", "restore", cfg + b"\x01\x00\x03" + ent(0x1011, 1) + b"load" + b"\x0a")
    write("slcan_node", "sdo_timeout", cfg + b"\x01\x00\x01" + ent(0x6083, 0) + b"\x08\x00\x00\x00" + b"\x09\x40")
    write("slcan_node", "abort", cfg + b"\x01\x0b\x00" + ent(0x1008, 0) + b"\x00\x00\x04\x05")
    # NMT, heartbeat, PDOs, SYNC, guarding
    write("slcan_node", "nmt_walk", cfg + b"\x06\x00\x01" + b"\x06\x01\x01" + b"\x06\x02\x00" + b"\x06\x03\x01" +
          b"\x09\x05" + b"\x06\x04\x01" + b"\x09\x02")
    write("slcan_node", "heartbeat", cfg + b"\x01\x00\x0b" + ent(0x1017, 0) + b"\x64\x00\x00\x00" + b"\x09\x20")
    write("slcan_node", "operational_pdos", cfg + b"\x06\x00\x01" + b"\x07\x01\x0f\x00\x00\x00\x00\x00\x00\x00\x02" +
          b"\x07\x00" + bytes(8) + b"\x00" + b"\x08\x40" + b"\x07\x07")
    write("slcan_node", "guarding", cfg + b"\x01\x00\x0b" + ent(0x100C, 0) + b"\x64\x00\x00\x00" + b"\x01\x00\x0f" +
          ent(0x100D, 0) + b"\x03\x00\x00\x00" + b"\x07\x07\x09\x10")
    write("slcan_node", "timestamps", cfg + b"\x0b\x08" + b"\x02" + ent(0x6041, 0) + b"\x00")


# ---- line_assembler: first byte = filter (bit 0: RefGo) and the rest cut at lengths from itself
def line_seeds():
    for i, s in enumerate([b"TP\r\nTS\n", b"O\r\n", b"V\nF\n", b"O\n\r", b"A" * 300 + b"\rTP\r", b"\tSO\t7\x01\x7f\r",
                           b"\r\r\n\n\r", b"x" * 70 + b"\n", b"TP\xff\rTP"]):
        write("line_assembler", f"refgo_{i}", b"\x01" + s)
        write("line_assembler", f"slcan_{i}", b"\x00" + s)


def codec_seeds():
    lines = [b"t63284041600000000000", b"T12ABCDEF2AA55", b"r7321", b"R1FFFFFFF8", b"t0800", b"t7FF8FFFFFFFFFFFFFFFF",
             b"O", b"Z1", b"s031C", b"M00000000", b"S9", b"V", b"t63G0", b"t6329", b"T200000000"]
    for i, l in enumerate(lines):
        write("slcan_codec", f"line_{i:02d}", l)


def config_seeds():
    docs = [
        {"model": "MC349", "ip": "10.0.0.7", "refgo-port": 0, "http_port": 8080, "log-level": "debug"},
        {"objects": {"6083.00": 2000, "3500.01": "demo"}},
        {"model": "MCFLAT", "model_overrides": {"encoder_inc": 4096}},
        {"plant": {"stops": [-30000, 1000000], "supply_nominal_V": 10}},
        {"homing": {"index_pulse_inc": 100}},
        {"slcan": {"frame_ack": "cr", "version": "1010", "serial_digits": 8, "queue_limit_bytes": 4096,
                   "max_clients": 2}},
        {"canopen": {"sdo_timeout_ms": 500, "sdo_block_size": 7, "dynamic_pdo_mapping": True,
                     "bootup_delay_ms": {"reset_node": 50, "reset_communication": 10}}},
        {"settings": {"udpEmulatorNotes": True}, "refgo": {"max_clients": 3}, "http": {"max_clients": 4}},
        {"max-clients": 1000, "idle-timeout": 30},
        {"model": "PUSHTRACK", "plant": {}},
    ]
    for i, d in enumerate(docs):
        write("config_json", f"doc_{i:02d}", json.dumps(d).encode())


def state_seeds():
    def doc(model, objects, crc=True):
        payload = {"objects": objects, "home_offset_inc": 12, "program": {"autostart": False, "script": None}}
        text = json.dumps(payload, separators=(",", ":"), sort_keys=True)
        d = {"format": "mcemu-drive-state", "format_version": 1, "model": model, "mcemu_version": "0.1.0",
             "written_utc": "2026-01-15T10:15:02Z", "payload": payload,
             "payload_crc32": "0x%08x" % (zlib.crc32(text.encode()) & 0xFFFFFFFF) if crc else "0x00000000"}
        return json.dumps(d, indent=2).encode()

    objs = {"6083.00": 2000, "6084.00": 3000, "607A.00": 10, "1017.00": 100, "3500.01": "demo", "5007.01": 10}
    write("state_file", "mc349", b"\x00" + doc("MC349", objs))
    write("state_file", "mc349_restamp", b"\x40" + doc("MC349", dict(objs, **{"6083.00": -1, "FFFF.00": 1}), False))
    write("state_file", "foreign_model", b"\x00" + doc("MCFLAT", objs))
    write("state_file", "mcflat", b"\x01" + doc("MCFLAT", {"6083.00": 5}))
    write("state_file", "bad_types", b"\x40" + doc("MC349", {"6083.00": "x", "3500.01": 5, "6060.00": 1.5}, False))
    write("state_file", "plant", b"\x80" + json.dumps({"format": "mcemu-plant-state", "format_version": 1,
                                                        "model": "MC349", "raw_position_inc": 123}).encode())


METHODS = {"GET": 0, "HEAD": 1, "POST": 2, "PUT": 3, "DELETE": 4, "PATCH": 5}


def http(method, target, body=b"", ctype=0, origin=0):
    """One raw-target request record of tests/fuzz/http_router.cpp (op 1)."""
    return (b"\x01" + bytes([METHODS[method]]) + chunk(target) + bytes([ctype, origin]) + chunk(body) + b"\x01")


def http_seeds():
    write("http_router", "info_status", http("GET", b"/api/v1/info") + http("GET", b"/api/v1/status") +
          http("HEAD", b"/api/v1/status"))
    write("http_router", "objects", http("GET", b"/api/v1/objects/6041/0") +
          http("PUT", b"/api/v1/objects/6083h/0", b'{"value": 1500}') +
          http("POST", b"/api/v1/objects/read", b'{"objects": [["6041", 0], ["6064", 0]]}') +
          http("PUT", b"/api/v1/objects/6041/0", b'{"value": 1}'))
    write("http_router", "refgo_move", http("POST", b"/api/v1/refgo", b'{"line": "PWC"}') +
          http("POST", b"/api/v1/refgo", b'{"line": "G10000"}') + b"\x02\xff\x02\xff" +
          http("GET", b"/api/v1/scope?sinceMs=0"))
    write("http_router", "store", http("POST", b"/api/v1/store", b"{}") + b"\x03" +
          http("POST", b"/api/v1/factory-reset", b"{}") + b"\x04")
    write("http_router", "faults", http("POST", b"/api/v1/faults", b'{"kind": "drive.inject", "cause": "stroke"}') +
          b"\x02\x20" + http("GET", b"/api/v1/faults") + http("DELETE", b"/api/v1/faults/f1") +
          http("POST", b"/api/v1/faults", b'{"kind": "drive.supply", "volts": 10, "durationMs": 50}') + b"\x02\x80")
    write("http_router", "cross_site", http("PUT", b"/api/v1/objects/6083h/0", b'{"value": 7}', 0, 2) +
          http("POST", b"/api/v1/store", b"{}", 2, 0) + http("POST", b"/api/v1/refgo", b'{"line": "TP"}', 1, 0))
    write("http_router", "clock_led_trace", http("POST", b"/api/v1/clock/advance", b'{"ms": 500}') +
          http("GET", b"/api/v1/led?fromMs=0&toMs=1200") + http("GET", b"/api/v1/trace?channels=http") +
          http("GET", b"/api/v1/trace/candump") + http("GET", b"/api/v1/openapi.json"))
    write("http_router", "settings_io", http("PUT", b"/api/v1/settings", b'{"udpEmulatorNotes": true}') +
          http("PUT", b"/api/v1/io/physical-inputs", b'{"mask": 1}') + http("GET", b"/api/v1/io") +
          http("POST", b"/api/v1/power-cycle", b"{}"))
    write("http_router", "pages", http("GET", b"/") + http("GET", b"/index.html") + http("GET", b"/nope") +
          http("GET", b"/api/v1/../../etc/passwd") + http("PATCH", b"/api/v1/info"))
    write("http_router", "routes", b"\x00\x00\x00\x00\x01\x00\x00\x00\x00" + b"\x00\x03\x05\x00\x00\x01\x00\x00\x00")


def ws_seeds():
    def text(t):
        return b"\x00" + chunk(t)
    write("ws_messages", "subscribe", text(b'{"subscribe": ["status", "trace"], "channels": ["refgo", "http"]}') +
          text(b'{"unsubscribe": ["status"]}') + text(b'{"subscribe": "udp"}') + text(b"not json"))
    write("ws_messages", "queue", b"\x02\x03\xff\x7f\x03\xff\x7f\x02\x04\x03" * 8 + b"\x03\xff\xff" * 4 +
          b"\x04\x07")
    write("ws_messages", "built", b"\x01\x02\x00\x02\x03\x00\x01\x02\x02\x02\x02")


def multipart_seeds():
    # the upload of web.md §6.1 as python-requests 2.28 sends it (Fullmo's uploader), and a browser's
    upl = (b"multipart/form-data; boundary=8f1a2b3c4d5e6f708192a3b4c5d6e7f8\n"
           b"--8f1a2b3c4d5e6f708192a3b4c5d6e7f8\r\nContent-Disposition: form-data; "
           b"name=\"Python script file for MovingCap CODE\"; filename=\"demo.py\"\r\n"
           b"Content-Type: text/x-python\r\n\r\n#id demo\r\nprint(1)\r\n\r\n"
           b"--8f1a2b3c4d5e6f708192a3b4c5d6e7f8--\r\n")
    write("multipart", "uploader", upl)
    write("multipart", "browser", b"multipart/form-data; boundary=\"----WebKitFormBoundaryAbC\"\n"
          b"pre\r\n------WebKitFormBoundaryAbC\r\ncontent-disposition: form-data; name=\"a\"\r\n\r\n1\r\n"
          b"------WebKitFormBoundaryAbC \r\nContent-Disposition: form-data; name=\"f\"; filename=\"q\\\"x.py\"\r\n"
          b"\r\n\x00\xff\r\n------WebKitFormBoundaryAbC--\r\nepilogue")


def ipc_frame(kind, body=b""):
    return (len(body) + 1).to_bytes(4, "little") + kind + body


def ipc_values(*values):
    """scripting/core/ipc.hpp values: None, int, bytes ('B'), str ('S')."""
    out = len(values).to_bytes(2, "little")
    for v in values:
        if v is None:
            out += b"N"
        elif isinstance(v, int):
            out += b"I" + (v & (2**64 - 1)).to_bytes(8, "little")
        else:
            raw = v.encode() if isinstance(v, str) else v
            out += (b"S" if isinstance(v, str) else b"B") + len(raw).to_bytes(4, "little") + raw
    return out


def script_ipc_seeds():
    """What a runner sends (hello, calls, output, sleeps, a socket request, the end) and what a
    script that writes on the socket itself could: a bad length, an unknown kind, half a frame."""
    run = (ipc_frame(b"H", b"3.11.2") + ipc_frame(b"K", ipc_values(1, 0)) +
           ipc_frame(b"C", (4).to_bytes(2, "little") + ipc_values()) +
           ipc_frame(b"C", (9).to_bytes(2, "little") + ipc_values(0x6041, 0)) +
           ipc_frame(b"O", b"hello\n") + ipc_frame(b"Z", ipc_values(1000000)) + ipc_frame(b"X") +
           ipc_frame(b"N", ipc_values("client", "127.0.0.1", 502)) + ipc_frame(b"N", ipc_values("server", "", 5000)) +
           ipc_frame(b"L", b"mcnet: cannot bind") + ipc_frame(b"E", ipc_values(2, 3)))
    write("script_ipc", "runner_session", b"\x07" + run)
    write("script_ipc", "values_all_tags",
          b"\x01" + ipc_frame(b"C", b"\x01\x00" + ipc_values(None, -1, b"\x00\xff", "t\u00ebxt")))
    write("script_ipc", "net_bad_kind", b"\x03" + ipc_frame(b"N", ipc_values("raw", "", 1)))
    write("script_ipc", "bad_length", b"\x02" + b"\x00\x00\x20\x00O")
    write("script_ipc", "unknown_kind", b"\x05" + ipc_frame(b"?", b"x"))
    write("script_ipc", "half_frame", b"\x02" + ipc_frame(b"O", b"abcdef")[:7])


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    ordinal = entries(sys.argv[1])
    refgo_seeds()
    slcan_seeds(ordinal)
    line_seeds()
    codec_seeds()
    config_seeds()
    state_seeds()
    http_seeds()
    ws_seeds()
    multipart_seeds()
    script_ipc_seeds()


if __name__ == "__main__":
    main()
