"""Input signals from text: a CSV table path or a small, safe formula language.

Used by the command line (``clutchsim rig --force "0.5 + sine(0.4, 1)"``) and by
scenario files.  A text is either

* a path to a CSV file (a header row, then two columns ``time [s], value``; read with
  :meth:`clutchsim.core.Table.from_csv`: linear interpolation, held after the last row), or
* a formula::

      expr  := term (("+" | "-") term)*
      term  := number | call | number "*" term | term "*" number | "-" term | "(" expr ")"
      call  := const(v) | step(t, height[, offset]) | ramp(start, duration, height[, offset])
             | sine(amplitude, freq[, phase, offset, start])
             | pulse(amplitude, width_percent, period[, offset, start])

  Arguments are numbers (``pi`` and ``+ - * /`` between numbers are allowed), given by
  position or by keyword.  Times in s, frequencies in Hz, phases in rad; values in the
  unit of the input they drive.

The formula is parsed with :func:`ast.parse` in ``"eval"`` mode and only whitelisted
node types are walked; nothing is ever evaluated by Python.  A formula is at most
:data:`MAX_FORMULA` characters with at most :data:`MAX_OPERATORS` operators and
:data:`MAX_DEPTH` levels of parentheses (checked on the text before parsing, so a huge or
deep input is refused with a ValueError, never a RecursionError); error messages quote at
most 60 characters of it.

Examples
--------
>>> sig = parse_signal("0.5 + sine(0.4, 1)")
>>> float(sig(0.25)[0])
0.9
>>> format_signal(parse_signal("2*step(1, 3)"))
'step(t=1.0, height=6.0, offset=0.0)'
"""

from __future__ import annotations

import ast
import math
from pathlib import Path

from ._util import quote
from .core.signals import Constant, Pulse, Ramp, Signal, Sine, Step, Sum, Table

__all__ = ["FUNCTIONS", "MAX_DEPTH", "MAX_FORMULA", "MAX_OPERATORS", "format_signal",
           "parse_signal", "scale_signal"]

#: longest formula [characters]; a longer input signal belongs in a CSV table
MAX_FORMULA = 10_000
#: most operators (+ - * /) in a formula: each is one level of Python's parser
MAX_OPERATORS = 500
#: deepest nesting of parentheses in a formula
MAX_DEPTH = 50

#: formula functions: name -> (signal class, argument names, number of required arguments,
#: argument name -> field name of the class)
FUNCTIONS: dict[str, tuple[type, tuple[str, ...], int, dict[str, str]]] = {
    "const": (Constant, ("v",), 1, {"v": "value"}),
    "step": (Step, ("t", "height", "offset"), 2, {"t": "time"}),
    "ramp": (Ramp, ("start", "duration", "height", "offset"), 3, {}),
    "sine": (Sine, ("amplitude", "freq", "phase", "offset", "start"), 2, {}),
    "pulse": (Pulse, ("amplitude", "width_percent", "period", "offset", "start"), 3,
              {"width_percent": "width"}),
}

_ALLOWED = ("numbers, pi, + and -, * by a number, / between numbers, parentheses and the "
            "calls " + ", ".join(f"{n}({', '.join(a[1])})" for n, a in FUNCTIONS.items()))


class _FormulaError(ValueError):
    pass


def parse_signal(text: str, *, base_dir: str | Path | None = None) -> Signal:
    """Build a :class:`~clutchsim.core.Signal` from a CSV path or a formula.

    Parameters
    ----------
    text : str
        A path to a two-column CSV file (``time [s], value``; relative paths are resolved
        against ``base_dir``) or a formula such as ``"0.5 + 0.4*sine(1, 1)"`` or
        ``"ramp(0, 10, 1.425) - ramp(15, 20, 2.85)"``.
    base_dir : str or Path, optional
        Directory for relative CSV paths (default: the current directory).

    Returns
    -------
    Signal

    Raises
    ------
    ValueError
        A missing or malformed CSV file (the message names the file and the row) or a
        formula with a token outside the grammar (the message names it and lists what is
        allowed).
    """
    if not isinstance(text, str):
        raise TypeError(f"signal must be a string (CSV path or formula), got "
                        f"{type(text).__name__}")
    stripped = text.strip()
    if not stripped:
        raise ValueError("empty signal: give a CSV path or a formula such as 'const(1)'")
    path = Path(stripped)
    if base_dir is not None and not path.is_absolute():
        path = Path(base_dir) / path
    if path.suffix.lower() == ".csv" or _is_file(path):
        if not _is_file(path):
            raise ValueError(f"{path}: input table not found")
        return Table.from_csv(path)
    shown = quote(stripped)
    if len(stripped) > MAX_FORMULA:
        raise ValueError(f"signal {shown}: a formula of {len(stripped):,} characters is "
                         f"longer than the {MAX_FORMULA:,} allowed; give a long signal as a "
                         "CSV table (time [s], value)")
    if "\x00" in stripped:
        raise ValueError(f"signal {shown}: holds a NUL character (binary data?); give a "
                         "formula or a CSV path")
    _check_size(stripped, shown)
    try:
        tree = ast.parse(stripped, mode="eval")
    except SyntaxError as exc:
        raise ValueError(f"signal {shown}: not a valid formula ({exc.msg} at column "
                         f"{exc.offset}); allowed: {_ALLOWED}") from None
    except (RecursionError, MemoryError):   # a backstop: _check_size bounds the nesting
        raise ValueError(f"signal {shown}: nested too deeply to read") from None
    try:
        value = _walk(tree.body, 0)
    except _FormulaError as exc:
        raise ValueError(f"signal {shown}: {exc}; allowed: {_ALLOWED}") from None
    except ValueError as exc:   # a signal class refusing its arguments (e.g. not finite)
        raise ValueError(f"signal {shown}: {exc}") from None
    except RecursionError:   # pragma: no cover - _check_size bounds the depth
        raise ValueError(f"signal {shown}: nested too deeply to read") from None
    return Constant(float(value)) if not isinstance(value, Signal) else value


def _check_size(text: str, shown: str) -> None:
    """Refuse a formula with too many operators or too deep parentheses (on the text)."""
    ops = sum(text.count(c) for c in "+-*/")
    if ops > MAX_OPERATORS:
        raise ValueError(f"signal {shown}: {ops:,} operators, more than the "
                         f"{MAX_OPERATORS} a formula may have; give a long signal as a CSV "
                         "table (time [s], value)")
    depth = deepest = 0
    for c in text:
        if c in "([{":
            depth += 1
            deepest = max(deepest, depth)
        elif c in ")]}":
            depth -= 1
    if deepest > MAX_DEPTH:
        raise ValueError(f"signal {shown}: parentheses nested {deepest} deep, more than the "
                         f"{MAX_DEPTH} allowed")


def _is_file(path: Path) -> bool:
    try:
        return path.is_file()
    except OSError:   # e.g. a formula longer than the longest file name
        return False


def _token(node: ast.AST) -> str:
    try:
        return quote(ast.unparse(node))
    # only names the offending token in an error message: whatever unparse raises (e.g.
    # RecursionError on a deeply nested node) must not replace the formula error
    except Exception:  # noqa: BLE001  # pragma: no cover - unparse handles every parsed node
        return type(node).__name__


def _walk(node: ast.AST, depth: int) -> float | Signal:
    # _check_size bounds the depth on the text; this bounds it on the tree
    if depth > MAX_OPERATORS + MAX_DEPTH:   # pragma: no cover - _check_size refuses first
        raise _FormulaError("nested too deeply")
    depth += 1
    if isinstance(node, ast.Constant):
        if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
            raise _FormulaError(f"{_token(node)} is not a number")
        return float(node.value)
    if isinstance(node, ast.Name):
        if node.id == "pi":
            return math.pi
        raise _FormulaError(f"unknown name {node.id!r}")
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
        value = _walk(node.operand, depth)
        return value if isinstance(node.op, ast.UAdd) else _times(value, -1.0)
    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub)):
        # a + b - c + ...: walk the left spine of the sum in a loop, not by recursion
        terms = []
        while isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub)):
            terms.append((node.op, node.right))
            node = node.left
        total = _walk(node, depth)
        for op, right in reversed(terms):
            value = _walk(right, depth)
            total = _plus(total, value if isinstance(op, ast.Add) else _times(value, -1.0))
        return total
    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Mult, ast.Div)):
        left, right = _walk(node.left, depth), _walk(node.right, depth)
        if isinstance(node.op, ast.Mult):
            if isinstance(left, Signal) and isinstance(right, Signal):
                raise _FormulaError(f"{_token(node)}: a signal can only be multiplied by a "
                                    "number")
            return _times(right, left) if isinstance(right, Signal) else _times(left, right)
        if isinstance(left, Signal) or isinstance(right, Signal):
            raise _FormulaError(f"{_token(node)}: '/' is only allowed between numbers")
        if right == 0.0:
            raise _FormulaError(f"{_token(node)}: division by zero")
        return left / right
    if isinstance(node, ast.Call):
        return _call(node, depth)
    raise _FormulaError(f"{_token(node)} is not allowed")


def _number(node: ast.AST, what: str, depth: int) -> float:
    value = _walk(node, depth)
    if isinstance(value, Signal):
        raise _FormulaError(f"{what} = {_token(node)} must be a number, not a signal")
    if not math.isfinite(value):
        raise _FormulaError(f"{what} = {_token(node)} must be finite")
    return value


def _call(node: ast.Call, depth: int) -> Signal:
    if not isinstance(node.func, ast.Name) or node.func.id not in FUNCTIONS:
        raise _FormulaError(f"{_token(node.func)} is not a known function")
    name = node.func.id
    cls, argnames, n_required, rename = FUNCTIONS[name]
    if len(node.args) > len(argnames):
        raise _FormulaError(f"{name}() takes at most {len(argnames)} arguments "
                            f"({', '.join(argnames)}), got {len(node.args)}")
    values: dict[str, float] = {}
    for arg_name, arg in zip(argnames, node.args):
        if isinstance(arg, ast.Starred):
            raise _FormulaError(f"{_token(arg)} is not allowed")
        values[arg_name] = _number(arg, f"{name}() argument {arg_name}", depth)
    for kw in node.keywords:
        if kw.arg is None:
            raise _FormulaError(f"'**' in {name}() is not allowed")
        if kw.arg not in argnames:
            raise _FormulaError(f"{name}() has no argument {kw.arg!r} (arguments: "
                                f"{', '.join(argnames)})")
        if kw.arg in values:
            raise _FormulaError(f"{name}() got argument {kw.arg!r} twice")
        values[kw.arg] = _number(kw.value, f"{name}() argument {kw.arg}", depth)
    missing = [a for a in argnames[:n_required] if a not in values]
    if missing:
        raise _FormulaError(f"{name}() is missing argument(s) {', '.join(missing)}")
    try:
        return cls(**{rename.get(k, k): v for k, v in values.items()})
    except ValueError as exc:
        raise _FormulaError(f"{name}(): {exc}") from None


def _plus(a: float | Signal, b: float | Signal) -> float | Signal:
    if not isinstance(a, Signal) and not isinstance(b, Signal):
        return a + b
    return _as(a) + _as(b)


def _as(x: float | Signal) -> Signal:
    return x if isinstance(x, Signal) else Constant(float(x))


def _times(x: float | Signal, k: float) -> float | Signal:
    return scale_signal(x, k) if isinstance(x, Signal) else x * k


def scale_signal(signal: Signal, k: float) -> Signal:
    """The signal multiplied by the number ``k`` (a new immutable signal)."""
    k = float(k)
    if isinstance(signal, Constant):
        return Constant(signal.value * k)
    if isinstance(signal, Step):
        return Step(signal.time, signal.height * k, signal.offset * k)
    if isinstance(signal, Ramp):
        return Ramp(signal.start, signal.duration, signal.height * k, signal.offset * k)
    if isinstance(signal, Sine):
        return Sine(signal.amplitude * k, signal.freq, signal.phase, signal.offset * k,
                    signal.start)
    if isinstance(signal, Pulse):
        return Pulse(signal.amplitude * k, signal.width, signal.period, signal.offset * k,
                     signal.start, signal.horizon)
    if isinstance(signal, Table):
        return Table(signal.times, signal.values * k, signal.hit_knots, signal.source)
    if isinstance(signal, Sum):
        return Sum(tuple(scale_signal(s, k) for s in signal.parts))
    raise TypeError(f"cannot scale a {type(signal).__name__}")


def format_signal(signal: Signal) -> str:
    """A formula that :func:`parse_signal` turns back into an equal signal.

    Tables have no formula and raise ``TypeError``.
    """
    if isinstance(signal, Sum):
        if not signal.parts:
            return "const(v=0.0)"
        return " + ".join(format_signal(s) for s in signal.parts)
    for name, (cls, argnames, _, rename) in FUNCTIONS.items():
        if type(signal) is cls:
            args = ", ".join(f"{a}={float(getattr(signal, rename.get(a, a)))!r}"
                             for a in argnames)
            return f"{name}({args})"
    raise TypeError(f"{type(signal).__name__} has no formula (only "
                    f"{', '.join(FUNCTIONS)} and their sums)")

