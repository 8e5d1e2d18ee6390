"""docs/security.md over the real binary (issue 28): relaxing script settings is not open over HTTP
(403)."""
import json
import os
import tempfile
import unittest

from mcemu_harness import Mcemu


def write_file(text, suffix):
    with tempfile.NamedTemporaryFile("w", suffix=suffix, prefix="sec-", delete=False) as f:
        f.write(text)
    return f.name


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


if __name__ == "__main__":
    unittest.main()
