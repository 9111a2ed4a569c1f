"""``result_html``: a richer notebook view of a :class:`~clutchsim.core.Result`."""

from __future__ import annotations

from html import escape

from .html import CSS, render_table
from .tables import STATS_KEYS, Table

__all__ = ["result_html", "result_tables"]


def result_tables(result) -> list[Table]:
    """Summary, solver statistics and a per-signal overview (unit, min, max, final).

    Parameters
    ----------
    result : clutchsim.core.Result

    Returns
    -------
    list of Table
    """
    import numpy as np
    summary = result.summary()
    info = tuple((k, v) for k, v in summary.items() if k not in STATS_KEYS)
    stats = tuple((k, summary[k]) for k in STATS_KEYS if k in summary)
    rows = []
    for name in result.signals:
        y = np.asarray(result[name], dtype=float)
        ok = y[np.isfinite(y)]
        rows.append((name, result.units.get(name, ""),
                     float(ok.min()) if ok.size else None,
                     float(ok.max()) if ok.size else None,
                     float(y[-1]) if y.size else None))
    return [Table("result", ("value",), info, units_from="rows"),
            Table("solver statistics", ("value",), stats, units_from="rows"),
            Table("signals", ("unit", "min", "max", "final"), tuple(rows),
                  row_label="signal", units_from="none")]


def result_html(result) -> str:
    """An HTML fragment for notebooks: status banner, summary, statistics and signals.

    Examples
    --------
    >>> from IPython.display import HTML            # doctest: +SKIP
    >>> HTML(result_html(res))                      # doctest: +SKIP
    """
    ok = bool(getattr(result, "success", result.status == "completed"))
    cls = "ok" if ok else "bad"
    tables = "".join(render_table(t) for t in result_tables(result))
    return (f'<div class="clutchsim-result"><style>'
            f'{_scoped(CSS)}</style><div class="banner {cls}">{escape(str(result.system))}: '
            f"{escape(str(result.status))} — {escape(str(result.message))}</div>{tables}</div>")


def _scoped(css: str) -> str:
    """Keep the report CSS from restyling the rest of a notebook."""
    import re
    css = re.sub(r"@media[^{]*\{(?:[^{}]*\{[^{}]*\})*[^{}]*\}", "", css.replace("\n", ""))
    out = []
    for rule in css.split("}"):
        if "{" not in rule:
            continue
        sel, body = rule.split("{", 1)
        if sel.strip() == ":root":
            out.append(f".clutchsim-result{{{body};font:14px/1.4 system-ui,sans-serif}}")
            continue
        if sel.startswith(("*", "body", "main", "header", "nav", "footer")):
            continue
        sel = ",".join(f".clutchsim-result {s.strip()}" for s in sel.split(","))
        out.append(f"{sel}{{{body}}}")
    return "".join(out)
