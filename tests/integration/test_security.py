"""docs/security.md over the real binary (issue 28): relaxing script settings is not open over HTTP
(403), and --api-token protects mcemu's own emulator endpoints while the drive's stay open."""
import json
import os
import tempfile
import unittest
import urllib.request

from mcemu_harness import Mcemu

TOKEN = "k2P9-mcemu-test-token-0123456789"


def write_file(text, suffix):
    with tempfile.NamedTemporaryFile("w", suffix=suffix, prefix="sec-", delete=False) as f:
        f.write(text)
    return f.name


def request(m, method, path, body=None, token=None):
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request("http://127.0.0.1:%d%s" % (m.ports["http"], path), data=data, method=method)
    if data is not None:
        req.add_header("Content-Type", "application/json")
    if token is not None:
        req.add_header("Authorization", "Bearer " + token)
    try:
        with urllib.request.urlopen(req, timeout=10) as resp:
            return resp.status, resp.read(), dict(resp.headers)
    except urllib.error.HTTPError as e:
        return e.code, e.read(), dict(e.headers)


class RelaxingSettings(unittest.TestCase):
    def test_http_may_tighten_but_not_relax(self):
        with Mcemu() as m:
            for relax in ({"scriptStrict": False}, {"scriptMemoryMiB": 257}, {"scriptMemoryMiB": 4096}):
                status, body = m.http("PUT", "/api/v1/settings", relax)
                self.assertEqual(status, 403, relax)
                self.assertIn("config file", json.loads(body)["error"]["message"])
            settings = json.loads(m.http("GET", "/api/v1/settings")[1])
            self.assertEqual((settings["scriptStrict"], settings["scriptMemoryMiB"]), (True, 256), "nothing changed")
            self.assertEqual(m.http("PUT", "/api/v1/settings", {"scriptMemoryMiB": 64})[0], 200)
            self.assertEqual(m.http("PUT", "/api/v1/settings", {"scriptMemoryMiB": 256})[0], 200)

    def test_the_config_file_may_relax_them(self):
        config = write_file(json.dumps({"settings": {"scriptStrict": False, "scriptMemoryMiB": 512}}), ".json")
        try:
            with Mcemu("--config", config) as m:
                self.assertEqual(m.http("PUT", "/api/v1/settings", {"scriptStrict": True, "scriptMemoryMiB": 64})[0],
                                 200)
                self.assertEqual(m.http("PUT", "/api/v1/settings", {"scriptStrict": False, "scriptMemoryMiB": 512})[0],
                                 200, "back to what the config file allowed")
                self.assertEqual(m.http("PUT", "/api/v1/settings", {"scriptMemoryMiB": 513})[0], 403)
        finally:
            os.unlink(config)


class ApiToken(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.token_file = write_file(TOKEN + "\n", ".token")
        cls.m = Mcemu("--api-token", cls.token_file, "--clock", "manual")

    @classmethod
    def tearDownClass(cls):
        cls.m.__exit__(None, None, None)
        os.unlink(cls.token_file)

    def test_emulator_endpoints_need_the_token(self):
        for method, path, body in (("PUT", "/api/v1/settings", {"traceScriptCalls": False}),
                                   ("POST", "/api/v1/clock/advance", {"ms": 1}),
                                   ("POST", "/api/v1/power-cycle", {}),
                                   ("POST", "/api/v1/faults", {"kind": "udp.drop", "count": 1}),
                                   ("DELETE", "/api/v1/faults", None)):
            for token in (None, "wrong-" + TOKEN):
                status, answer, headers = request(self.m, method, path, body, token)
                self.assertEqual(status, 401, (method, path, token))
                self.assertEqual(json.loads(answer)["error"]["code"], "unauthorized")
                self.assertEqual(headers.get("WWW-Authenticate"), 'Bearer realm="mcemu"')
            status, _, _ = request(self.m, method, path, body, TOKEN)
            self.assertIn(status, (200, 201), (method, path))

    def test_the_drives_own_doors_stay_open(self):
        self.assertEqual(request(self.m, "GET", "/api/v1/info")[0], 200)
        self.assertEqual(request(self.m, "GET", "/api/v1/settings")[0], 200)
        self.assertEqual(request(self.m, "PUT", "/api/v1/objects/6083/0", {"value": 2000})[0], 200)
        self.assertEqual(request(self.m, "POST", "/api/v1/refgo", {"line": "TP"})[0], 200)
        self.assertEqual(request(self.m, "GET", "/index.html")[0], 200)

    def test_a_short_token_file_stops_start_up(self):
        short = write_file("short\n", ".token")
        try:
            m = Mcemu("--api-token", short, ready=False)
            self.assertEqual(m.wait_exit(), 2)
            self.assertIn("at least 16 characters", m.log())
        finally:
            os.unlink(short)


if __name__ == "__main__":
    unittest.main()
