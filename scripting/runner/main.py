# _mcemu_main: one run of a MovingCap CODE script (scripting.md §10.2). mcemu starts this process
# per run; it says hello, waits for the start message (sent 100 ms of drive time after the start
# request), compiles, reports the result, executes the script as "__main__" from "<stdin>" and
# reports how it ended. Tracebacks go to the console in the MicroPython form.
import os
import signal
import sys

import _mcemu_ipc
import _mcemu_modules
import _mcemu_source
import _mcemu_tb

FILENAME = '<stdin>'


def _install_line_sampler(channel):
    """SIGUSR1: store the line of the innermost <stdin> frame in the shared page, never on the
    socket (the handler may run while a send is half done)."""

    def on_usr1(signum, frame):
        f = frame
        while f is not None and f.f_code.co_filename != FILENAME:
            f = f.f_back
        # f_lineno is None while the frame stands between lines (CPython 3.11); whatever a handler
        # raises is raised in the script at the interrupted point, so it must not raise.
        line = f.f_lineno if f is not None else None
        if line is not None:
            channel.set_line(line)

    signal.signal(signal.SIGUSR1, on_usr1)


def _table(values):
    rows = []
    for k in range(0, len(values) - 4, 5):
        rows.append(tuple(values[k:k + 5]))
    return rows


def run(channel):
    channel.send(b'H', ('%d.%d.%d' % sys.version_info[:3]).encode())
    kind, body = channel.recv_message()
    if kind != 83:  # S
        return 3
    v = _mcemu_ipc.decode_values(body)
    strict, bind_address, platver, source = bool(v[0]), v[2], v[3], v[4]
    table = _table(v[5:])

    def log(text):
        channel.send(b'L', text.encode('utf-8', 'replace'))

    world = _mcemu_modules.World(channel, table, strict, _mcemu_modules.parse_platver(platver), bind_address, log)
    try:
        code = _mcemu_source.compile_script(source, strict)
    except _mcemu_source.CompileError as err:
        channel.output(_mcemu_tb.format_compile_error(err))
        channel.send(b'K', _mcemu_ipc.encode_values([0, err.line]))
        return 0
    channel.send(b'K', _mcemu_ipc.encode_values([1, 0]))
    scope = {'__name__': '__main__', '__builtins__': world.builtins}
    how, line = 0, 0
    try:
        exec(code, scope)
    except SystemExit:
        how = 1
    except _mcemu_ipc.Closed:
        return 0
    except BaseException as exc:  # noqa: B902 - every uncaught exception of the script
        how, line = 2, _mcemu_tb.innermost_line(exc)
        try:
            text = _mcemu_tb.format_exception(exc, strict)
        except MemoryError:
            text = _mcemu_tb.exception_line(exc, strict)
        exc = None
        channel.output(text)
    channel.send(b'E', _mcemu_ipc.encode_values([how, line]))
    return 0


def main():
    try:
        channel = _mcemu_ipc.Channel()
    except OSError:
        os._exit(4)
    _install_line_sampler(channel)
    status = 0
    try:
        status = run(channel)
    except _mcemu_ipc.Closed:
        status = 0
    except MemoryError:
        status = 5  # not even the traceback fitted: the loop reports an engine failure
    except BaseException as exc:  # a fault of the runner itself
        try:
            channel.send(b'F', ('%s: %s' % (type(exc).__name__, exc)).encode('utf-8', 'replace'))
        except BaseException:
            pass
        status = 6
    os._exit(status)
