#!/usr/bin/env python3
"""Start the mcemu of a built image inside the image's own file system and check it answers.

Usage: image_check.py ROOTFS INSPECT.json

ROOTFS is the mounted file system of a container created from the image (`podman mount`), INSPECT
the image's `podman image inspect` output. The image's ENTRYPOINT + CMD run as its USER, in its
WORKDIR, with its ENV, in a mount namespace whose root is ROOTFS (pivot_root) with /proc mounted —
what a container runtime would start, without one (`./tools/dev image`: these machines cannot run
containers). Not a chroot: the kernel refuses user namespaces to a chrooted process, and the
MovingCap CODE sandbox (bwrap, docs/security.md) needs one. Run it in a fresh network namespace
with `lo` up and net.ipv4.ip_unprivileged_port_start = 0 (as Docker sets it in a container), so
the drive's default ports, 80 included, are free and bindable by the non-root user.

The root file system is mounted read-only with only the image's VOLUMEs writable, as
deploy/k8s/statefulset.yaml runs it (readOnlyRootFilesystem, the state on a volume).

Checks: the four listeners on 0.0.0.0 at the drive's default ports, which are the image's EXPOSE
list; one RefGo answer; one HTTP answer; the UDP console; Store Permanently writes the state file
into the image's state volume as the image's user; a script runs, in the sandbox; SIGTERM ends it
with status 0. Every wait is
bounded and polls; exit status 0 = all checks passed.
"""
import ctypes
import errno
import json
import os
import re
import signal
import socket
import subprocess
import sys
import threading
import time
import urllib.request

DEFAULTS = {"refgo": ("tcp", 10001), "slcan": ("tcp", 15001), "http": ("tcp", 80), "udp": ("udp", 14999)}
# EXPOSE also names the FAULHABER binary protocol, which only the FH_ models open (docs/faulhaber.md).
EXPOSED = {f"{port}/{proto}" for proto, port in DEFAULTS.values()} | {"10002/tcp"}
LISTEN_RE = re.compile(r"listening: (\w+) (tcp|udp) (\S+):(\d+)")


def fail(message, log=None):
    print(f"image check FAILED: {message}", file=sys.stderr)
    if log is not None:
        print("--- mcemu log ---\n" + "\n".join(log), file=sys.stderr)
    sys.exit(1)


def wait_for(predicate, timeout, what):
    deadline = time.monotonic() + timeout
    while not (value := predicate()):
        if time.monotonic() > deadline:
            raise TimeoutError(what)
        time.sleep(0.02)
    return value


# pivot_root(2) has no libc wrapper; its number per architecture
SYS_PIVOT_ROOT = {"x86_64": 155, "aarch64": 41}
CLONE_NEWNS, MS_REC, MS_PRIVATE, MNT_DETACH = 0x20000, 0x4000, 1 << 18, 2


def enter_root(rootfs):
    """In the child, before exec: its own mount namespace with ROOTFS as / and a fresh /proc."""
    libc = ctypes.CDLL(None, use_errno=True)

    def check(rc, what):
        if rc != 0:
            raise OSError(ctypes.get_errno(), what)

    check(libc.unshare(CLONE_NEWNS), "unshare")
    check(libc.mount(None, b"/", None, MS_REC | MS_PRIVATE, None), "mount --make-rprivate /")
    check(libc.mount(b"proc", os.path.join(rootfs, "proc").encode(), b"proc", 0, None), "mount proc")
    os.chdir(rootfs)
    check(libc.syscall(SYS_PIVOT_ROOT[os.uname().machine], b".", b"."), "pivot_root")
    check(libc.umount2(b".", MNT_DETACH), "umount the old root")
    os.chdir("/")


def user_ids(rootfs, user):
    name, _, group = user.partition(":")
    for line in open(os.path.join(rootfs, "etc/passwd")):
        fields = line.split(":")
        if fields[0] == name or fields[2] == name:
            uid, gid = int(fields[2]), int(fields[3])
            break
    else:
        fail(f"user {name!r} of the image is not in its /etc/passwd")
    if group:
        gid = int(group) if group.isdigit() else next(
            int(l.split(":")[2]) for l in open(os.path.join(rootfs, "etc/group")) if l.split(":")[0] == group)
    return uid, gid


def main():
    rootfs, inspect_path = sys.argv[1], sys.argv[2]
    config = json.load(open(inspect_path))[0]["Config"]
    argv = (config.get("Entrypoint") or []) + (config.get("Cmd") or [])
    user = config.get("User") or "root"
    uid, gid = user_ids(rootfs, user)
    if uid == 0:
        fail(f"the image runs as root (USER {user!r})")
    workdir = config.get("WorkingDir") or "/"
    env = dict(e.split("=", 1) for e in config.get("Env") or [])
    exposed = set(config.get("ExposedPorts") or {})
    if exposed != EXPOSED:
        fail(f"EXPOSE {sorted(exposed)} is not the drives' default ports {sorted(EXPOSED)}")
    volumes = sorted(config.get("Volumes") or {})
    if volumes != ["/var/lib/mcemu/state"]:
        fail(f"VOLUME {volumes} is not the state directory of the ENTRYPOINT (/var/lib/mcemu/state)")
    # As deploy/k8s runs it: the root file system read-only, only the volumes writable (this runs
    # in a mount namespace of its own: the mounts vanish with it).
    subprocess.run(["mount", "--bind", rootfs, rootfs], check=True)
    for volume in volumes:
        path = os.path.join(rootfs, volume.lstrip("/"))
        subprocess.run(["mount", "--bind", path, path], check=True)
    subprocess.run(["mount", "-o", "remount,bind,ro", rootfs], check=True)
    # deploy/k8s gives the pod an emptyDir at /tmp: the script engine's working directory per run
    subprocess.run(["mount", "-t", "tmpfs", "-o", "size=16m,mode=1777", "tmpfs", os.path.join(rootfs, "tmp")],
                   check=True)
    if not os.path.isfile(os.path.join(rootfs, "usr/bin/python3")):
        fail("the image has no /usr/bin/python3 (the MovingCap CODE engine)")
    try:
        open(os.path.join(rootfs, "var/lib/mcemu/probe"), "w").close()
        fail("the root file system is still writable after the read-only remount")
    except OSError as e:
        if e.errno != errno.EROFS:
            raise
    print(f"image check: {' '.join(argv)} as {user} ({uid}:{gid}) in {workdir}, root {rootfs} "
          f"(read-only, writable volumes {volumes})")

    def enter():
        enter_root(rootfs)
        os.chdir(workdir)
        os.setgroups([])
        os.setgid(gid)
        os.setuid(uid)

    proc = subprocess.Popen(argv, preexec_fn=enter, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    log, listeners = [], {}

    def read():
        for line in proc.stdout:
            log.append(line.rstrip("\n"))
            if m := LISTEN_RE.search(line):
                listeners[m.group(1)] = (m.group(2), m.group(3), int(m.group(4)))

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        wait_for(lambda: proc.poll() is not None or any(" ready" in l for l in log), 20, "mcemu ready")
        if proc.poll() is not None:
            reader.join(2)
            fail(f"mcemu exited at start-up with status {proc.returncode}", log)
        for service, (proto, port) in DEFAULTS.items():
            if listeners.get(service) != (proto, "0.0.0.0", port):
                fail(f"{service}: expected 'listening: {service} {proto} 0.0.0.0:{port}', got {listeners.get(service)}",
                     log)
        status_uid = next(l for l in open(f"/proc/{proc.pid}/status") if l.startswith("Uid:")).split()[1]
        if int(status_uid) != uid:
            fail(f"mcemu runs as uid {status_uid}, not the image's user {uid}", log)

        with socket.create_connection(("127.0.0.1", 10001), timeout=5) as s:
            s.sendall(b"TP\r")
            reply = b""
            while not reply.endswith(b">"):
                chunk = s.recv(4096)
                if not chunk:
                    break
                reply += chunk
        if reply != b"TP\r\n0\r\n>":
            fail(f"RefGo TP answered {reply!r}", log)

        with urllib.request.urlopen("http://127.0.0.1:80/api/v1/info", timeout=5) as resp:
            info = json.load(resp)
        want = {"emulator": "mcemu", "bind": "0.0.0.0", "stateDir": "/var/lib/mcemu/state",
                "ports": {s: p for s, (_, p) in DEFAULTS.items()}}
        if {k: info.get(k) for k in want} != want:
            fail(f"GET /api/v1/info answered {info}", log)

        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as u:
            u.settimeout(5)
            u.bind(("127.0.0.1", 0))
            u.sendto(b"\r", ("127.0.0.1", 14999))
            data = b""
            while not data.endswith(b"\r>\r\n"):
                data += u.recv(4096)
        if b"IP Address: 192.168.2.150 " not in data:
            fail(f"UDP registration answered {data!r}", log)

        # a MovingCap CODE script runs in the image and prints on UDP 14999 (scripting.md §10)
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as u:
            u.settimeout(10)
            u.bind(("127.0.0.1", 0))
            u.sendto(b"\r", ("127.0.0.1", 14999))
            for path, body, ctype in (("/api/v1/script", b'#id image check\r\nprint("hello from the image")\r\n',
                                       "text/x-python"), ("/api/v1/script/start", b"{}", "application/json")):
                req = urllib.request.Request("http://127.0.0.1:80" + path, data=body,
                                             method="PUT" if path == "/api/v1/script" else "POST",
                                             headers={"Content-Type": ctype})
                urllib.request.urlopen(req, timeout=10).read()
            data = b""
            while b"hello from the image\r\n" not in data:
                data += u.recv(4096)
        with urllib.request.urlopen("http://127.0.0.1:80/api/v1/info", timeout=5) as resp:
            sandbox = json.load(resp)["scripting"].get("sandbox", {})
        if not sandbox.get("active"):
            fail(f"the script ran without its sandbox: {sandbox}", log)

        req = urllib.request.Request("http://127.0.0.1:80/api/v1/store", data=b"{}", method="POST",
                                     headers={"Content-Type": "application/json"})
        with urllib.request.urlopen(req, timeout=10) as resp:
            if json.load(resp) != {"ok": True}:
                fail("POST /api/v1/store did not answer ok", log)
        state = os.path.join(rootfs, "var/lib/mcemu/state/drive-1.json")
        if not os.path.isfile(state) or os.stat(state).st_uid != uid:
            fail(f"Store Permanently did not write {state} as uid {uid}", log)
    except (OSError, TimeoutError, ValueError) as e:
        fail(f"{type(e).__name__}: {e}", log)
    finally:
        if proc.poll() is None:
            proc.send_signal(signal.SIGTERM)
        try:
            rc = proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            rc = "killed after 10 s"
        reader.join(2)
    if rc != 0:
        fail(f"mcemu did not stop cleanly on SIGTERM: {rc}", log)
    print("image check passed: refgo 10001, slcan 15001, http 80, udp 14999 on 0.0.0.0; TP, /api/v1/info, "
          f"UDP boot log, a script in the sandbox, Store as uid {uid}, clean SIGTERM")


if __name__ == "__main__":
    main()
