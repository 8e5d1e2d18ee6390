"""The JSON API of web.md §8 over real HTTP against the mcemu binary (port 0): the routes that work
with the server's present wiring, the OpenAPI document walked route by route, and one request per
error class (400, 404, 405, 409, 413 from the transport, 415, 503)."""
import http.client
import json
import os
import re
import subprocess
import tempfile
import unittest

from mcemu_harness import MCEMU, Mcemu, wait_for

SAMPLE = {"{index}": "6041", "{sub}": "0", "{id}": "f999"}
# Routes whose call changes the drive or waits for a hook; the walk sends them only a body that
# cannot pass validation, so that it proves the route exists without acting.
ACTING = {("post", "/api/v1/store"), ("post", "/api/v1/factory-reset"), ("post", "/api/v1/power-cycle"),
          ("post", "/api/v1/clock/advance"), ("post", "/api/v1/refgo"), ("post", "/api/v1/faults"),
          ("put", "/api/v1/settings"), ("put", "/api/v1/io/physical-inputs"),
          ("put", "/api/v1/objects/{index}/{sub}"), ("put", "/api/v1/script"), ("post", "/api/v1/script/start"),
          ("post", "/api/v1/script/stop"), ("post", "/api/v1/script/pause"), ("post", "/api/v1/script/resume"),
          ("put", "/api/v1/script/autostart")}
# The raw body of an acting route whose refusal is not a JSON one (an empty script is refused).
REFUSED_BODY = {("put", "/api/v1/script"): b""}


class Client:
    def __init__(self, port):
        self.port = port

    def request(self, method, path, body=None, content_type="application/json", headers=None):
        c = http.client.HTTPConnection("127.0.0.1", self.port, timeout=10)
        try:
            data = body if isinstance(body, (bytes, type(None))) else json.dumps(body).encode()
            h = dict(headers or {})
            if data is not None and content_type:
                h["Content-Type"] = content_type
            c.request(method, path, body=data, headers=h)
            r = c.getresponse()
            return r.status, {k.lower(): v for k, v in r.getheaders()}, r.read()
        finally:
            c.close()

    def json(self, method, path, body=None, **kw):
        status, headers, data = self.request(method, path, body, **kw)
        return status, json.loads(data) if data else None


class WebApi(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.m = Mcemu()
        cls.c = Client(cls.m.ports["http"])

    @classmethod
    def tearDownClass(cls):
        cls.m.__exit__(None, None, None)

    def assert_error(self, status, body, expected_status, code=None):
        self.assertEqual(status, expected_status, body)
        self.assertIn("error", body)
        self.assertIn("message", body["error"])
        if code:
            self.assertEqual(body["error"]["code"], code)

    # ---- routes that work with the present wiring ------------------------------------------
    def test_info_and_clock(self):
        status, info = self.c.json("GET", "/api/v1/info")
        self.assertEqual(status, 200)
        self.assertEqual(info["emulator"], "mcemu")
        self.assertEqual(info["model"], "MC349")
        self.assertEqual(info["ports"]["http"], self.m.ports["http"])
        self.assertEqual(info["clock"], {"mode": "real", "scale": 1})
        self.assertTrue(info["scripting"]["available"], info["scripting"])
        self.assertRegex(info["scripting"]["engine"], r"^python3 3\.[0-9]+\.[0-9]+$")
        status, clock = self.c.json("GET", "/api/v1/clock")
        self.assertEqual((status, clock["mode"], clock["scale"]), (200, "real", 1))
        self.assertIsInstance(clock["timeMs"], int)

    def test_status_footer_follows_refgo(self):
        status, s = self.c.json("GET", "/api/v1/status")
        self.assertEqual(status, 200)
        self.assertEqual(s["footer"]["statwd"], "StatWd " + "%04Xh" % s["statusword"])
        status, r = self.c.json("POST", "/api/v1/refgo", {"line": "PWC"})
        self.assertEqual((status, r["reply"], r["answer"], r["ok"]), (200, "PWC\r\n>", None, True))
        wait_for(lambda: self.c.json("GET", "/api/v1/status")[1]["footer"]["live"] == "MC Live RDY", what="RDY")
        seq1 = self.c.json("GET", "/api/v1/status")[1]["seq"]
        seq2 = self.c.json("GET", "/api/v1/status")[1]["seq"]
        self.assertGreater(seq2, seq1)
        status, r = self.c.json("POST", "/api/v1/refgo", {"line": "OR6041,0,h"})
        self.assertTrue(r["answer"].startswith("OR6041,0,"), r)
        self.c.json("POST", "/api/v1/refgo", {"line": "PQ"})

    def test_objects_io_settings_scope_trace(self):
        status, o = self.c.json("GET", "/api/v1/objects/6083h/00h")
        self.assertEqual((status, o["index"], o["sub"]), (200, "6083h", "00h"))
        status, r = self.c.json("POST", "/api/v1/objects/read", {"objects": [["6083", 0], ["7000", 0]]})
        self.assertEqual(status, 200)
        self.assertEqual(r["values"][1], {"abortCode": "06020000h"})
        status, io = self.c.json("GET", "/api/v1/io")
        self.assertEqual(set(io), {"effective", "physical", "virtual", "outputs"})
        status, io = self.c.json("PUT", "/api/v1/io/physical-inputs", {"set": [1]})
        self.assertEqual((status, io["physical"]), (200, 65536))
        wait_for(lambda: self.c.json("GET", "/api/v1/status")[1]["footer"]["io"] == "I1.........O....", what="IN1")
        self.c.json("PUT", "/api/v1/io/physical-inputs", {"clear": [1]})
        status, s = self.c.json("PUT", "/api/v1/settings", {"traceScriptCalls": True})
        self.assertEqual((status, s["traceScriptCalls"]), (200, True))
        self.c.json("PUT", "/api/v1/settings", {"traceScriptCalls": False})
        status, scope = self.c.json("GET", "/api/v1/scope")
        self.assertEqual((status, scope["sampleMs"]), (200, 5))
        self.assertGreater(len(scope["pos"]), 0)
        self.assertEqual(len(scope["pos"]), len(scope["sw"]))
        status, t = self.c.json("GET", "/api/v1/trace?channels=api&limit=10000")
        self.assertEqual(status, 200)
        texts = [e["text"] for e in t["events"]]
        self.assertTrue(any(x.startswith("PUT io/physical-inputs") for x in texts), texts)
        self.assertTrue(all(e["channel"] == "api" for e in t["events"]))
        status, headers, text = self.c.request("GET", "/api/v1/trace/text?channels=api")
        self.assertEqual(status, 200)
        self.assertTrue(headers["content-type"].startswith("text/plain"))
        self.assertIn(" api event ", text.decode())
        status, headers, text = self.c.request("GET", "/api/v1/trace/candump")
        self.assertEqual(status, 200)
        for line in text.decode().splitlines():  # empty until the SLCAN side is traced
            self.assertRegex(line, r"^\(\d+\.\d{6}\) can0 [0-9A-F]{3,8}#")

    def test_faults_listing_and_removal(self):
        status, f = self.c.json("POST", "/api/v1/faults", {"kind": "udp.drop", "count": 3})
        self.assertEqual(status, 201, f)
        status, listed = self.c.json("GET", "/api/v1/faults")
        self.assertIn({"kind": "udp.drop", "count": 3, "id": f["id"], "remaining": 3}, listed["faults"])
        self.assertEqual(self.c.json("DELETE", f"/api/v1/faults/{f['id']}")[0], 200)
        status, body = self.c.json("DELETE", f"/api/v1/faults/{f['id']}")
        self.assert_error(status, body, 404, "not-found")

    def test_eds_is_the_dump(self):
        status, headers, eds = self.c.request("GET", "/api/v1/eds")
        self.assertEqual(status, 200)
        dump = subprocess.run([MCEMU, "--dump-eds"], capture_output=True, text=True, timeout=30).stdout
        strip = lambda t: [l for l in t.splitlines() if not re.match(r"^(Creation|Modification)(Date|Time)=", l)]
        self.assertEqual(strip(eds.decode()), strip(dump))

    def test_no_cors_and_no_store(self):
        for path in ("/api/v1/info", "/api/v1/status", "/api/v1/openapi.json"):
            status, headers, _ = self.c.request("GET", path, headers={"Origin": "http://evil.example"})
            self.assertEqual(status, 200)
            self.assertFalse([h for h in headers if h.startswith("access-control")], headers)
            self.assertEqual(headers["cache-control"], "no-store")

    # ---- the OpenAPI document, walked over HTTP ---------------------------------------------
    def test_openapi_describes_every_served_route(self):
        status, doc = self.c.json("GET", "/api/v1/openapi.json")
        self.assertEqual(status, 200)
        self.assertEqual(doc["openapi"], "3.0.3")
        self.assertGreaterEqual(len(doc["paths"]), 30)
        for path, methods in doc["paths"].items():
            concrete = path
            for k, v in SAMPLE.items():
                concrete = concrete.replace(k, v)
            for method in methods:
                body = None
                if method in ("post", "put"):
                    body = {"__not_a_field__": True} if (method, path) in ACTING else {}
                    body = REFUSED_BODY.get((method, path), body)
                status, headers, data = self.c.request(method.upper(), concrete, body)
                self.assertNotEqual(status, 405, f"{method} {path}")
                if (method, path) in ACTING:
                    self.assertEqual(status, 400, f"{method} {path}: refused, so the walk changed nothing")
                self.assertFalse(status == 404 and headers.get("content-type", "").startswith("text/html"),
                                 f"{method} {path} is not routed")
                self.assertNotIn(b"no API route", data, f"{method} {path} is not routed")
        # and the reverse: a path under /api/ that is not in the document is a JSON 404 (web.md §1.4:
        # API clients parse JSON); a page that does not exist is the HTML 404 page
        for method in ("GET", "POST", "DELETE"):
            status, headers, data = self.c.request(method, "/api/v1/not-a-route", {} if method == "POST" else None)
            self.assertEqual(headers["content-type"], "application/json", method)
            self.assert_error(status, json.loads(data), 404, "not-found")
            self.assertIn("/api/v1/not-a-route", json.loads(data)["error"]["message"])
        status, headers, data = self.c.request("GET", "/not-a-page.html")
        self.assertEqual(status, 404)
        self.assertTrue(headers["content-type"].startswith("text/html"))
        self.assertIn(b"/index.html", data)

    # ---- one request per error class ----------------------------------------------------
    def test_400_syntax(self):
        status, body = self.c.json("PUT", "/api/v1/objects/6083/0", b"{", content_type="application/json")
        self.assert_error(status, body, 400, "syntax")
        status, body = self.c.json("POST", "/api/v1/refgo", {"line": "TP\r"})
        self.assert_error(status, body, 400, "syntax")

    def test_400_range(self):
        """The JSON API is strict (object-dictionary.md §3.2): -1 to an UNSIGNED32 is a 400, not 0xFFFFFFFF."""
        before = self.c.json("GET", "/api/v1/objects/6083/0")[1]["value"]
        status, body = self.c.json("PUT", "/api/v1/objects/6083/0", {"value": -1})
        self.assert_error(status, body, 400, "range")
        self.assertEqual(body["error"]["abortCode"], "06090032h")
        self.assertEqual(self.c.json("GET", "/api/v1/objects/6083/0")[1]["value"], before, "nothing stored")

    def test_404_object(self):
        status, body = self.c.json("GET", "/api/v1/objects/7000/0")
        self.assert_error(status, body, 404, "abort")
        self.assertEqual(body["error"]["abortCode"], "06020000h")

    def test_405_with_allow(self):
        status, headers, data = self.c.request("DELETE", "/api/v1/info")
        self.assertEqual(status, 405)
        self.assertEqual(headers["allow"], "GET, HEAD")
        self.assert_error(status, json.loads(data), 405, "method")

    def test_409_refusal(self):
        status, body = self.c.json("PUT", "/api/v1/objects/6041/0", {"value": 1})
        self.assert_error(status, body, 409, "abort")
        self.assertEqual(body["error"]["abortCode"], "06010002h")
        status, body = self.c.json("POST", "/api/v1/clock/advance", {"ms": 10})
        self.assert_error(status, body, 409, "conflict")
        status, body = self.c.json("PUT", "/api/v1/io/physical-inputs", {"set": [9]})
        self.assert_error(status, body, 409, "conflict")
        self.assertIn("IN9", body["error"]["message"])

    def test_413_from_the_transport(self):
        c = http.client.HTTPConnection("127.0.0.1", self.m.ports["http"], timeout=10)
        try:
            c.putrequest("PUT", "/api/v1/objects/6083/0")
            c.putheader("Content-Type", "application/json")
            c.putheader("Content-Length", str(2 * 1024 * 1024))
            c.endheaders()
            r = c.getresponse()
            self.assertEqual(r.status, 413)
            self.assertIn("error", json.loads(r.read()))
        finally:
            c.close()
        self.assertEqual(self.c.json("GET", "/api/v1/objects/6083/0")[1]["value"], 1000, "nothing changed")

    def test_415_content_type(self):
        status, body = self.c.json("POST", "/api/v1/refgo", b'{"line": "PWC"}', content_type="text/plain")
        self.assert_error(status, body, 415, "content-type")
        status, body = self.c.json("POST", "/api/v1/store", b"", content_type="application/x-www-form-urlencoded")
        self.assert_error(status, body, 415, "content-type")
        status, _ = self.c.json("GET", "/api/v1/status")
        self.assertEqual(status, 200)

    def test_409_script_kill_without_a_script(self):
        status, body = self.c.json("POST", "/api/v1/faults", {"kind": "script.kill"})
        self.assert_error(status, body, 409, "conflict")

    def test_503_engine_unavailable(self):
        # scripting.md §10.1.8: a host without a usable python3 (here: one that does not exist)
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
            json.dump({"scripting": {"python": "/nonexistent/python3"}}, f)
        try:
            with Mcemu("--config", f.name) as m:
                status, body = Client(m.ports["http"]).json("POST", "/api/v1/script/start", {})
                self.assert_error(status, body, 503, "unavailable")
        finally:
            os.unlink(f.name)


class SettingsFromConfig(unittest.TestCase):
    """The start values of the runtime settings come from "settings" of --config (web.md §8.9)."""

    def config(self, doc):
        f = tempfile.NamedTemporaryFile("w", suffix=".json", delete=False)
        json.dump(doc, f)
        f.close()
        self.addCleanup(os.unlink, f.name)
        return f.name

    def test_start_values(self):
        with Mcemu("--config", self.config({"settings": {"scriptMemoryMiB": 64, "scriptStrict": False}})) as m:
            status, s = Client(m.ports["http"]).json("GET", "/api/v1/settings")
            self.assertEqual(status, 200)
            self.assertEqual(s, {"udpEmulatorNotes": False, "scriptStrict": False, "scriptMemoryMiB": 64,
                                 "traceScriptCalls": False})

    def test_unknown_setting_stops_start_up_naming_it(self):
        m = Mcemu("--config", self.config({"settings": {"bogus": 1}}), ready=False)
        rc = m.wait_exit(timeout=30)
        self.assertEqual(rc, 2)
        self.assertIn("bogus", m.log())
        if m.tmp:
            m.tmp.cleanup()


if __name__ == "__main__":
    unittest.main()
