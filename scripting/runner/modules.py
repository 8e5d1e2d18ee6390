# _mcemu_modules: the modules a script can import (scripting.md §5–§8.3) and its builtins. The
# engine's own `sys` and builtins are not changed; the script gets views made for it.
import builtins as _builtins
import gc as _gc
import re
import sys as _real_sys
import types

import _mcemu_mcnet
import _mcemu_tb

INT_MIN, INT_MAX = -(1 << 31), (1 << 31) - 1
TICKS_PERIOD = 1 << 30
TICKS_HALF = 1 << 29


def to_int(value):
    """MicroPython's mp_obj_get_int on a 32-bit port (scripting.md §5.2)."""
    t = type(value)
    if t is int:
        v = value
    elif isinstance(value, int):  # bool and int subclasses
        v = int(value)
    else:
        raise TypeError("can't convert %s to int" % t.__name__)
    if v < INT_MIN or v > INT_MAX:
        raise OverflowError('overflow converting long int to machine word')
    return v


def _arity_error(required, most, given):
    if required == most:
        return TypeError('function takes %d positional arguments but %d were given' % (most, given))
    if given < required:
        return TypeError('function missing %d required positional arguments' % (required - given))
    return TypeError('function expected at most %d arguments, got %d' % (most, given))


def _no_attribute(name):
    def __getattr__(attr):
        raise AttributeError("'module' object has no attribute '%s'" % attr)
    return __getattr__


def _c_function(f):
    """A module function as MicroPython's C functions take it: positional arguments only."""
    def w(*args, **kw):
        if kw:
            raise TypeError('function does not take keyword arguments')
        return f(*args)
    w.__name__ = w.__qualname__ = f.__name__
    return w


def _module(name):
    m = types.ModuleType(name)
    m.__getattr__ = _no_attribute(name)
    return m


def _drive_function(channel, fid, name, shape, required):
    most = len(shape)
    call = channel.call

    if most == 0:
        def f(*args, **kw):
            if kw:
                raise TypeError('function does not take keyword arguments')
            if args:
                raise _arity_error(0, 0, len(args))
            return call(fid, ())
    elif most == 1 and required == 1:
        def f(*args, **kw):
            if kw:
                raise TypeError('function does not take keyword arguments')
            if len(args) != 1:
                raise _arity_error(1, 1, len(args))
            return call(fid, (to_int(args[0]),))
    else:
        def f(*args, **kw):
            if kw:
                raise TypeError('function does not take keyword arguments')
            if not required <= len(args) <= most:
                raise _arity_error(required, most, len(args))
            return call(fid, tuple(to_int(a) for a in args))
    f.__name__ = f.__qualname__ = name
    return f


def _text_of(data):
    try:
        return data.decode('utf-8')
    except UnicodeDecodeError:
        return data.decode('latin-1')


class _Implementation(tuple):
    """sys.implementation: attributes name, version, platform, platver."""

    def __new__(cls, platver):
        self = tuple.__new__(cls, ('micropython', (1, 9, 4), 'movingcap', platver))
        return self

    name = property(lambda self: self[0])
    version = property(lambda self: self[1])
    platform = property(lambda self: self[2])
    platver = property(lambda self: self[3])

    def __repr__(self):
        return '(name=%r, version=%r, platform=%r, platver=%r)' % tuple(self)


def parse_platver(text):
    """"v50.00.10.00_RE" (100Ah) → (50, 0, 10, 0)."""
    nums = [int(n) for n in re.findall(r'\d+', text or '')][:4]
    return tuple(nums + [0] * (4 - len(nums)))


class Stream:
    def __init__(self, channel):
        self._channel = channel

    def write(self, text):
        if not isinstance(text, (str, bytes, bytearray)):
            raise TypeError("object with buffer protocol required")
        self._channel.output(text)
        return len(text)

    def flush(self):
        pass


class _Stdin:
    def read(self, *args):
        return ''

    def readline(self, *args):
        return ''


class World:
    """Everything the script sees; `modules` maps import names to module objects."""

    def __init__(self, channel, table, strict, platver, bind_address, log):
        self.channel = channel
        self.strict = strict
        self.modules = {}
        self.service = _mcemu_mcnet.Service(log)
        channel.service = self.service
        ids = {}
        drive = _module('mcdrive')
        for fid, module, name, shape, required in table:
            ids[module + '.' + name] = fid
            if module == 'mcdrive':
                setattr(drive, name, _drive_function(channel, fid, name, shape, required))
        self.ids = ids
        self.modules['mcdrive'] = self.modules['drive'] = drive
        self.modules['refgo'] = self._refgo()
        self.modules['mcnet'] = self._mcnet(bind_address)
        tm = self._time()
        self.modules['time'] = self.modules['utime'] = tm
        self.stdout = Stream(channel)
        self.modules['sys'] = self._sys(platver)
        self.modules['gc'] = self._gc()
        self.modules['micropython'] = self._micropython()
        self.builtins = self._builtins()

    # ---- refgo (scripting.md §6)
    def _refgo(self):
        m = _module('refgo')
        call, ids = self.channel.call, self.ids
        f_cmd, f_open, f_read = ids['refgo.cmd'], ids['refgo.open'], ids['refgo.read']
        f_write, f_close = ids['refgo.write'], ids['refgo.close']

        def cmd(*args, **kw):
            if kw:
                raise TypeError('function does not take keyword arguments')
            if len(args) != 1:
                raise _arity_error(1, 1, len(args))
            if not isinstance(args[0], str):
                raise TypeError("can't convert %s to str" % type(args[0]).__name__)
            return call(f_cmd, (args[0],))

        def open(*args, **kw):
            if kw:
                raise TypeError('function does not take keyword arguments')
            if len(args) == 1:
                mode = to_int(args[0])
            elif len(args) == 2:  # legacy open(name, number): 0 means mode 2
                number = to_int(args[1])
                mode = 2 if number == 0 else number
            else:
                raise _arity_error(1, 2, len(args))
            return call(f_open, (mode,))

        def read(*args, **kw):
            if kw:
                raise TypeError('function does not take keyword arguments')
            if len(args) not in (0, 2):
                raise _arity_error(0, 2, len(args))
            line = call(f_read, ())
            return None if line is None else _text_of(line)

        def write(*args, **kw):
            if kw:
                raise TypeError('function does not take keyword arguments')
            if len(args) not in (1, 3):
                raise _arity_error(1, 3, len(args))
            msg = args[-1]
            data = msg.encode('utf-8') if isinstance(msg, str) else bytes(msg)
            return call(f_write, (data,))

        def close(*args, **kw):
            if kw:
                raise TypeError('function does not take keyword arguments')
            if len(args) > 1:
                raise _arity_error(0, 1, len(args))
            return call(f_close, ())

        for f in (cmd, open, read, write, close):
            setattr(m, f.__name__, f)
        return m

    def _mcnet(self, bind_address):
        m = _module('mcnet')
        m.McNet = _mcemu_mcnet.make_class(self.service, self.channel, bind_address)
        return m

    # ---- time / utime (scripting.md §8.2)
    def _time(self):
        m = _module('time')
        ch = self.channel

        def sleep(seconds):
            if isinstance(seconds, int):
                ch.sleep_us(to_int(seconds) * 1000000)
            elif not self.strict and isinstance(seconds, float):
                ch.sleep_us(int(seconds * 1000000))
            else:
                raise TypeError("can't convert %s to int" % type(seconds).__name__)

        def sleep_ms(ms):
            ch.sleep_us(to_int(ms) * 1000)

        def sleep_us(us):
            ch.sleep_us(to_int(us))

        def ticks_ms():
            return ch.ticks_ms()

        def ticks_us():
            return ch.ticks_us()

        def ticks_add(t, d):
            return (to_int(t) + to_int(d)) % TICKS_PERIOD

        def ticks_diff(a, b):
            return ((to_int(a) - to_int(b) + TICKS_HALF) % TICKS_PERIOD) - TICKS_HALF

        for f in (sleep, sleep_ms, sleep_us, ticks_ms, ticks_us, ticks_add, ticks_diff):
            setattr(m, f.__name__, _c_function(f))
        return m

    # ---- sys (scripting.md §8.1)
    def _sys(self, platver):
        m = _module('sys')
        ch, world, tm = self.channel, self, self.modules['time']
        m.version = '3.4.0'
        m.version_info = (3, 4, 0)
        m.implementation = _Implementation(platver)
        m.platform = 'movingcap'
        m.byteorder = 'little'
        m.maxsize = 2147483647
        m.argv = []
        m.path = []
        m.stdin = _Stdin()
        m.stdout = self.stdout
        m.stderr = Stream(ch)
        cycle = [ch.ticks_ms()]

        def exit(retval=0):
            raise SystemExit(retval)

        def print_exception(exc, file=None):
            (file if file is not None else m.stdout).write(_mcemu_tb.format_exception(exc, world.strict))

        def exc_info():
            return _real_sys.exc_info()

        def cycle_time_ms(period):
            period = to_int(period)
            now = ch.ticks_ms()
            if period <= 0:
                cycle[0] = now
                return 0
            r = tm.ticks_diff(tm.ticks_add(cycle[0], period), now)
            if r > 0:
                ch.sleep_us(r * 1000)
            cycle[0] = tm.ticks_add(cycle[0], period) if r >= 0 else now
            return r

        def time():
            return ch.ticks_ms()

        def wait(ms):
            ch.sleep_us(to_int(ms) * 1000)

        for f in (exit, print_exception, exc_info, cycle_time_ms, time, wait):
            setattr(m, f.__name__, _c_function(f))
        return m

    def _gc(self):
        m = _module('gc')
        m.collect = lambda: _gc.collect() and None
        m.mem_free = lambda: 65536
        m.mem_alloc = lambda: 0
        m.enable = lambda: None
        m.disable = lambda: None
        return m

    def _micropython(self):
        m = _module('micropython')
        m.const = lambda x: x
        stdout = self.stdout
        m.mem_info = lambda *a: stdout.write('GC: total: 65536, used: 0, free: 65536\n') and None
        return m

    # ---- builtins (scripting.md §8.1, §8.3, §9)
    def _builtins(self):
        b = dict(_builtins.__dict__)
        world = self
        real_import = _builtins.__import__
        real_pow = _builtins.pow

        def print(*args, sep=' ', end='\n', file=None, flush=False):
            s = (' ' if sep is None else sep).join([str(a) for a in args]) + ('\n' if end is None else end)
            (file if file is not None else world.stdout).write(s)

        def __import__(name, globals=None, locals=None, fromlist=(), level=0):
            if level == 0 and name in world.modules:
                return world.modules[name]
            if world.strict:
                raise ImportError("no module named '%s'" % name)
            return real_import(name, globals, locals, fromlist, level)

        def _mp_truediv_(a, b):
            if isinstance(a, int) and isinstance(b, int):
                raise TypeError("unsupported types for __truediv__: 'int', 'int'")
            return a / b

        def _mp_pow_(a, e):
            if isinstance(a, int) and isinstance(e, int) and e < 0:
                raise ValueError('negative power with no float support')
            return a ** e

        def pow(*args):
            if len(args) == 2:
                return _mp_pow_(*args)
            return real_pow(*args)

        b['print'] = print
        b['__import__'] = __import__
        b['const'] = lambda x: x
        b['_mp_truediv_'] = _mp_truediv_
        b['_mp_pow_'] = _mp_pow_
        for name in ('exit', 'quit', 'help', 'copyright', 'credits', 'license'):
            b.pop(name, None)
        if self.strict:
            b['pow'] = pow
            for name in ('float', 'complex', 'open', 'input'):
                b.pop(name, None)
        return b
