"""Unit tests of the Python runner of the script engine (scripting/runner/*.py), run by CTest with
Debian's /usr/bin/python3: tab expansion, the strict-mode checks and their line numbers, the
MicroPython traceback form, ticks arithmetic, mcnet settings and frame rules.

The runner modules are loaded exactly as mcemu's bootstrap loads them: one module object per file,
named _mcemu_<file>, registered in sys.modules, in the order of scripting/CMakeLists.txt.
"""
import os
import socket
import struct
import sys
import types
import unittest

RUNNER = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'scripting', 'runner')
ORDER = ['ipc', 'source', 'tb', 'mcnet', 'modules', 'main']


def load_runner():
    for name in ORDER:
        full = '_mcemu_' + name
        if full in sys.modules:
            continue
        with open(os.path.join(RUNNER, name + '.py'), 'rb') as f:
            src = f.read()
        m = types.ModuleType(full)
        sys.modules[full] = m
        exec(compile(src, '<mcemu:%s>' % full, 'exec'), m.__dict__)


load_runner()
source = sys.modules['_mcemu_source']
tb = sys.modules['_mcemu_tb']
mcnet = sys.modules['_mcemu_mcnet']
modules = sys.modules['_mcemu_modules']
ipc = sys.modules['_mcemu_ipc']


def compile_error(text, strict=True):
    try:
        source.compile_script(text.encode() if isinstance(text, str) else text, strict)
    except source.CompileError as e:
        return e.name, e.message, e.line, e.parser
    return None


def run_text(text, strict=True, builtins=None):
    """Compiles and runs a script; returns the formatted traceback of its exception, or None."""
    code = source.compile_script(text.encode(), strict)
    world_builtins = builtins if builtins is not None else _plain_builtins(strict)
    try:
        exec(code, {'__name__': '__main__', '__builtins__': world_builtins})
    except BaseException as exc:
        return tb.format_exception(exc, strict)
    return None


def _plain_builtins(strict):
    """The strict builtins without a channel (enough for arithmetic checks)."""
    w = modules.World.__new__(modules.World)
    w.strict = strict
    w.modules = {}
    w.stdout = None
    return modules.World._builtins(w)


class TabExpansion(unittest.TestCase):
    def test_tab_is_eight_columns(self):
        text = 'if 1:\n\tx = 1\n        y = 2\n'
        self.assertEqual(source.expand_tabs(text), 'if 1:\n        x = 1\n        y = 2\n')
        self.assertIsNone(compile_error(text))

    def test_tab_after_spaces_advances_to_next_stop(self):
        self.assertEqual(source.expand_tabs('if 1:\n   \tx = 1\n'), 'if 1:\n        x = 1\n')

    def test_tabs_inside_strings_and_continuations_stay(self):
        text = 's = """\n\tinside\n"""\nt = (1,\n\t2)\nu = 1 + \\\n\t2\n'
        self.assertEqual(source.expand_tabs(text), text)

    def test_line_numbers_do_not_change(self):
        text = 'x = 1\n\tif x:\n'
        self.assertEqual(source.expand_tabs(text).count('\n'), text.count('\n'))

    def test_crlf_source_compiles(self):
        self.assertIsNone(compile_error('if 1:\r\n\tx = 1\r\n'))


class StrictMode(unittest.TestCase):
    def test_float_literals(self):
        for lit in ('1.5', '1e3', '.5', '2j', '3.'):
            self.assertEqual(compile_error('x = 1\ny = %s\n' % lit),
                             ('SyntaxError', 'decimal numbers not supported', 2, True), lit)

    def test_hex_with_e_is_not_a_float(self):
        self.assertIsNone(compile_error('x = 0x1e\n'))

    def test_fstring(self):
        self.assertEqual(compile_error('a = 1\n\nb = f"{a}"\n'), ('SyntaxError', 'invalid syntax', 3, True))

    def test_newer_syntax(self):
        cases = {
            'if (n := 3):\n    pass\n': 1,
            'x = 1\nmatch x:\n    case 1:\n        pass\n': 2,
            'x = 1\ndef f(a, /, b):\n    pass\n': 2,
            'x: int = 1\n': 1,
            'try:\n    pass\nexcept* ValueError:\n    pass\n': 1,
        }
        for text, line in cases.items():
            self.assertEqual(compile_error(text), ('SyntaxError', 'invalid syntax', line, True), text)

    def test_first_construct_in_file_order(self):
        self.assertEqual(compile_error('a = f"x"\nb = 1.5\n')[2], 1)
        self.assertEqual(compile_error('a = 1.5\nb = f"x"\n')[1], 'decimal numbers not supported')

    def test_float_before_a_later_parse_error(self):
        self.assertEqual(compile_error('a = 2.5\nb = (\n'), ('SyntaxError', 'decimal numbers not supported', 1, True))

    def test_parser_messages(self):
        self.assertEqual(compile_error('x = 1\n  y = 2\n'), ('IndentationError', 'unexpected indent', 2, True))
        self.assertEqual(compile_error('if 1:\n    x = 1\n  y = 2\n'),
                         ('IndentationError', 'unindent does not match any outer indentation level', 3, True))
        self.assertEqual(compile_error('if 1:\nx = 1\n'), ('SyntaxError', 'invalid syntax', 2, True))
        self.assertEqual(compile_error('import mcdrive a drive\n'), ('SyntaxError', 'invalid syntax', 1, True))
        self.assertEqual(compile_error('x = (1,\n'), ('SyntaxError', 'invalid syntax', 1, True))

    def test_dlu_compile_error_line_22(self):
        text = '#id maxTRACK N23 demo rev8\n' + 'x = 1\n' * 20 + ' x = 2\n'
        err = compile_error(text)
        self.assertEqual(err, ('IndentationError', 'unexpected indent', 22, True))

    def test_compiler_errors_carry_the_scope(self):
        err = compile_error('x = 1\nreturn 5\n')
        self.assertEqual(err, ('SyntaxError', "'return' outside function", 2, False))

    def test_non_strict_keeps_engine_texts_and_allows_floats(self):
        self.assertIsNone(compile_error('x = 1.5\ny = f"{x}"\n', strict=False))
        name, message, line, _ = compile_error('if 1:\nx = 1\n', strict=False)
        self.assertEqual((name, line), ('IndentationError', 2))
        self.assertIn('expected an indented block', message)

    def test_true_division_of_ints(self):
        out = run_text('a = 7\nb = 2\nc = a / b\n')
        self.assertEqual(out, 'Traceback (most recent call last):\n  File "<stdin>", line 3, in <module>\n'
                              "TypeError: unsupported types for __truediv__: 'int', 'int'\n")
        self.assertIn('line 2', run_text('a = 7\na /= 0\n'))
        self.assertIn('__truediv__', run_text('class C:\n    pass\no = C()\no.v = 4\no.v /= 2\n'))
        self.assertIn('__truediv__', run_text('l = [4]\nl[0] /= 2\n'))

    def test_augmented_targets_evaluated_once(self):
        out = run_text('n = []\ndef k():\n    n.append(1)\n    return 0\nl = [2]\nl[k()] **= 3\nif l != [8] or n != [1]:\n'
                       '    raise ValueError(l, n)\n')
        self.assertIsNone(out)

    def test_negative_power(self):
        for expr in ('2 ** -1', 'pow(2, -1)'):
            self.assertEqual(run_text('x = %s\n' % expr).splitlines()[-1], 'ValueError: negative power with no float support')
        self.assertIsNone(run_text('x = 2 ** 10\nassert x == 1024\nassert pow(3, 2, 5) == 4\n'))

    def test_division_by_zero_text(self):
        for expr in ('1 // 0', '1 % 0', 'divmod(1, 0)'):
            self.assertEqual(run_text('x = %s\n' % expr).splitlines()[-1], 'ZeroDivisionError: division by zero')

    def test_removed_builtins(self):
        for name in ('float', 'complex', 'open', 'input'):
            self.assertEqual(run_text('x = %s\n' % name).splitlines()[-1], "NameError: name '%s' is not defined" % name)

    def test_non_strict_division(self):
        self.assertIsNone(run_text('x = 7 / 2\nassert x == 3.5\n', strict=False))


class Tracebacks(unittest.TestCase):
    def test_udp_vector_7_4(self):
        out = run_text('def f():\n    return 1 // 0\nf()\n')
        self.assertEqual(out, 'Traceback (most recent call last):\n  File "<stdin>", line 3, in <module>\n'
                              '  File "<stdin>", line 2, in f\nZeroDivisionError: division by zero\n')

    def test_exception_lines(self):
        self.assertEqual(run_text('raise ValueError\n').splitlines()[-1], 'ValueError: ')
        self.assertEqual(run_text('d = {}\nd["x"]\n').splitlines()[-1], 'KeyError: x')
        self.assertEqual(run_text('raise OSError(23)\n').splitlines()[-1], 'OSError: 23')
        self.assertEqual(run_text('raise ValueError("a", 1)\n').splitlines()[-1], "ValueError: ('a', 1)")

    def test_recursion_is_runtime_error(self):
        out = run_text('def f(n):\n    return f(n + 1)\nf(0)\n')
        self.assertEqual(out.splitlines()[-1], 'RuntimeError: maximum recursion depth exceeded')
        self.assertIn('  File "<stdin>", line 3, in <module>', out)

    def test_compile_error_form(self):
        err = source.CompileError('IndentationError', 'unexpected indent', 22)
        self.assertEqual(tb.format_compile_error(err),
                         'Traceback (most recent call last):\n  File "<stdin>", line 22\nIndentationError: unexpected indent\n')
        err = source.CompileError('SyntaxError', "'return' outside function", 2, parser=False)
        self.assertIn('line 2, in <module>\n', tb.format_compile_error(err))

    def test_engine_frames_are_hidden(self):
        out = run_text('x = pow(2, -3)\n')
        self.assertEqual(out.count('File'), 1)


class LineSampler(unittest.TestCase):
    """SIGUSR1 stores the line of the innermost <stdin> frame; a frame between lines has no line
    (f_lineno None), and the handler must not raise into the script then (it did: "TypeError:
    unsupported operand type(s) for &: 'NoneType' and 'int'" at line -1, under load)."""

    def handler(self):
        import signal
        before = signal.getsignal(signal.SIGUSR1)
        self.addCleanup(signal.signal, signal.SIGUSR1, before)
        lines = []
        channel = types.SimpleNamespace(set_line=lines.append)
        sys.modules['_mcemu_main']._install_line_sampler(channel)
        return signal.getsignal(signal.SIGUSR1), lines

    @staticmethod
    def frame(filename, lineno, back=None):
        return types.SimpleNamespace(f_code=types.SimpleNamespace(co_filename=filename), f_lineno=lineno, f_back=back)

    def test_innermost_script_frame(self):
        on_usr1, lines = self.handler()
        on_usr1(10, self.frame('<mcemu:_mcemu_modules>', 3, self.frame('<stdin>', 7)))
        self.assertEqual(lines, [7])

    def test_frame_between_lines_stores_nothing(self):
        on_usr1, lines = self.handler()
        on_usr1(10, self.frame('<stdin>', None))
        on_usr1(10, self.frame('<mcemu:_mcemu_modules>', 5))
        self.assertEqual(lines, [])


class Conversions(unittest.TestCase):
    def test_to_int(self):
        self.assertEqual(modules.to_int(True), 1)
        self.assertEqual(modules.to_int(-2**31), -2**31)
        with self.assertRaisesRegex(OverflowError, '^overflow converting long int to machine word$'):
            modules.to_int(2**31)
        with self.assertRaisesRegex(TypeError, "^can't convert str to int$"):
            modules.to_int('5')

    def test_platver(self):
        self.assertEqual(modules.parse_platver('v50.00.10.00_RE'), (50, 0, 10, 0))
        self.assertEqual(modules.parse_platver(''), (0, 0, 0, 0))

    def test_values_round_trip(self):
        vals = [None, 5, -1, 'tëxt', b'\x00\xff']
        self.assertEqual(ipc.decode_values(ipc.encode_values(vals)), vals)


class McNetRules(unittest.TestCase):
    def test_settings(self):
        self.assertEqual(mcnet.parse_settings('SERVER:502'), ('server', None, 502))
        self.assertEqual(mcnet.parse_settings('SERVER:192.168.1.5:502'), ('server', None, 502))
        self.assertEqual(mcnet.parse_settings('UDP:5000'), ('udp', None, 5000))
        self.assertEqual(mcnet.parse_settings('UDP:10.0.0.1:5000'), ('udp', '10.0.0.1', 5000))
        self.assertEqual(mcnet.parse_settings('plc.local:502'), ('client', 'plc.local', 502))
        for bad in ('', 'SERVER:', 'SERVER:x', 'SERVER:70000', 'a:b:c:d', ':5', 'UDP:', 5):
            self.assertIsNone(mcnet.parse_settings(bad), bad)

    def _object(self):
        cls = mcnet.make_class(mcnet.Service(lambda t: None), None, '127.0.0.1')
        o = cls.__new__(cls)
        o._rx = bytearray()
        o._mode = mcnet.LineMode()
        return o

    def test_frames(self):
        o = self._object()
        o._rx += b'junk<ab>cd<e'
        o._mode.start, o._mode.end = ord('<'), ord('>')
        self.assertEqual(bytes(o._frame()), b'<ab>')
        self.assertIsNone(o._frame())
        self.assertEqual(bytes(o._rx), b'<e')

    def test_min_len_skips_early_end_markers(self):
        o = self._object()
        o._rx += b'\x02\x03\x00\x00\x03\x01\x02\x03\x99\x03'
        o._mode.start, o._mode.end, o._mode.min_len, o._mode.max_len = 2, 3, 9, 9
        # the first end marker at position ≥ 9 (markers included) ends the frame
        self.assertIsNone(o._frame())
        o._rx[:] = b'\x02\x03\x00\x00\x03\x01\x02\x03\x03'
        self.assertEqual(len(o._frame()), 9)

    def test_max_len_resynchronises(self):
        o = self._object()
        o._rx += b'abcdefgh\n'
        o._mode.max_len = 4
        # no end marker within 4 bytes: the first byte is dropped until one is
        self.assertEqual(bytes(o._frame()), b'fgh\n')
        self.assertEqual(bytes(o._rx), b'')


class NetOpen(unittest.TestCase):
    """Channel.net_open: mcemu's reply carries the socket (SCM_RIGHTS); a sleep's 'W' that arrives
    first is kept for the sleep."""

    def setUp(self):
        import mmap
        self.runner_end, self.loop_end = socket.socketpair()
        self.channel = ipc.Channel(sock=self.runner_end, page=mmap.mmap(-1, ipc.PAGE_SIZE))

    def tearDown(self):
        self.runner_end.close()
        self.loop_end.close()

    def reply(self, values, fd=None):
        body = b'R' + ipc.encode_values(values)
        frame = struct.pack('<I', len(body)) + body
        if fd is None:
            self.loop_end.sendall(frame)
        else:
            socket.send_fds(self.loop_end, [frame[:3], frame[3:]], [fd])

    def request(self):
        head = self.loop_end.recv(4)
        body = self.loop_end.recv(struct.unpack('<I', head)[0])
        self.assertEqual(body[:1], b'N')
        return ipc.decode_values(body[1:])

    def test_the_socket_arrives_with_the_reply(self):
        a, b = socket.socketpair()
        wake = struct.pack('<I', 1) + b'W'
        self.loop_end.sendall(wake)  # a sleep's wake that came first
        self.reply([0, '10.0.0.7'], fd=a.fileno())
        err, sock, peer = self.channel.net_open('udp', 'plc', 5000)
        self.assertEqual(self.request(), ['udp', 'plc', 5000])
        self.assertEqual((err, peer), (0, '10.0.0.7'))
        a.close()  # the runner holds its own copy
        sock.sendall(b'x')
        self.assertEqual(b.recv(1), b'x')
        self.assertFalse(sock.getblocking())
        sock.close()
        b.close()
        self.assertEqual(self.channel.recv_message(), (87, b''), "the wake is kept for the sleep")

    def test_a_refusal_has_no_socket(self):
        self.reply([98, ''])
        self.assertEqual(self.channel.net_open('server', '', 80), (98, None, ''))
        with self.assertRaises(OSError) as e:
            mcnet._opened((98, None, ''))
        self.assertEqual(e.exception.errno, 98)


if __name__ == '__main__':
    unittest.main()
