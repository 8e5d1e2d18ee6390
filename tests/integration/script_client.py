"""Clients for the MovingCap CODE integration tests (scripting.md, web.md §6, udp-debug.md §4).

- `upload_script`, `code_act`: the HTTP requests Fullmo's uploader (testing/mctk/uploader.py of
  KickdriveOliver/movingcap-code-suite) makes through python-requests 2.28 — written here byte for
  byte on a plain socket (python-requests is not needed; its bytes are the contract): a multipart
  POST /program.html and GET /program.html?codeAct=N, each on a new connection, and the status it
  checks (200).
- `UdpConsole`: a UDP 14999 listener (as Docklight or Fullmo's UdpMonitor) that registers with "\\r"
  and collects every datagram.
- `RefGo`: one TCP RefGo client with request/reply by prompt.
The WebSocket client of every integration test is ws_client.py.
Every wait is bounded and polls; nothing sleeps a fixed time where a condition can be polled.
"""
import os
import socket
import time

UPLOAD_FIELD = "Python script file for MovingCap CODE"
USER_AGENT = "python-requests/2.28.1"  # Debian bookworm's python3-requests


def _read_response(sock, timeout=10.0, head=False):
    """(status, headers dict lower-case, body) of one HTTP/1.1 response with Content-Length (none
    for a HEAD request)."""
    sock.settimeout(timeout)
    data = b""
    while b"\r\n\r\n" not in data:
        chunk = sock.recv(65536)
        if not chunk:
            raise ConnectionError("connection closed before the response header: %r" % data)
        data += chunk
    header, _, body = data.partition(b"\r\n\r\n")
    lines = header.decode("latin-1").split("\r\n")
    status = int(lines[0].split(" ")[1])
    headers = {}
    for line in lines[1:]:
        name, _, value = line.partition(":")
        headers[name.strip().lower()] = value.strip()
    length = 0 if head else int(headers.get("content-length", "0"))
    while len(body) < length:
        chunk = sock.recv(65536)
        if not chunk:
            break
        body += chunk
    return status, headers, body[:length]


def requests_multipart(field, filename, content, content_type="text/x-python", boundary=None):
    """urllib3 1.26's encode_multipart_formdata for one file field, as python-requests uses it."""
    boundary = boundary or os.urandom(16).hex()
    body = (b"--" + boundary.encode() + b"\r\n" +
            b'Content-Disposition: form-data; name="' + field.encode() + b'"; filename="' + filename.encode() +
            b'"\r\n' + b"Content-Type: " + content_type.encode() + b"\r\n\r\n" + content + b"\r\n" +
            b"--" + boundary.encode() + b"--\r\n")
    return body, "multipart/form-data; boundary=" + boundary


def upload_request(device, script_name, content, field=UPLOAD_FIELD, extra_headers=b""):
    """The bytes of `requests.post("http://" + device + "/program.html", files={field: (name, content,
    "text/x-python")})`: Host from the URL, then the session's default headers, then the body's."""
    body, ctype = requests_multipart(field, script_name, content)
    return (b"POST /program.html HTTP/1.1\r\n"
            b"Host: " + device.encode() + b"\r\n"
            b"User-Agent: " + USER_AGENT.encode() + b"\r\n"
            b"Accept-Encoding: gzip, deflate\r\n"
            b"Accept: */*\r\n"
            b"Connection: keep-alive\r\n" + extra_headers +
            b"Content-Length: " + str(len(body)).encode() + b"\r\n"
            b"Content-Type: " + ctype.encode() + b"\r\n"
            b"\r\n" + body)


def get_request(device, target, extra_headers=b""):
    """The bytes of `requests.get("http://" + device + target)`."""
    return (b"GET " + target.encode() + b" HTTP/1.1\r\n"
            b"Host: " + device.encode() + b"\r\n"
            b"User-Agent: " + USER_AGENT.encode() + b"\r\n"
            b"Accept-Encoding: gzip, deflate\r\n"
            b"Accept: */*\r\n"
            b"Connection: keep-alive\r\n" + extra_headers + b"\r\n")


def exchange(port, request, address="127.0.0.1", head=False):
    """One request on a new connection (each requests.post/get of UPL opens its own session)."""
    with socket.create_connection((address, port), timeout=10) as s:
        s.sendall(request)
        return _read_response(s, head=head)


def upload_script(port, content, script_name="script.py", extra_headers=b""):
    """UPL upload_script(): True when the answer is 200, and the (status, headers, body)."""
    answer = exchange(port, upload_request("127.0.0.1:%d" % port, script_name, content, extra_headers=extra_headers))
    return answer[0] == 200, answer


def code_act(port, n, extra_headers=b""):
    """UPL start_script() (n = 3) / stop_script() (n = 4): True when the answer is 200."""
    answer = exchange(port, get_request("127.0.0.1:%d" % port, "/program.html?codeAct=%d" % n, extra_headers))
    return answer[0] == 200, answer


class UdpConsole:
    """A registered UDP debug listener that keeps every datagram it receives."""

    def __init__(self, udp_port, address="127.0.0.1"):
        self.target = (address, udp_port)
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(("127.0.0.1", 0))
        self.datagrams = []
        self.register()

    def register(self):
        """Sends "\\r" (udp-debug.md §2) and waits for the prompt that ends the answer."""
        mark = len(self.datagrams)
        self.sock.sendto(b"\r", self.target)
        self.wait(lambda: b">\r\n" in b"".join(self.datagrams[mark:]), what="registration prompt")

    def poll(self, timeout=0.05):
        self.sock.settimeout(timeout)
        try:
            while True:
                data, _ = self.sock.recvfrom(65536)
                self.datagrams.append(data)
                self.sock.settimeout(0.001)
        except (socket.timeout, BlockingIOError):
            pass

    def text(self, since=0):
        return b"".join(self.datagrams[since:])

    def wait(self, predicate, timeout=10.0, what="UDP output"):
        deadline = time.monotonic() + timeout
        while True:
            if predicate():
                return
            if time.monotonic() > deadline:
                raise TimeoutError("no %s within %.0f s; got %r" % (what, timeout, self.text()[-3000:]))
            self.poll()

    def wait_for(self, needle, since=0, timeout=10.0):
        self.wait(lambda: needle in self.text(since), timeout, "%r" % needle)
        return self.text(since)

    def mark(self):
        self.poll(0.001)
        return len(self.datagrams)

    def close(self):
        self.sock.close()


class RefGo:
    """One RefGo connection; request() sends a line and returns the reply up to its prompt."""

    def __init__(self, port, address="127.0.0.1"):
        self.sock = socket.create_connection((address, port), timeout=10)
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.buf = b""

    def send(self, data):
        self.sock.sendall(data)

    def read_until(self, predicate, timeout=5.0):
        deadline = time.monotonic() + timeout
        while not predicate(self.buf):
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError("RefGo: no reply within %.1f s; got %r" % (timeout, self.buf))
            self.sock.settimeout(left)
            chunk = self.sock.recv(4096)
            if not chunk:
                raise ConnectionError("RefGo connection closed; got %r" % self.buf)
            self.buf += chunk
        out, self.buf = self.buf, b""
        return out

    def request(self, line, timeout=5.0):
        self.send(line.encode() + b"\r")
        return self.read_until(lambda b: b.endswith(b">"), timeout)

    def nothing_within(self, seconds):
        self.sock.settimeout(seconds)
        try:
            chunk = self.sock.recv(4096)
        except socket.timeout:
            return True
        self.buf += chunk
        return False

    def tp(self):
        reply = self.request("TP")
        return int(reply.split(b"\r\n")[1])

    def close(self):
        self.sock.close()


# A script of our own in attachment mode 3 (refgo.md §5): every RefGo line goes to the script, which
# answers "[line]>" (original case and spaces); polls refgo.read() and sleeps 1 ms when idle.
MODE3_ECHO = b"""#id mode 3 echo
import refgo
import sys
refgo.open(3)
while True:
    line = refgo.read()
    if line is None:
        sys.wait(1)
    else:
        refgo.write("[" + line + "]>")
"""
