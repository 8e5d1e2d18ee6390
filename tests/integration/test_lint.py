"""The dependency lint of tools/lint_deps.sh finds each kind of violation (and passes on the repo);
and the tests' own hygiene: one WebSocket client for every test (ws_client.py)."""
import os
import shutil
import subprocess
import tempfile
import unittest

LINT = os.path.join(os.path.dirname(__file__), "../../tools/lint_deps.sh")
ROOT = os.path.join(os.path.dirname(__file__), "../..")


def lint(root):
    return subprocess.run([LINT], capture_output=True, text=True, env=dict(os.environ, LINT_ROOT=root), timeout=60)


class Lint(unittest.TestCase):
    def test_repository_is_clean(self):
        r = lint(ROOT)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)

    def test_each_violation_is_found(self):
        cases = {
            "drive/x.cpp": '#include <boost/asio/io_context.hpp>\n',
            "drive/modes/y.hpp": '#include <thread>\n',
            "iofunc/z.cpp": 'auto t = std::chrono::steady_clock::now();\n',
            "protocols/refgo/a.cpp": '#include <spdlog/spdlog.h>\n',
            "protocols/slcan/b.cpp": '#include "protocols/canopen/node.hpp"\n',
            "web/api/c.cpp": '#include "web/net/http_server.hpp"\n',
            "drive/d.cpp": '#include "protocols/refgo/session.hpp"\n',
            "drive/e.cpp": 'std::this_thread::sleep_for(x);\n',
            "protocols/can/f.hpp": '#include <mutex>\n',
        }
        for path, text in cases.items():
            with tempfile.TemporaryDirectory() as tmp, self.subTest(path=path):
                full = os.path.join(tmp, path)
                os.makedirs(os.path.dirname(full))
                with open(full, "w") as f:
                    f.write(text)
                r = lint(tmp)
                self.assertEqual(r.returncode, 1, r.stdout)
                self.assertIn(path, r.stdout)

    def test_net_folders_may_do_io(self):
        with tempfile.TemporaryDirectory() as tmp:
            full = os.path.join(tmp, "protocols/refgo/net/n.cpp")
            os.makedirs(os.path.dirname(full))
            with open(full, "w") as f:
                f.write('#include <boost/asio/io_context.hpp>\n#include <spdlog/spdlog.h>\n')
            self.assertEqual(lint(tmp).returncode, 0)


class TestClients(unittest.TestCase):
    def test_one_websocket_client(self):
        """Issue 23: the integration tests share one WebSocket client, ws_client.py; no other test file
        of Python or JavaScript does a handshake of its own (the browser tests use the browser's)."""
        needles = ("258EAFA5-" + "E914-47DA-95CA-C5AB0DC85B11", "Sec-WebSocket-" + "Key")  # not found in this file
        handshakes = []
        for dirpath, dirs, files in os.walk(os.path.join(ROOT, "tests")):
            dirs[:] = [d for d in dirs if d != "node_modules"]
            for name in files:
                if not name.endswith((".py", ".mjs", ".js")):
                    continue
                path = os.path.join(dirpath, name)
                with open(path, encoding="utf-8", errors="replace") as f:
                    text = f.read()
                if any(n in text for n in needles):
                    handshakes.append(os.path.relpath(path, ROOT))
        self.assertEqual(handshakes, [os.path.join("tests", "integration", "ws_client.py")])


if __name__ == "__main__":
    unittest.main()
