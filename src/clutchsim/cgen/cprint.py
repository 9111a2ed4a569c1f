"""Print a generated network plant as C: one printer over the plant's own Python source.

The generated plant module (:mod:`clutchsim.network.codegen`) and the compiled helpers it
calls (the kernels the friction models declare, ``FrictionModel.kernels``, their
shared helpers, :func:`~clutchsim.network._kernels.table` and
:func:`~clutchsim.network._kernels.lock_solve`) are written in a small subset of Python that
numba compiles.  :func:`print_c` reads the same source (its :mod:`ast`) and prints it as
C99, following the call graph from the plant's entry points: nothing is written twice by
hand, so the C program cannot drift from the compiled plant.

The subset (anything else raises :class:`CPrintError` naming the construct, the function
and its line):

* statements: assignment (also to ``a, b = ...`` from a tuple, a conditional tuple or a
  call returning a tuple), augmented assignment, ``if``/``elif``/``else``, ``while``,
  ``for ... in range(...)``, ``return``, ``pass``, ``break``, ``continue``, calls;
* expressions: float/int/bool constants, arithmetic (``+ - * / // % **``), comparisons
  (chained too), ``and``/``or``/``not`` on conditions, conditional expressions, ``abs``,
  ``min``, ``max``, ``float``, ``int``, ``math.*`` functions and ``math.pi``, module-level
  numeric constants, calls of other compiled functions;
* arrays (float64): the entry points' arguments, local ``np.zeros``/``np.empty`` (or their
  stack forms ``local_zeros``/``local_empty``, :mod:`clutchsim.core._borrow`) of one or
  two dimensions, indexing ``a[i]``/``a[i, j]`` with integer indices, and slices
  ``a[i:j]`` passed to a function (a pointer into ``a``).

Types follow numba's: every function is specialised on the types of its arguments at
each call site (scalars ``double``/``int``/``bool``, 1-D and 2-D arrays); a local's type is
the join of the values assigned to it (``int`` and ``double`` give ``double``).
Arithmetic keeps Python's meaning where C differs: ``/`` is true division, ``//`` and
``%`` floor, ``min``/``max`` return the first of equal arguments.
"""

from __future__ import annotations

import ast
import inspect
import math
import textwrap
from dataclasses import dataclass, field

__all__ = ["CPrintError", "CProgram", "print_c"]

D, I, B, A1, A2 = "double", "int", "bool", "a1", "a2"
SCALARS = (D, I, B)

#: math functions the printer maps to <math.h> (same names)
_MATH = {"tanh", "exp", "log", "log1p", "expm1", "sqrt", "sin", "cos", "tan", "asin",
         "acos", "atan", "atan2", "sinh", "cosh", "atanh", "copysign", "fabs", "floor",
         "ceil", "hypot", "pow"}
_MATH_CONST = {"pi": math.pi, "e": math.e}
#: C keywords that are legal Python names
_C_WORDS = {"auto", "case", "char", "const", "default", "do", "double", "enum", "extern",
            "float", "goto", "inline", "int", "long", "register", "restrict", "short",
            "signed", "sizeof", "static", "struct", "switch", "typedef", "union",
            "unsigned", "void", "volatile"}
_BINOP = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*"}
_CMP = {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==",
        ast.NotEq: "!="}

#: the array constructors of the generated code and the kernels, and what they fill
_ARRAY_MAKERS = {"np.zeros": "zeros", "np.empty": "empty", "local_zeros": "zeros",
                 "local_empty": "empty"}


def _array_maker(func) -> str | None:
    """``"zeros"``/``"empty"`` when ``func`` (a call's function) creates a local array."""
    if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name):
        return _ARRAY_MAKERS.get(f"{func.value.id}.{func.attr}")
    if isinstance(func, ast.Name):
        return _ARRAY_MAKERS.get(func.id)
    return None


PRELUDE = """\
#include <math.h>
#include <string.h>

/* Python semantics where C differs */
static inline double cs_fmin(double a, double b) { return b < a ? b : a; }
static inline double cs_fmax(double a, double b) { return b > a ? b : a; }
static inline int cs_imin(int a, int b) { return b < a ? b : a; }
static inline int cs_imax(int a, int b) { return b > a ? b : a; }
static inline int cs_ifloordiv(int a, int b) {
    int q = a / b; if ((a % b != 0) && ((a < 0) != (b < 0))) q -= 1; return q; }
static inline int cs_imod(int a, int b) {
    int r = a % b; if (r != 0 && ((r < 0) != (b < 0))) r += b; return r; }
static inline double cs_fmod(double a, double b) {
    double r = fmod(a, b); if (r != 0.0 && ((r < 0.0) != (b < 0.0))) r += b; return r; }
static inline double cs_floordiv(double a, double b) { return floor(a / b); }
"""


class CPrintError(ValueError):
    """A construct of the plant's source that the C printer cannot print."""


@dataclass
class CProgram:
    """The printed C source and the entry points it defines (``name -> C prototype``)."""

    source: str
    entries: dict[str, str] = field(default_factory=dict)


def _join(a: str, b: str) -> str:
    if a == b:
        return a
    if a in SCALARS and b in SCALARS:
        if D in (a, b):
            return D
        return I
    raise CPrintError(f"a value that is both {a} and {b}")


@dataclass
class _Func:
    """One Python function to print: its tree, globals and where it came from."""

    name: str
    tree: ast.FunctionDef
    globals: dict
    where: str


def _func_of(obj, name: str) -> _Func:
    py = getattr(obj, "py_func", obj)
    try:
        src = textwrap.dedent(inspect.getsource(py))
    except (OSError, TypeError) as exc:
        raise CPrintError(f"the source of {name} cannot be read for printing as C") from exc
    tree = ast.parse(src).body[0]
    if not isinstance(tree, ast.FunctionDef):
        raise CPrintError(f"{name} is not a plain function")
    return _Func(name, tree, py.__globals__, f"{py.__module__}.{py.__name__}")


class _Printer:
    """Specialises and prints functions on demand (see :func:`print_c`)."""

    def __init__(self):
        self.specs: dict[tuple, tuple[str, str | tuple]] = {}   # (where, sig) -> (cname, ret)
        self.rets: dict[tuple, object] = {}
        self.funcs: list[tuple[str, str, str, bool]] = []   # (name, head, text, entry)
        self.names: set[str] = set()
        self.tuples: set[int] = set()

    def cname(self, fn: _Func) -> str:
        base = "cs_" + fn.name.lstrip("_")
        name, k = base, 2
        while name in self.names:
            name, k = f"{base}_{k}", k + 1
        self.names.add(name)
        return name

    def returns(self, fn: _Func, sig: tuple):
        """The return type of ``fn`` called with ``sig`` (inference only)."""
        key = (fn.where, sig)
        if key not in self.rets:
            self.rets[key] = _Body(self, fn, sig).infer()
        return self.rets[key]

    def function(self, fn: _Func, sig: tuple, cname: str | None = None, entry=False):
        """Print ``fn`` specialised on ``sig`` (once); its (C name, return type)."""
        key = (fn.where, sig)
        if key in self.specs:
            return self.specs[key]
        body = _Body(self, fn, sig)
        ret = body.infer()
        name = cname or self.cname(fn)
        self.specs[key] = (name, ret)
        text = body.render(name, ret)
        head = text.split("\n", 1)[0].rstrip(" {")
        self.funcs.append((name, head, text, entry))
        return name, ret


def _ctype(t) -> str:
    if isinstance(t, tuple):
        return f"cs_tup{t[1]}"
    return {D: "double", I: "int", B: "int", None: "void"}[t]


class _Body:
    """Type inference and printing of one specialisation of one function."""

    def __init__(self, pr: _Printer, fn: _Func, sig: tuple):
        self.pr, self.fn = pr, fn
        args = fn.tree.args
        if args.vararg or args.kwarg or args.kwonlyargs or args.defaults or args.posonlyargs:
            self.fail(fn.tree, "only positional arguments without defaults")
        self.params = [a.arg for a in args.args]
        if len(self.params) != len(sig):
            self.fail(fn.tree, f"called with {len(sig)} arguments, takes {len(self.params)}")
        self.types: dict[str, str] = dict(zip(self.params, sig))
        self.arrays: dict[str, tuple] = {}      # local arrays: name -> (size, ncols|None, zero)
        self.ret = "unset"
        self.final = False
        self.tmp = 0
        self.vla: set[str] = set()
        self.assigned = _assigned_names(fn.tree)

    # ------------------------------------------------------------------ errors
    def fail(self, node, what: str):
        line = getattr(node, "lineno", None)
        at = f" (line {line} of its source)" if line else ""
        code = ast.unparse(node).split("\n")[0][:80] if isinstance(node, ast.AST) else ""
        raise CPrintError(f"cannot print {self.fn.where} as C{at}: {what}"
                          + (f": {code!r}" if code else ""))

    def name(self, n: str) -> str:
        return n + "_" if n in _C_WORDS else n

    # ------------------------------------------------------------------ inference
    def infer(self):
        for _ in range(20):
            before = (dict(self.types), self.ret)
            self.ret = "unset"
            self.block(self.fn.tree.body, emit=False)
            if (dict(self.types), self.ret) == before:
                break
        else:
            self.fail(self.fn.tree, "the types of its locals do not settle")
        self.final = True
        return None if self.ret == "unset" else self.ret

    # ------------------------------------------------------------------ expressions
    def const(self, node):
        v = node.value
        if isinstance(v, bool):
            return ("1" if v else "0"), B
        if isinstance(v, int):
            return str(v), I
        if isinstance(v, float):
            if not math.isfinite(v):
                self.fail(node, "a non-finite constant")
            r = repr(v)
            return (r if any(c in r for c in ".en") else r + ".0"), D
        self.fail(node, f"a constant of type {type(v).__name__}")

    def glob(self, node, name: str):
        g = self.fn.globals
        if name not in g:
            self.fail(node, f"unknown name {name}")
        v = g[name]
        if isinstance(v, bool | int | float):
            return self.const(ast.Constant(value=bool(v) if isinstance(v, bool) else
                                           (int(v) if isinstance(v, int) else float(v))))
        self.fail(node, f"the global {name} is not a numeric constant")

    def expr(self, node) -> tuple[str, str]:
        """(C code, type) of an expression; arrays have type a1/a2."""
        if isinstance(node, ast.Constant):
            return self.const(node)
        if isinstance(node, ast.Name):
            if node.id in self.types:
                return self.name(node.id), self.types[node.id]
            if node.id in self.assigned:
                raise _NotYet()
            return self.glob(node, node.id)
        if isinstance(node, ast.Attribute):
            if isinstance(node.value, ast.Name) and node.value.id == "math" \
                    and node.attr in _MATH_CONST:
                return repr(_MATH_CONST[node.attr]), D
            self.fail(node, "an attribute other than math.pi/math.e")
        if isinstance(node, ast.BinOp):
            return self.binop(node)
        if isinstance(node, ast.UnaryOp):
            a, t = self.scalar(node.operand)
            if isinstance(node.op, ast.USub):
                return f"(-{a})", I if t == B else t
            if isinstance(node.op, ast.UAdd):
                return f"(+{a})", I if t == B else t
            if isinstance(node.op, ast.Not):
                return f"(!{a})", B
            self.fail(node, "the operator ~")
        if isinstance(node, ast.BoolOp):
            op = " && " if isinstance(node.op, ast.And) else " || "
            parts = []
            for v in node.values:
                a, t = self.scalar(v)
                if t != B:
                    self.fail(node, "and/or of a value that is not a condition")
                parts.append(a)
            return "(" + op.join(parts) + ")", B
        if isinstance(node, ast.Compare):
            left = node.left
            parts = []
            for op, right in zip(node.ops, node.comparators):
                if type(op) not in _CMP:
                    self.fail(node, f"the comparison {type(op).__name__}")
                a, _ = self.scalar(left)
                b, _ = self.scalar(right)
                parts.append(f"({a} {_CMP[type(op)]} {b})")
                left = right
            return ("(" + " && ".join(parts) + ")" if len(parts) > 1 else parts[0]), B
        if isinstance(node, ast.IfExp):
            c, _ = self.scalar(node.test)
            a, ta = self.scalar(node.body)
            b, tb = self.scalar(node.orelse)
            return f"({c} ? {a} : {b})", _join(ta, tb)
        if isinstance(node, ast.Subscript):
            return self.subscript(node)
        if isinstance(node, ast.Call):
            return self.call(node)
        self.fail(node, f"the construct {type(node).__name__}")

    def scalar(self, node):
        code, t = self.expr(node)
        if t not in SCALARS:
            self.fail(node, f"an array ({t}) where a number is needed")
        return code, t

    def binop(self, node):
        a, ta = self.scalar(node.left)
        b, tb = self.scalar(node.right)
        ints = ta in (I, B) and tb in (I, B)
        op = type(node.op)
        if op in _BINOP:
            return f"({a} {_BINOP[op]} {b})", I if ints else D
        if op is ast.Div:
            if ints:
                return f"((double)({a}) / (double)({b}))", D
            return f"({a} / {b})", D
        if op is ast.FloorDiv:
            return (f"cs_ifloordiv({a}, {b})", I) if ints else (f"cs_floordiv({a}, {b})", D)
        if op is ast.Mod:
            return (f"cs_imod({a}, {b})", I) if ints else (f"cs_fmod({a}, {b})", D)
        if op is ast.Pow:
            if ints:
                self.fail(node, "an integer power")
            return f"pow({a}, {b})", D
        self.fail(node, f"the operator {op.__name__}")

    def index(self, node):
        code, t = self.scalar(node)
        if t not in (I, B):
            self.fail(node, "an index that is not an integer")
        return code

    def subscript(self, node):
        base = node.value
        if not isinstance(base, ast.Name):
            self.fail(node, "indexing of something other than a named array")
        arr, t = self.expr(base)
        sl = node.slice
        if isinstance(sl, ast.Slice):
            self.fail(node, "a slice outside a call's arguments")
        if t == A1:
            if isinstance(sl, ast.Tuple):
                self.fail(node, "two indices into a one-dimensional array")
            return f"{arr}[{self.index(sl)}]", D
        if t == A2:
            if not (isinstance(sl, ast.Tuple) and len(sl.elts) == 2):
                self.fail(node, "a two-dimensional array needs two indices")
            i, j = (self.index(e) for e in sl.elts)
            return f"{arr}[({i}) * {self.ncols(base.id)} + ({j})]", D
        self.fail(node, f"indexing of a {t}")

    def ncols(self, name: str) -> str:
        if name in self.arrays:
            return str(self.arrays[name][1])
        return f"{self.name(name)}_nc"

    def argument(self, node):
        """(C argument list entries, type) of one call argument (arrays, slices)."""
        if isinstance(node, ast.Subscript) and isinstance(node.slice, ast.Slice):
            sl = node.slice
            if not isinstance(node.value, ast.Name):
                self.fail(node, "a slice of something other than a named array")
            arr, t = self.expr(node.value)
            if t != A1:
                self.fail(node, "a slice of a two-dimensional array")
            if sl.step is not None:
                self.fail(node, "a slice with a step")
            lo = self.index(sl.lower) if sl.lower is not None else "0"
            if sl.upper is not None:
                self.index(sl.upper)
            return [f"({arr} + {lo})"], A1
        code, t = self.expr(node)
        if t == A2:
            return [code, self.ncols(node.id)], A2
        return [code], t

    def call(self, node):
        f = node.func
        if node.keywords:
            self.fail(node, "keyword arguments")
        if isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) \
                and f.value.id == "math":
            if f.attr not in _MATH:
                self.fail(node, f"the function math.{f.attr}")
            args = [self.scalar(a)[0] for a in node.args]
            return f"{f.attr}({', '.join(args)})", D
        if isinstance(f, ast.Attribute):
            self.fail(node, f"a call of {ast.unparse(f)} outside an array's creation")
        if not isinstance(f, ast.Name):
            self.fail(node, "a call of an expression")
        if f.id in ("abs", "float", "int") and f.id not in self.fn.globals:
            if len(node.args) != 1:
                self.fail(node, f"{f.id} of {len(node.args)} arguments")
            a, t = self.scalar(node.args[0])
            if f.id == "abs":
                return (f"abs({a})", I) if t in (I, B) else (f"fabs({a})", D)
            if f.id == "float":
                return f"((double)({a}))", D
            return f"((int)({a}))", I
        if f.id in ("min", "max") and f.id not in self.fn.globals:
            if len(node.args) < 2:
                self.fail(node, f"{f.id} of fewer than two numbers")
            vals = [self.scalar(a) for a in node.args]
            ints = all(t in (I, B) for _, t in vals)
            fn = f"cs_{'i' if ints else 'f'}{f.id}"
            code = vals[0][0]
            for c, _ in vals[1:]:
                code = f"{fn}({code}, {c})"
            return code, I if ints else D
        target = self.fn.globals.get(f.id)
        if target is None or not callable(target) or f.id in ("range", "len", "print"):
            self.fail(node, f"a call of {f.id}")
        args, sig = [], []
        for a in node.args:
            codes, t = self.argument(a)
            args += codes
            sig.append(t)
        callee = _func_of(target, f.id)
        if self.final:
            cname, ret = self.pr.function(callee, tuple(sig))
        else:
            cname, ret = "?", self.pr.returns(callee, tuple(sig))
        return f"{cname}({', '.join(args)})", ret

    def tuple_value(self, node, n: int) -> list[tuple[str, str]] | tuple[str, int]:
        """Components of a tuple-valued expression: a list of (code, type), or
        ``(call code, n)`` for a call returning a tuple."""
        if isinstance(node, ast.Tuple):
            if len(node.elts) != n:
                self.fail(node, f"{len(node.elts)} values for {n} targets")
            return [self.scalar(e) for e in node.elts]
        if isinstance(node, ast.IfExp):
            c, _ = self.scalar(node.test)
            a = self.tuple_value(node.body, n)
            b = self.tuple_value(node.orelse, n)
            if not (isinstance(a, list) and isinstance(b, list)):
                self.fail(node, "a conditional between calls returning tuples")
            return [(f"({c} ? {x} : {y})", _join(tx, ty)) for (x, tx), (y, ty) in zip(a, b)]
        if isinstance(node, ast.Call):
            code, t = self.call(node)
            if not (isinstance(t, tuple) and t[1] == n):
                self.fail(node, f"a call that does not return {n} values")
            return code, n
        self.fail(node, "a tuple value of this form")

    # ------------------------------------------------------------------ statements
    def block(self, stmts, emit: bool, depth: int = 1) -> list[str]:
        out = []
        for s in stmts:
            try:
                out += self.stmt(s, emit, depth)
            except _NotYet:
                if emit:
                    self.fail(s, "a name used before it has a value")
        return out

    def settype(self, node, name: str, t: str):
        if name in self.arrays:
            self.fail(node, f"{name} is an array; it cannot be given a number")
        old = self.types.get(name)
        if old is None:
            self.types[name] = t
        elif old != t:
            if old in (A1, A2) or t in (A1, A2):
                self.fail(node, f"{name} holds both an array and a number")
            if name in self.params and _join(old, t) != old:
                self.fail(node, f"argument {name} ({old}) is given a {t}")
            self.types[name] = _join(old, t)

    def stmt(self, s, emit: bool, depth: int) -> list[str]:
        pad = "    " * depth
        if isinstance(s, ast.Expr):
            if isinstance(s.value, ast.Constant) and isinstance(s.value.value, str):
                return []           # docstring
            if not isinstance(s.value, ast.Call):
                self.fail(s, "an expression statement that is not a call")
            code, t = self.expr(s.value)
            return [f"{pad}{'(void)' if t is not None else ''}{code};"]
        if isinstance(s, ast.Assign):
            if len(s.targets) != 1:
                self.fail(s, "a chained assignment")
            return self.assign(s, s.targets[0], s.value, emit, pad)
        if isinstance(s, ast.AugAssign):
            op = type(s.op)
            if op not in _BINOP and op is not ast.Div:
                self.fail(s, f"the augmented operator {op.__name__}")
            sym = _BINOP.get(op, "/")
            v, tv = self.scalar(s.value)
            if isinstance(s.target, ast.Name):
                tname = s.target.id
                if tname not in self.types:
                    self.fail(s, f"{tname} is updated before it has a value")
                t_old = self.types[tname]
                if op is ast.Div and t_old != D:
                    self.fail(s, f"/= on the integer {tname}")
                self.settype(s, tname, _join(t_old, tv) if t_old != B else I)
                tgt = self.name(tname)
            elif isinstance(s.target, ast.Subscript):
                tgt, _ = self.subscript(s.target)
            else:
                self.fail(s, "an augmented assignment to this target")
            return [f"{pad}{tgt} {sym}= {v};"]
        if isinstance(s, ast.If):
            c, _ = self.scalar(s.test)
            out = [f"{pad}if ({c}) {{"] + self.block(s.body, emit, depth + 1)
            if s.orelse:
                out += [f"{pad}}} else {{"] + self.block(s.orelse, emit, depth + 1)
            return out + [f"{pad}}}"]
        if isinstance(s, ast.While):
            if s.orelse:
                self.fail(s, "while ... else")
            c, _ = self.scalar(s.test)
            return [f"{pad}while ({c}) {{"] + self.block(s.body, emit, depth + 1) + [f"{pad}}}"]
        if isinstance(s, ast.For):
            return self.for_(s, emit, depth)
        if isinstance(s, ast.Return):
            return self.return_(s, pad)
        if isinstance(s, ast.Pass):
            return [f"{pad};"]
        if isinstance(s, ast.Break):
            return [f"{pad}break;"]
        if isinstance(s, ast.Continue):
            return [f"{pad}continue;"]
        self.fail(s, f"the statement {type(s).__name__}")

    def for_(self, s, emit, depth):
        pad = "    " * depth
        it = s.iter
        if s.orelse:
            self.fail(s, "for ... else")
        if not (isinstance(s.target, ast.Name) and isinstance(it, ast.Call)
                and isinstance(it.func, ast.Name) and it.func.id == "range"
                and 1 <= len(it.args) <= 3 and not it.keywords):
            self.fail(s, "a for loop other than over range(...)")
        args = [self.index(a) for a in it.args]
        start, stop, step = ("0", args[0], "1") if len(args) == 1 else (
            args[0], args[1], args[2] if len(args) == 3 else "1")
        if len(it.args) == 3:
            st = it.args[2]
            neg = isinstance(st, ast.UnaryOp) and isinstance(st.op, ast.USub)
            lit = st.operand if neg else st
            if not (isinstance(lit, ast.Constant) and isinstance(lit.value, int)) \
                    or lit.value == 0:
                self.fail(s, "a range step that is not a non-zero integer constant")
            cmp = ">" if neg else "<"
        else:
            cmp = "<"
        v = s.target.id
        self.settype(s, v, I)
        if self.types[v] != I:
            self.fail(s, f"loop variable {v} is also given a non-integer value")
        self.tmp += 1
        end = f"_end{self.tmp}"
        cv = self.name(v)
        # the bound is evaluated once, as Python's range does
        return ([f"{pad}{{ int {end} = {stop};",
                 f"{pad}for ({cv} = {start}; {cv} {cmp} {end}; {cv} += {step}) {{"]
                + self.block(s.body, emit, depth + 1) + [f"{pad}}} }}"])

    def return_(self, s, pad):
        if s.value is None:
            self.setret(s, None)
            return [f"{pad}return;"]
        if isinstance(s.value, ast.Tuple):
            vals = [self.scalar(e)[0] for e in s.value.elts]
            n = len(vals)
            self.setret(s, ("tuple", n))
            self.pr.tuples.add(n)
            return [f"{pad}{{ cs_tup{n} _r = {{{{{', '.join(vals)}}}}}; return _r; }}"]
        code, t = self.expr(s.value)
        if t in (A1, A2):
            self.fail(s, "returning an array")
        self.setret(s, I if t == B else t)
        return [f"{pad}return {code};"]

    def setret(self, s, t):
        if self.ret == "unset":
            self.ret = t
            return
        if self.ret == t:
            return
        if self.ret is None or t is None or isinstance(self.ret, tuple) or isinstance(t, tuple):
            self.fail(s, "returns of different kinds (a value, none, a tuple)")
        self.ret = _join(self.ret, t)

    def assign(self, s, tgt, value, emit, pad):
        # array creation
        if isinstance(value, ast.Call) and _array_maker(value.func):
            return self.new_array(s, tgt, value, pad)
        if isinstance(tgt, ast.Name):
            code, t = self.expr(value)
            if t is None:
                self.fail(s, "the value of a call that returns nothing")
            if isinstance(t, tuple):
                self.fail(s, "a tuple assigned to one name")
            if t in (A1, A2):
                self.fail(s, "an array assigned to a name (aliasing)")
            self.settype(s, tgt.id, t)
            return [f"{pad}{self.name(tgt.id)} = {code};"]
        if isinstance(tgt, ast.Subscript):
            lhs, _ = self.subscript(tgt)
            code, _ = self.scalar(value)
            return [f"{pad}{lhs} = {code};"]
        if isinstance(tgt, ast.Tuple):
            n = len(tgt.elts)
            comps = self.tuple_value(value, n)
            out = [f"{pad}{{"]
            if isinstance(comps, tuple):
                out.append(f"{pad}    cs_tup{n} _r = {comps[0]};")
                vals = [(f"_r.v[{i}]", D) for i in range(n)]
            else:
                vals = []
                for i, (c, t) in enumerate(comps):
                    out.append(f"{pad}    {_ctype(t)} _v{i} = {c};")
                    vals.append((f"_v{i}", t))
            for e, (v, t) in zip(tgt.elts, vals):
                if isinstance(e, ast.Name):
                    if e.id == "_":
                        continue
                    self.settype(s, e.id, t)
                    out.append(f"{pad}    {self.name(e.id)} = {v};")
                elif isinstance(e, ast.Subscript):
                    out.append(f"{pad}    {self.subscript(e)[0]} = {v};")
                else:
                    self.fail(s, "a nested tuple target")
            return [*out, f"{pad}}}"]
        self.fail(s, "an assignment to this target")

    def new_array(self, s, tgt, value, pad):
        kind = _array_maker(value.func)
        if kind is None or len(value.args) != 1 or value.keywords:
            self.fail(s, f"{ast.unparse(value.func)}(...) (only np.zeros(shape), np.empty(shape) "
                      "and their stack forms local_zeros(shape), local_empty(shape))")
        if not isinstance(tgt, ast.Name):
            self.fail(s, "an array created into something other than a name")
        shape = value.args[0]
        dims = shape.elts if isinstance(shape, ast.Tuple) else [shape]
        if len(dims) not in (1, 2):
            self.fail(s, "an array of more than two dimensions")
        codes = [self.index(d) for d in dims]
        name = tgt.id
        if name in self.params:
            self.fail(s, f"the argument {name} re-created as an array")
        size = " * ".join(f"({c})" for c in codes)
        consts = [_int_value(d, self.fn.globals) for d in dims]
        if None not in consts:
            size = str(max(math.prod(consts), 1))
        entry = (size, codes[1] if len(codes) == 2 else None)
        old = self.arrays.get(name)
        if old is not None and old != entry:
            self.fail(s, f"the array {name} created twice with different shapes")
        self.arrays[name] = entry
        self.types[name] = A2 if len(codes) == 2 else A1
        cn = self.name(name)
        if None in consts:
            if pad != "    ":
                self.fail(s, "an array whose size is not a constant, created inside a block")
            decl = f"{pad}double {cn}[({size}) > 0 ? ({size}) : 1];"
            self.vla.add(name)
            return [decl] + ([f"{pad}memset({cn}, 0, sizeof({cn}));"] if kind == "zeros"
                             else [])
        return [f"{pad}memset({cn}, 0, sizeof({cn}));"] if kind == "zeros" else []

    # ------------------------------------------------------------------ rendering
    def render(self, cname: str, ret) -> str:
        self.vla: set[str] = set()
        self.tmp = 0
        body = self.block(self.fn.tree.body, emit=True)
        params = []
        for p in self.params:
            t = self.types[p]
            cn = self.name(p)
            if t == A1:
                params.append(f"double *{cn}")
            elif t == A2:
                params += [f"double *{cn}", f"int {cn}_nc"]
            else:
                params.append(f"{_ctype(t)} {cn}")
        decls = []
        for n, t in self.types.items():
            if n in self.params:
                continue
            if t in (A1, A2):
                if n not in self.vla:
                    size = self.arrays[n][0]
                    decls.append(f"    double {self.name(n)}[{size}];")
            else:
                decls.append(f"    {_ctype(t)} {self.name(n)} = 0;")
        rtype = _ctype(None if ret is None else ret)
        head = f"{rtype} {cname}({', '.join(params) or 'void'}) {{"
        return "\n".join([head, f"    /* {self.fn.where} */", *decls, *body, "}", ""])


class _NotYet(Exception):
    """A local used before inference has typed it (the inference loop retries)."""


def _assigned_names(tree) -> set[str]:
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            out.add(node.id)
    return out


def _int_value(node, globs):
    """The value of a constant integer expression (literals, integer globals, + - *), or
    None."""
    if isinstance(node, ast.Constant):
        ok = isinstance(node.value, int) and not isinstance(node.value, bool)
        return node.value if ok else None
    if isinstance(node, ast.Name):
        v = globs.get(node.id)
        return v if isinstance(v, int) and not isinstance(v, bool) else None
    if isinstance(node, ast.BinOp) and type(node.op) in _BINOP:
        a, b = _int_value(node.left, globs), _int_value(node.right, globs)
        if a is None or b is None:
            return None
        return {ast.Add: a + b, ast.Sub: a - b, ast.Mult: a * b}[type(node.op)]
    return None


def print_c(module, entries: dict[str, tuple]) -> CProgram:
    """The C program of the generated plant ``module`` for ``entries`` (its function name
    -> the types of its arguments: ``"double"``, ``"int"``, ``"a1"``, ``"a2"``).  Every
    entry ``f`` becomes the C function ``cs_<f>`` (a 2-D array argument ``X`` is followed by
    ``int X_nc``, its number of columns); the functions it calls are printed with it.
    Raises :class:`CPrintError` for a construct outside the subset."""
    src = inspect.getsource(module)
    tree = ast.parse(src)
    defs = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
    pr = _Printer()
    for name in entries:
        pr.names.add("cs_" + name)
    out = {}
    for name, sig in entries.items():
        if name not in defs:
            raise CPrintError(f"the generated plant has no function {name}")
        fn = _Func(name, defs[name], vars(module), f"{module.__name__}.{name}")
        pr.function(fn, tuple(sig), "cs_" + name, entry=True)
    protos, bodies = [], []
    for name, head, text, entry in pr.funcs:
        if entry:
            out[name[3:]] = head + ";"
        protos.append(("" if entry else "static ") + head + ";")
        bodies.append(("" if entry else "static ") + text)
    tup = [f"typedef struct {{ double v[{n}]; }} cs_tup{n};" for n in sorted(pr.tuples)]
    head = f"/* Printed by clutchsim.cgen.cprint from {module.__name__}. Do not edit. */"
    source = "\n".join([head, PRELUDE, *tup, "", *protos, "", *bodies])
    return CProgram(source, out)
