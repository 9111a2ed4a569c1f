"""Derived columns: a small, safe expression language over the columns of a record.

Used by fit specifications (``[data] derived``) to compute, e.g., a normal-load ratio from
two actuator forces::

    s = "(F_act1 + F_act2) / mean(F_act1 + F_act2)"

The text is parsed with :mod:`ast` and only these nodes are evaluated (never ``eval``):

* numbers, and names of columns of the record (``t`` is the time);
* ``+ - * /`` and ``**`` (a number as exponent), unary ``-`` and ``+``, parentheses;
* element-wise functions ``abs(x)``, ``sqrt(x)``, ``sign(x)``;
* reductions over the whole column, giving one number: ``mean(x)``, ``rms(x)``,
  ``min(x)``, ``max(x)``, ``first(x)``, ``last(x)``.

This grammar is separate from the time-signal grammar of :mod:`clutchsim.signal_expr`
(signals of time for the simulators); here every name is a measured column (numpy arrays).
"""

from __future__ import annotations

import ast
from collections.abc import Mapping

import numpy as np

from ..core.system import closest

__all__ = ["COLUMN_FUNCTIONS", "evaluate_column"]

_ELEMENTWISE = {"abs": np.abs, "sqrt": np.sqrt, "sign": np.sign}
_REDUCE = {"mean": np.mean, "rms": lambda x: np.sqrt(np.mean(np.square(x))), "min": np.min,
           "max": np.max, "first": lambda x: x[0], "last": lambda x: x[-1]}
#: functions a derived-column expression may call
COLUMN_FUNCTIONS = tuple(_ELEMENTWISE) + tuple(_REDUCE)
_MAX_LENGTH = 500
_MAX_DEPTH = 30


def evaluate_column(text: str, columns: Mapping[str, np.ndarray]) -> np.ndarray:
    """Value of the expression ``text`` over ``columns`` (arrays of one length).

    Returns a float array of that length (a constant expression is broadcast).  Raises
    ValueError naming the unknown column or the token outside the grammar.
    """
    if not isinstance(text, str) or not text.strip():
        raise ValueError(f"derived column: expression {text!r} must be a non-empty string")
    if len(text) > _MAX_LENGTH:
        raise ValueError(f"derived column: expression is {len(text)} characters long; at most "
                         f"{_MAX_LENGTH}")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise ValueError(f"derived column {text!r}: not a valid expression ({exc.msg})") from None
    n = len(next(iter(columns.values()))) if columns else 0
    with np.errstate(all="ignore"):
        value = _walk(tree.body, columns, text, 0)
    out = np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy()
    bad = np.flatnonzero(~np.isfinite(out))
    if bad.size:
        raise ValueError(f"derived column {text!r} is not finite at row {bad[0]} "
                         f"({np.count_nonzero(~np.isfinite(out))} row(s); a division by zero "
                         "or the square root of a negative value?)")
    return out


def _walk(node, cols, text, depth):
    if depth > _MAX_DEPTH:
        raise ValueError(f"derived column {text!r}: nested too deeply")
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
            and not isinstance(node.value, bool):
        return float(node.value)
    if isinstance(node, ast.Name):
        if node.id not in cols:
            raise ValueError(f"derived column {text!r}: unknown column {node.id!r}"
                             f"{closest(node.id, cols)}; columns: {', '.join(cols)}")
        return np.asarray(cols[node.id], dtype=float)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        v = _walk(node.operand, cols, text, depth + 1)
        return -v if isinstance(node.op, ast.USub) else v
    if isinstance(node, ast.BinOp):
        a = _walk(node.left, cols, text, depth + 1)
        b = _walk(node.right, cols, text, depth + 1)
        if isinstance(node.op, ast.Add):
            return a + b
        if isinstance(node.op, ast.Sub):
            return a - b
        if isinstance(node.op, ast.Mult):
            return a * b
        if isinstance(node.op, ast.Div):
            return a / b
        if isinstance(node.op, ast.Pow):
            if not isinstance(b, float) or abs(b) > 16:
                raise ValueError(f"derived column {text!r}: the exponent of ** must be a "
                                 "number between -16 and 16")
            return a ** b
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and not node.keywords:
        name = node.func.id
        if name in COLUMN_FUNCTIONS:
            if len(node.args) != 1:
                raise ValueError(f"derived column {text!r}: {name}() takes one argument")
            arg = _walk(node.args[0], cols, text, depth + 1)
            if name in _ELEMENTWISE:
                return _ELEMENTWISE[name](arg)
            return float(_REDUCE[name](np.atleast_1d(arg)))
        raise ValueError(f"derived column {text!r}: unknown function {name!r}"
                         f"{closest(name, COLUMN_FUNCTIONS)}; functions: "
                         f"{', '.join(COLUMN_FUNCTIONS)}")
    shown = ast.get_source_segment(text.strip(), node) or type(node).__name__
    raise ValueError(f"derived column {text!r}: {shown!r} is outside the grammar (numbers, "
                     f"column names, + - * / **, and {', '.join(COLUMN_FUNCTIONS)})")
