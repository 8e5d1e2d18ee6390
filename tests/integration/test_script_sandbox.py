"""The OS sandbox around MovingCap CODE scripts over the real binary (issue 28, docs/security.md).

A script that tries to leave the drive — through introspection to `os`, `__import__` of the
interpreter's own builtins, a traceback frame walk, `ctypes` — and then to read or write host files,
connect to a local TCP listener, start a process, signal or trace mcemu, fork without end or fill
the disk: every attempt fails, the script gets an error it prints on UDP, mcemu and the other drive
of the process keep answering, and nothing on the host changes. Once with the default settings and
once with the MicroPython checks lifted (scriptStrict false from the config file).

Also: the sandbox is reported in GET /api/v1/info; where it cannot be set up (a bwrap that does not
exist) scripts do not start and every door says why, unless --unsafe-scripts; the script processes
die with mcemu.
"""
import json
import os
import signal
import socket
import tempfile
import threading
import time
import unittest

from mcemu_harness import Mcemu, wait_for
from script_client import RefGo, UdpConsole, code_act, get_request, exchange

# One attempt per line: "escape <name>: refused <Exception> <errno>" when it failed with an exception,
# "escape <name>: result <repr>" when it returned (the test judges the value). The routes to the
# interpreter's own machinery work in strict mode too (the MicroPython checks are not a sandbox).
ESCAPE = r'''#id escape
def attempt(name, f):
    try:
        r = f()
    except BaseException as e:
        print('escape %s: refused %s %s' % (name, type(e).__name__, getattr(e, 'errno', '')))
        return
    print('escape %s: result %r' % (name, r))

# introspection: a class of os, and its module's globals
OS_GLOBALS = None
for c in ().__class__.__base__.__subclasses__():
    if c.__name__ == '_wrap_close':
        OS_GLOBALS = c.__init__.__globals__
print('escape introspection: reached os.%s' % OS_GLOBALS['system'].__name__)
# __import__ and open of the interpreter's real builtins (the script's own have neither)
B = OS_GLOBALS['__builtins__']
if not isinstance(B, dict):
    B = B.__dict__
IMP = B['__import__']
OPEN = B['open']
os = IMP('os')
# a traceback frame walk to the runner's frames and their builtins
try:
    1 // 0
except ZeroDivisionError as e:
    f = e.__traceback__.tb_frame
    while f.f_back is not None:
        f = f.f_back
    FRAME_B = f.f_builtins
attempt('frame walk: read host file', lambda: FRAME_B['open'](SECRET).read())
attempt('read host file', lambda: OPEN(SECRET).read())
attempt('read /etc/shadow', lambda: OPEN('/etc/shadow').read())
attempt('read /proc/1/environ', lambda: OPEN('/proc/1/environ').read())
attempt('write host dir', lambda: OPEN(HOST_DIR + '/escaped', 'w'))
attempt('write /usr', lambda: OPEN('/usr/escaped', 'w'))
attempt('write /', lambda: OPEN('/escaped', 'w'))
attempt('connect local listener', lambda: IMP('socket').create_connection(('127.0.0.1', PORT), 2))
attempt('udp socket', lambda: IMP('socket').socket(2, 2))
attempt('os.system', lambda: os.system('id > ' + HOST_DIR + '/escaped-id'))
attempt('subprocess', lambda: IMP('subprocess').run(['/usr/bin/touch', HOST_DIR + '/escaped-touch']))
attempt('posix_spawn', lambda: os.posix_spawn('/usr/bin/true', ['true'], {}))
attempt('execv', lambda: os.execv('/usr/bin/true', ['true']))
attempt('kill mcemu', lambda: os.kill(MCEMU_PID, 9))
attempt('kill everything', lambda: os.kill(-1, 9))
def bomb():
    n = 0
    while n < 1000:
        os.fork()
        n += 1
    return n
attempt('fork bomb', bomb)
ct = IMP('ctypes')
libc = ct.CDLL(None, use_errno=True)
attempt('ctypes fork', lambda: (libc.fork(), ct.get_errno()))
attempt('ctypes ptrace mcemu', lambda: (libc.ptrace(16, MCEMU_PID, 0, 0), ct.get_errno()))
attempt('ctypes mount', lambda: (libc.mount(b'none', b'/usr', b'tmpfs', 0, None), ct.get_errno()))
attempt('ctypes unshare', lambda: (libc.unshare(0x10000000), ct.get_errno()))
attempt('setuid root', lambda: os.setuid(0))
def fill():
    f = OPEN('/tmp/fill', 'wb')
    n = 0
    while n < 4096:
        f.write(b'x' * 65536)
        f.flush()
        n += 1
    return n
attempt('fill the disk', fill)
print('escape done')
'''

# attempts that raise, with the errno they must fail with (1 EPERM, 2 ENOENT, 3 ESRCH, 28 ENOSPC,
# 30 EROFS; setuid(0) in the sandbox's user namespace: EINVAL 22, outside it EPERM 1)
REFUSED = {
    "frame walk: read host file": ("FileNotFoundError", "2"),
    "read host file": ("FileNotFoundError", "2"),
    "read /etc/shadow": ("FileNotFoundError", "2"),
    "read /proc/1/environ": ("FileNotFoundError", "2"),
    "write host dir": ("FileNotFoundError", "2"),
    "write /usr": ("OSError", "30"),
    "write /": ("OSError", "30"),
    "connect local listener": ("PermissionError", "1"),
    "udp socket": ("PermissionError", "1"),
    "subprocess": ("PermissionError", "1"),
    "posix_spawn": ("PermissionError", "1"),
    "execv": ("PermissionError", "1"),
    "kill mcemu": ("ProcessLookupError", "3"),
    "kill everything": ("ProcessLookupError", "3"),
    "fork bomb": ("PermissionError", "1"),
    "fill the disk": ("OSError", "28"),
}
# attempts that return: libc's -1 with errno EPERM; system()'s "could not run the shell" (127 << 8)
RESULT = {
    "ctypes fork": "(-1, 1)",
    "ctypes ptrace mcemu": "(-1, 1)",
    "ctypes mount": "(-1, 1)",
    "ctypes unshare": "(-1, 1)",
    "os.system": str(127 << 8),
}


def escape_lines(text):
    out = {}
    for line in text.decode("utf-8", "replace").splitlines():  # code: lines end in LF CR, prints CR LF
        if line.startswith("escape ") and ": " in line:
            name, _, what = line[len("escape "):].rpartition(": ")
            out[name] = what
    return out


def write_config(doc):
    with tempfile.NamedTemporaryFile("w", suffix=".json", prefix="sandbox-", delete=False) as f:
        json.dump(doc, f)
    return f.name


class Listener:
    """A local TCP listener that counts the connections it accepts."""

    def __init__(self):
        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(8)
        self.sock.settimeout(0.2)
        self.port = self.sock.getsockname()[1]
        self.accepted = 0
        self.stop = False
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self):
        while not self.stop:
            try:
                c, _ = self.sock.accept()
                self.accepted += 1
                c.close()
            except OSError:
                pass

    def close(self):
        self.stop = True
        self.thread.join(2)
        self.sock.close()


class Escapes:
    """The attempts against a two-drive process; subclasses say how mcemu is started."""

    ARGS = ()

    @classmethod
    def setUpClass(cls):
        cls.host = tempfile.TemporaryDirectory(prefix="mcemu-host-")
        cls.secret = os.path.join(cls.host.name, "secret.txt")
        with open(cls.secret, "w") as f:
            f.write("host secret\n")
        cls.m = Mcemu("--drives", "2", *cls.ARGS)

    @classmethod
    def tearDownClass(cls):
        cls.m.__exit__(None, None, None)
        cls.host.cleanup()

    def run_escape(self):
        m = self.m
        listener = Listener()
        udp = UdpConsole(m.ports["udp"])
        try:
            source = (ESCAPE.replace("SECRET", repr(self.secret)).replace("HOST_DIR", repr(self.host.name))
                      .replace("PORT", str(listener.port)).replace("MCEMU_PID", str(m.proc.pid)))
            status, _ = m.http("PUT", "/api/v1/script", source.encode(), content_type="text/x-python")
            self.assertEqual(status, 200)
            before = set(os.listdir(self.host.name))
            mark = udp.mark()
            status, _ = m.http("POST", "/api/v1/script/start", {})
            self.assertEqual(status, 200)
            udp.wait_for(b"escape done\r\n", mark, timeout=60)
            lines = escape_lines(udp.text(mark))
            wait_for(lambda: json.loads(m.http("GET", "/api/v1/script")[1])["state"] == "OFF", what="script ended")
            # every attempt failed with an error the script could print
            self.assertTrue(lines.get("introspection", "").startswith("reached os."), lines)
            for name, (exc, errno) in REFUSED.items():
                self.assertEqual(lines.get(name), "refused %s %s" % (exc, errno), name)
            for name, value in RESULT.items():
                self.assertEqual(lines.get(name), "result " + value, name)
            self.assertIn(lines.get("setuid root"), ("refused PermissionError 1", "refused OSError 22"))
            # nothing on the host changed, nothing connected, mcemu and the other drive answer
            self.assertEqual(set(os.listdir(self.host.name)), before)
            self.assertFalse(os.path.exists("/usr/escaped") or os.path.exists("/escaped"))
            self.assertEqual(listener.accepted, 0)
            self.assertIsNone(m.proc.poll(), "mcemu is alive")
            for drive in (1, 2):
                rg = RefGo(m.drives[drive]["refgo"][1], address=m.drives[drive]["refgo"][0])
                self.assertEqual(rg.request("TS"), b"TS\r\n0\r\n>", "drive %d answers RefGo" % drive)
                rg.close()
                status, _ = m.http("GET", "/api/v1/info", drive=drive)
                self.assertEqual(status, 200)
            # and a plain script still runs on the other drive of the process
            udp2 = UdpConsole(m.drives[2]["udp"][1], address=m.drives[2]["udp"][0])
            try:
                status, _ = m.http("PUT", "/api/v1/script", b"#id ok\nprint('drive 2 ok')\n",
                                   content_type="text/x-python", drive=2)
                self.assertEqual(status, 200)
                mark2 = udp2.mark()
                self.assertEqual(m.http("POST", "/api/v1/script/start", {}, drive=2)[0], 200)
                udp2.wait_for(b"drive 2 ok\r\n", mark2)
            finally:
                udp2.close()
        finally:
            udp.close()
            listener.close()
        return lines


class EscapesStrict(Escapes, unittest.TestCase):
    """Default settings: strict mode on."""

    def test_every_escape_fails(self):
        self.run_escape()


class EscapesWithTheChecksLifted(Escapes, unittest.TestCase):
    """scriptStrict false from the config file: the full CPython language, still inside the sandbox."""

    @classmethod
    def setUpClass(cls):
        cls.config = write_config({"settings": {"scriptStrict": False}})
        cls.ARGS = ("--config", cls.config)
        super().setUpClass()

    @classmethod
    def tearDownClass(cls):
        super().tearDownClass()
        os.unlink(cls.config)

    def test_every_escape_fails(self):
        self.run_escape()

    def test_direct_imports_fail_the_same_way(self):
        listener = Listener()
        udp = UdpConsole(self.m.ports["udp"])
        try:
            source = ("#id direct\nimport os, socket, subprocess\n"
                      "def attempt(name, f):\n"
                      "    try:\n"
                      "        f()\n"
                      "    except OSError as e:\n"
                      "        print('escape %s: refused %d' % (name, e.errno))\n"
                      "attempt('socket', lambda: socket.create_connection(('127.0.0.1', " + str(listener.port) +
                      "), 2))\n"
                      "attempt('fork', os.fork)\n"
                      "attempt('run', lambda: subprocess.run(['/usr/bin/id']))\n"
                      "attempt('open', lambda: open(" + repr(self.secret) + "))\n"
                      "print('escape done')\n")
            self.m.http("PUT", "/api/v1/script", source.encode(), content_type="text/x-python")
            mark = udp.mark()
            self.m.http("POST", "/api/v1/script/start", {})
            udp.wait_for(b"escape done\r\n", mark, timeout=30)
            self.assertEqual(escape_lines(udp.text(mark)),
                             {"socket": "refused 1", "fork": "refused 1", "run": "refused 1", "open": "refused 2"})
            self.assertEqual(listener.accepted, 0)
        finally:
            udp.close()
            listener.close()


def descendants(pid):
    """Every process below `pid` (its children's children too)."""
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        try:
            for task in os.listdir("/proc/%d/task" % p):
                with open("/proc/%d/task/%s/children" % (p, task)) as f:
                    kids = [int(k) for k in f.read().split()]
                    out += kids
                    todo += kids
        except (FileNotFoundError, ProcessLookupError):
            pass
    return out


def alive(pid):
    try:
        with open("/proc/%d/stat" % pid) as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False


class SandboxAvailability(unittest.TestCase):
    def test_info_says_the_scripts_are_sandboxed(self):
        with Mcemu() as m:
            sandbox = json.loads(m.http("GET", "/api/v1/info")[1])["scripting"]["sandbox"]
            self.assertEqual((sandbox["active"], sandbox["unsafe"]), (True, False))
            self.assertIn("no network", sandbox["description"])
            wait_for(lambda: m.has_line("sandbox bubblewrap"), what="the log line")

    def test_script_processes_die_with_mcemu(self):
        m = Mcemu()
        try:
            udp = UdpConsole(m.ports["udp"])
            m.http("PUT", "/api/v1/script", b"#id spin\nprint('spinning')\nwhile True:\n    pass\n",
                   content_type="text/x-python")
            mark = udp.mark()
            m.http("POST", "/api/v1/script/start", {})
            udp.wait_for(b"spinning\r\n", mark)
            udp.close()
            engine = descendants(m.proc.pid)
            self.assertGreaterEqual(len(engine), 2, "bwrap and python3 under mcemu")
            m.proc.send_signal(signal.SIGKILL)
            m.wait_exit()
            wait_for(lambda: not any(alive(p) for p in engine), timeout=10, what="the engine processes gone")
        finally:
            if m.proc.poll() is None:
                m.kill()
            if m.tmp:
                m.tmp.cleanup()

    def test_without_a_sandbox_scripts_do_not_start_and_everything_says_why(self):
        config = write_config({"scripting": {"bwrap": "/nonexistent/bwrap"}})
        try:
            with Mcemu("--config", config) as m:
                info = json.loads(m.http("GET", "/api/v1/info")[1])["scripting"]
                self.assertFalse(info["available"])
                self.assertIn("/nonexistent/bwrap", info["reason"])
                self.assertIn("--unsafe-scripts", info["reason"])
                self.assertEqual((info["sandbox"]["active"], info["sandbox"]["unsafe"]), (False, False))
                wait_for(lambda: m.has_line("script engine unavailable: scripts do not run because the script "
                                            "sandbox cannot be set up"), what="the log line")
                udp = UdpConsole(m.ports["udp"])
                try:
                    m.http("PUT", "/api/v1/script", b"#id nobox\nprint('ran')\n", content_type="text/x-python")
                    mark = udp.mark()
                    self.assertTrue(code_act(m.ports["http"], 3)[0])
                    udp.wait_for(b"code: engine unavailable, script id: nobox\n\r", mark)
                    text = udp.text(mark)
                    self.assertTrue(text.startswith(b"code: starting, script id: nobox\n\rcode: scripts do not run "
                                                    b"because the script sandbox cannot be set up ("), text)
                    self.assertEqual(text.count(b"\n\r"), 3, "starting, why, engine unavailable")
                    self.assertNotIn(b"ran", text)
                    self.assertEqual(m.http("POST", "/api/v1/script/start", {})[0], 503)
                finally:
                    udp.close()
                _, _, page = exchange(m.ports["http"], get_request("127.0.0.1:%d" % m.ports["http"], "/program.html"))
                self.assertIn(b"The script engine is not available: scripts do not run because", page)
        finally:
            os.unlink(config)

    def test_unsafe_scripts_run_without_it_and_say_so(self):
        config = write_config({"scripting": {"bwrap": "/nonexistent/bwrap"}})
        try:
            with Mcemu("--config", config, "--unsafe-scripts") as m:
                info = json.loads(m.http("GET", "/api/v1/info")[1])["scripting"]
                self.assertTrue(info["available"])
                self.assertEqual((info["sandbox"]["active"], info["sandbox"]["unsafe"]), (False, True))
                self.assertTrue(info["sandbox"]["reason"].startswith("UNSAFE"))
                udp = UdpConsole(m.ports["udp"])
                try:
                    m.http("PUT", "/api/v1/script", b"#id bare\nprint('ran')\n", content_type="text/x-python")
                    mark = udp.mark()
                    self.assertEqual(m.http("POST", "/api/v1/script/start", {})[0], 200)
                    udp.wait_for(b"ran\r\n", mark)
                    self.assertIn(b"code: UNSAFE: scripts run without the script sandbox", udp.text(mark))
                finally:
                    udp.close()
                wait_for(lambda: m.has_line("WITHOUT the sandbox (--unsafe-scripts)"), what="the warning")
                _, _, page = exchange(m.ports["http"], get_request("127.0.0.1:%d" % m.ports["http"], "/program.html"))
                self.assertIn(b"UNSAFE: scripts run without the script sandbox", page)
        finally:
            os.unlink(config)

    def test_unsafe_scripts_is_not_a_config_key(self):
        config = write_config({"unsafe_scripts": True})
        try:
            m = Mcemu("--config", config, ready=False)
            self.assertEqual(m.wait_exit(), 2)
            self.assertIn("unsafe_scripts", m.log())
        finally:
            os.unlink(config)


if __name__ == "__main__":
    unittest.main()
