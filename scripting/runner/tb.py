# _mcemu_tb: tracebacks in the MicroPython v1.9.4 form (scripting.md §4, udp-debug.md §4.5). Only
# frames of the script itself (file "<stdin>") are listed; lines end in "\n" (the loop turns each
# into "\r\n").
FILENAME = '<stdin>'

# strict mode: names and texts forced to MicroPython's (scripting.md §9)
_STRICT_NAMES = {'RecursionError': 'RuntimeError', 'ModuleNotFoundError': 'ImportError'}


def script_frames(tb):
    """(line, function) of every <stdin> frame, outermost first."""
    frames = []
    while tb is not None:
        code = tb.tb_frame.f_code
        if code.co_filename == FILENAME:
            frames.append((tb.tb_lineno, code.co_name))
        tb = tb.tb_next
    return frames


def innermost_line(exc):
    frames = script_frames(exc.__traceback__)
    return frames[-1][0] if frames else 0


def _text(value):
    try:
        return str(value)
    except Exception:  # a broken __str__ must not hide the exception
        return '<%s object>' % type(value).__name__


def exception_line(exc, strict):
    name = type(exc).__name__
    args = exc.args if isinstance(getattr(exc, 'args', None), tuple) else ()
    if strict:
        if isinstance(exc, RecursionError):
            return 'RuntimeError: maximum recursion depth exceeded'
        name = _STRICT_NAMES.get(name, name)
        if name == 'ZeroDivisionError':
            return 'ZeroDivisionError: division by zero'
    if len(args) == 0:
        return name + ': '
    if len(args) == 1:
        return name + ': ' + _text(args[0])
    return name + ': ' + _text(args)


def format_exception(exc, strict):
    lines = ['Traceback (most recent call last):']
    for line, function in script_frames(exc.__traceback__):
        lines.append('  File "%s", line %d, in %s' % (FILENAME, line, function))
    lines.append(exception_line(exc, strict))
    return '\n'.join(lines) + '\n'


def format_compile_error(err):
    """A CompileError of _mcemu_source."""
    frame = '  File "%s", line %d' % (FILENAME, err.line)
    if not err.parser:
        frame += ', in <module>'
    return 'Traceback (most recent call last):\n%s\n%s: %s\n' % (frame, err.name, err.message)
