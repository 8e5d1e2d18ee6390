# _mcemu_source: from the uploaded bytes to a code object (scripting.md §2.1, §9): decoding,
# indentation tabs expanded as MicroPython measures them, the strict-mode checks with
# MicroPython's error texts, and the rewrite of `/`, `/=`, `**`, `**=` into checked calls.
import ast
import io
import tokenize

FILENAME = '<stdin>'
TAB_SIZE = 8

# Names the rewrite calls; they live in the script's builtins (see _mcemu_modules).
TRUEDIV = '_mp_truediv_'
POW = '_mp_pow_'


class CompileError(Exception):
    """A script that does not compile: `name: message` at `line`. `parser` errors print one frame
    line without a scope (udp-debug.md §4.5); compiler errors carry `, in <module>`."""

    def __init__(self, name, message, line, parser=True):
        Exception.__init__(self, name, message, line)
        self.name = name
        self.message = message
        self.line = line
        self.parser = parser


def decode(data):
    """UTF-8 (a BOM dropped), else Latin-1 (scripting.md §2.1)."""
    if data.startswith(b'\xef\xbb\xbf'):
        data = data[3:]
    try:
        return data.decode('utf-8')
    except UnicodeDecodeError:
        return data.decode('latin-1')


def expand_tabs(text):
    """Expands the tabs in the leading white space of every line that starts a logical line (a
    tab advances to the next multiple of 8 columns); line numbers do not change."""
    out = []
    depth = 0          # open brackets
    quote = None       # the open string's delimiter, if a string spans lines
    continued = False  # the previous line ended in a backslash
    for line in text.splitlines(True):
        starts_logical = depth == 0 and quote is None and not continued
        i = 0
        if starts_logical:
            col = 0
            while i < len(line) and line[i] in ' \t\f':
                col = (col // TAB_SIZE + 1) * TAB_SIZE if line[i] == '\t' else (0 if line[i] == '\f' else col + 1)
                i += 1
            if '\t' in line[:i]:
                line = ' ' * col + line[i:]
                i = col
        continued = False
        n = len(line)
        while i < n:
            c = line[i]
            if quote is not None:
                if c == '\\':
                    i += 2
                    continue
                if line.startswith(quote, i):
                    i += len(quote)
                    quote = None
                    continue
                if c in '\r\n' and len(quote) == 1:
                    quote = None  # an unterminated string ends at the line end (a syntax error)
                i += 1
                continue
            if c == '#':
                break
            if c in '\'"':
                quote = line[i:i + 3] if line.startswith(c * 3, i) else c
                i += len(quote)
                continue
            if c in '([{':
                depth += 1
            elif c in ')]}':
                depth = max(0, depth - 1)
            elif c == '\\' and line[i + 1:].strip('\r\n') == '':
                continued = True
                break
            i += 1
        out.append(line)
    return ''.join(out)


# ---- strict checks (scripting.md §9)

_INVALID = 'invalid syntax'
_DECIMAL = 'decimal numbers not supported'
_KEEP_INDENT = ('unexpected indent', 'unindent does not match any outer indentation level')


def _violations(tree):
    found = []

    def add(node, message):
        found.append((node.lineno, node.col_offset, message))

    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and type(node.value) in (float, complex):
            add(node, _DECIMAL)
        elif isinstance(node, (ast.JoinedStr, ast.NamedExpr, ast.Match, ast.AnnAssign)):
            add(node, _INVALID)
        elif type(node).__name__ == 'TryStar':
            add(node, _INVALID)
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)) and node.args.posonlyargs:
            add(node.args.posonlyargs[0], _INVALID)
    return found


def _is_float_token(text):
    t = text.lower()
    if t.startswith(('0x', '0o', '0b')):
        return False
    return '.' in t or 'e' in t or t.endswith('j')


def _token_violation_before(text, line, col):
    """The first float literal or f-string before (line, col), found by the tokenizer: MicroPython's
    lexer reports those before a later syntax error."""
    try:
        for tok in tokenize.generate_tokens(io.StringIO(text).readline):
            if (tok.start[0], tok.start[1]) >= (line, col):
                return None
            if tok.type == tokenize.NUMBER and _is_float_token(tok.string):
                return tok.start[0], _DECIMAL
            if tok.type == tokenize.STRING:
                prefix = tok.string[:tok.string.find(tok.string[-1])].lower()
                if 'f' in prefix:
                    return tok.start[0], _INVALID
    except (tokenize.TokenError, SyntaxError, IndentationError):
        return None
    return None


def _parse_error(text, err, strict):
    line = err.lineno or 1
    if not strict:
        return CompileError(type(err).__name__, err.msg, line)
    if isinstance(err, IndentationError) and not isinstance(err, TabError) and err.msg in _KEEP_INDENT:
        name, message = 'IndentationError', err.msg
    else:
        name, message = 'SyntaxError', _INVALID
    earlier = _token_violation_before(text, line, max(0, (err.offset or 1) - 1))
    if earlier is not None:
        line, message = earlier
        name = 'SyntaxError'
    return CompileError(name, message, line)


class _Rewrite(ast.NodeTransformer):
    """`a / b` → _mp_truediv_(a, b), `a ** b` → _mp_pow_(a, b); the augmented forms evaluate their
    target once (temporaries for attribute and subscript targets)."""

    def __init__(self):
        self.temp = 0

    def visit_BinOp(self, node):
        self.generic_visit(node)
        name = TRUEDIV if isinstance(node.op, ast.Div) else POW if isinstance(node.op, ast.Pow) else None
        if name is None:
            return node
        call = ast.Call(func=ast.Name(id=name, ctx=ast.Load()), args=[node.left, node.right], keywords=[])
        return ast.copy_location(call, node)

    def visit_AugAssign(self, node):
        self.generic_visit(node)
        name = TRUEDIV if isinstance(node.op, ast.Div) else POW if isinstance(node.op, ast.Pow) else None
        if name is None:
            return node
        stmts = []
        target = node.target
        if isinstance(target, ast.Name):
            load = ast.Name(id=target.id, ctx=ast.Load())
            store = ast.Name(id=target.id, ctx=ast.Store())
        else:
            obj = self._temp(stmts, target.value, node)
            if isinstance(target, ast.Attribute):
                load = ast.Attribute(value=ast.Name(id=obj, ctx=ast.Load()), attr=target.attr, ctx=ast.Load())
                store = ast.Attribute(value=ast.Name(id=obj, ctx=ast.Load()), attr=target.attr, ctx=ast.Store())
            else:
                key = self._temp(stmts, target.slice, node)
                load = ast.Subscript(value=ast.Name(id=obj, ctx=ast.Load()), slice=ast.Name(id=key, ctx=ast.Load()),
                                     ctx=ast.Load())
                store = ast.Subscript(value=ast.Name(id=obj, ctx=ast.Load()), slice=ast.Name(id=key, ctx=ast.Load()),
                                      ctx=ast.Store())
        call = ast.Call(func=ast.Name(id=name, ctx=ast.Load()), args=[load, node.value], keywords=[])
        stmts.append(ast.Assign(targets=[store], value=call))
        for s in stmts:
            ast.copy_location(s, node)
            ast.fix_missing_locations(s)
        return stmts

    def _temp(self, stmts, value, node):
        self.temp += 1
        name = '_mp_t%d_' % self.temp
        stmts.append(ast.Assign(targets=[ast.Name(id=name, ctx=ast.Store())], value=value))
        return name


def compile_script(data, strict):
    """Bytes of the uploaded script → code object, or CompileError."""
    text = expand_tabs(decode(data))
    try:
        tree = ast.parse(text, FILENAME, 'exec')
    except SyntaxError as err:  # IndentationError and TabError too
        raise _parse_error(text, err, strict) from None
    except (ValueError, MemoryError, RecursionError) as err:  # NUL bytes, absurd nesting
        raise CompileError('SyntaxError', _INVALID if strict else str(err), 1) from None
    if strict:
        bad = _violations(tree)
        if bad:
            line, _, message = min(bad)
            raise CompileError('SyntaxError', message, line)
        tree = ast.fix_missing_locations(_Rewrite().visit(tree))
    try:
        return compile(tree, FILENAME, 'exec', dont_inherit=True)
    except SyntaxError as err:
        raise CompileError('SyntaxError', err.msg, err.lineno or 1, parser=False) from None
    except (ValueError, MemoryError, RecursionError) as err:
        raise CompileError('SyntaxError', _INVALID if strict else str(err), 1, parser=False) from None
