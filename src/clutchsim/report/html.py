"""Draw a :class:`~clutchsim.report.gather.ReportData` as one self-contained HTML page.

No JavaScript, no external resources: CSS is inline, figures are ``data:`` URIs, and a
Content-Security-Policy forbids any network access from the page.  Every string that
comes from the directory (file names, JSON values, TOML text) is HTML-escaped.
"""

from __future__ import annotations

import base64
import math
from html import escape

from .gather import Figure, ReportData
from .tables import MISSING, Table
from .units import label

__all__ = ["CSP", "CSP_SCRIPTS", "CSS", "format_value", "render", "render_table"]

CSP = ("default-src 'none'; img-src data:; style-src 'unsafe-inline'; "
       "base-uri 'none'; form-action 'none'")
#: the policy of a page with interactive figures: its own inline scripts, nothing fetched
CSP_SCRIPTS = CSP.replace("default-src 'none';",
                          "default-src 'none'; script-src 'unsafe-inline';")

CSS = """
:root{--fg:#1d232b;--mute:#5b6573;--line:#d5dae1;--head:#f2f4f7;--bad:#b3261e;
--badbg:#fdecea;--ok:#1e6b35;--okbg:#e8f5ec;--warnbg:#fff6df;--acc:#2b5d9b}
*{box-sizing:border-box}
body{margin:0;font:15px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,"DejaVu Sans",
sans-serif;color:var(--fg);background:#fff}
main{max-width:1180px;margin:0 auto;padding:20px 28px 48px}
header h1{font-size:1.55rem;margin:0 0 6px}
h2{font-size:1.2rem;margin:34px 0 10px;padding-bottom:4px;border-bottom:2px solid var(--line)}
h3{font-size:.98rem;margin:20px 0 6px;color:var(--mute);font-weight:600;
overflow-wrap:anywhere}
dl.meta{display:grid;grid-template-columns:max-content 1fr;gap:2px 14px;margin:8px 0;
color:var(--mute);font-size:.92rem}
dl.meta dt{font-weight:600}dl.meta dd{margin:0;overflow-wrap:anywhere}
nav{margin:14px 0 0;font-size:.9rem}nav a{margin-right:14px;color:var(--acc)}
code,pre,.num{font-family:ui-monospace,"DejaVu Sans Mono",Menlo,Consolas,monospace}
pre{background:#f7f8fa;border:1px solid var(--line);border-radius:6px;padding:10px 12px;
font-size:.84rem;overflow:auto;max-height:34em;white-space:pre}
.banner{padding:10px 14px;border-radius:6px;margin:10px 0;font-weight:600}
.banner.ok{background:var(--okbg);color:var(--ok)}
.banner.bad{background:var(--badbg);color:var(--bad)}
.banner.info{background:var(--head);color:var(--mute)}
.scroll{overflow-x:auto;max-width:100%;margin:4px 0 10px}
table{border-collapse:collapse;font-size:.86rem}
th,td{border:1px solid var(--line);padding:4px 8px;text-align:left;vertical-align:top}
thead th{background:var(--head);font-weight:600;vertical-align:bottom;min-width:5.5em;
max-width:11em}
tbody th{background:#fafbfc;font-weight:600;white-space:nowrap;position:sticky;left:0}
thead th:first-child{position:sticky;left:0}
td.num{text-align:right;white-space:nowrap;font-variant-numeric:tabular-nums;
font-size:.83rem}
td.txt{max-width:46em;overflow-wrap:anywhere}
.unit{display:block;font-weight:400;color:var(--mute);font-size:.8rem}
.kv td.unitc{color:var(--mute)}
tr.failed td,tr.failed th{background:var(--badbg)}
tr.failed th{color:var(--bad)}
.st-ok{color:var(--ok);font-weight:600}.st-bad{color:var(--bad);font-weight:600}
.st-warn{color:#8a5a00;font-weight:600}.banner.warn{background:var(--warnbg);color:#8a5a00}
ul.warn{background:var(--warnbg);border-radius:6px;padding:8px 12px 8px 30px}
ul.warn li{overflow-wrap:anywhere}
.none{color:var(--mute)}
figure{margin:18px 0 26px;padding:0}
figure img{display:block;max-width:100%;height:auto;border:1px solid var(--line);
border-radius:4px}
figcaption{color:var(--mute);font-size:.9rem;margin-top:6px}
footer{margin-top:40px;color:var(--mute);font-size:.8rem}
@media print{.scroll{overflow:visible}pre{max-height:none;white-space:pre-wrap}
figure{break-inside:avoid}nav{display:none}}
"""


def format_value(v) -> str:
    """A cell's text: 4 significant digits for floats, yes/no for booleans, "—" for None.

    Examples
    --------
    >>> format_value(0.000123456), format_value(12345.678), format_value(True)
    ('0.0001235', '12346', 'yes')
    """
    if v is MISSING:
        return ""
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "NaN"
        if math.isinf(v):
            return "∞" if v > 0 else "−∞"
        if v == 0:
            return "0"
        return f"{v:.0f}" if 1e4 <= abs(v) < 1e6 else f"{v:.4g}"
    if isinstance(v, list):
        return _format_list(v)
    return str(v)


def _format_list(v: list) -> str:
    if len(v) <= 8:
        return "[" + ", ".join(format_value(x) for x in v) + "]"
    head = ", ".join(format_value(x) for x in v[:3])
    return f"[{head}, …, {format_value(v[-1])}] ({len(v)} values)"


def _is_num(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _cell(v) -> str:
    cls = "num" if _is_num(v) or isinstance(v, bool) or v is None else "txt"
    return f'<td class="{cls}">{escape(format_value(v))}</td>'


def _header(name: str, with_unit: bool) -> str:
    if not with_unit:
        return f"<th>{escape(str(name))}</th>"
    text, unit = label(name)
    u = f'<span class="unit">[{escape(unit)}]</span>' if unit else ""
    return f'<th title="{escape(str(name))}">{escape(text)}{u}</th>'


def render_table(t: Table, *, heading: bool = True) -> str:
    """One table (with its title as an ``<h3>``) inside a horizontally scrolling box."""
    parts = [f"<h3>{escape(t.title)}</h3>"] if heading and t.title else []
    if t.units_from == "rows":
        labels = [label(name) for name, _ in t.rows]
        with_units = any(u for _, u in labels)
        body = []
        for (name, v), (text, unit) in zip(t.rows, labels):
            u = f'<td class="unitc">{escape(unit or "")}</td>' if with_units else ""
            body.append(f'<tr><th title="{escape(str(name))}">{escape(text)}</th>{_cell(v)}'
                        f"{u}</tr>")
        parts.append('<div class="scroll"><table class="kv"><tbody>' + "".join(body)
                     + "</tbody></table></div>")
        return "".join(parts)
    units = t.units_from == "columns"
    head = f"<th>{escape(t.row_label)}</th>" + "".join(_header(c, units) for c in t.columns)
    body = []
    for i, row in enumerate(t.rows):
        cls = ' class="failed"' if i in t.failed else ""
        body.append(f"<tr{cls}><th>{escape(str(row[0]))}</th>"
                    + "".join(_cell(v) for v in row[1:]) + "</tr>")
    parts.append(f'<div class="scroll"><table><thead><tr>{head}</tr></thead><tbody>'
                 + "".join(body) + "</tbody></table></div>")
    return "".join(parts)


def render(data: ReportData, *, interactive: tuple[str, str] | None = None) -> str:
    """The whole page as a string.  ``interactive``: ``(head, body)`` of interactive
    figures (:mod:`clutchsim.report.interactive`): ``head`` (the inlined scripts) goes into
    the page's head, ``body`` becomes the section "Interactive figures", and the page's
    policy allows inline scripts (still no network access)."""
    sections = [
        ("status", "Status and warnings", _status(data)),
        ("metrics", "Metrics", "".join(render_table(t) for t in data.tables)),
        ("parameters", "Parameters", "".join(render_table(t) for t in data.parameters)),
        ("scenario", "Scenario", "".join(
            f"<h3>{escape(n)}</h3><pre>{escape(text)}</pre>" for n, text in data.scenarios)),
        ("solver", "Solver statistics",
         render_table(data.solver) if data.solver else ""),
        ("interactive", "Interactive figures", interactive[1] if interactive else ""),
        ("figures", "Figures", "".join(_figure(f) for f in data.figures)),
        ("files", "Files", _files(data)),
    ]
    sections = [s for s in sections if s[2]]
    nav = "".join(f'<a href="#{sid}">{escape(name)}</a>' for sid, name, _ in sections)
    body = "".join(f'<section id="{sid}"><h2>{escape(name)}</h2>{html}</section>'
                   for sid, name, html in sections)
    csp, head = (CSP_SCRIPTS, interactive[0]) if interactive else (CSP, "")
    return (
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        f'<meta http-equiv="Content-Security-Policy" content="{csp}">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        '<meta name="generator" content="clutchsim ' + escape(data.version) + '">'
        '<link rel="icon" href="data:,">'
        f"<title>{escape(data.title)}</title><style>{CSS}</style>{head}</head><body><main>"
        f"<header><h1>{escape(data.title)}</h1>{_meta(data)}<nav>{nav}</nav></header>"
        f"{body}<footer>Written by clutchsim {escape(data.version)}. Rebuild with "
        f"<code>clutchsim report {escape(_shell_dir(data))}</code>.</footer>"
        "</main></body></html>\n")


def _shell_dir(data: ReportData) -> str:
    import shlex
    return shlex.quote(data.directory.name or str(data.directory))


def _meta(data: ReportData) -> str:
    items = [("kind", data.kind), ("clutchsim", data.version), ("created", data.created),
             ("directory", str(data.directory.resolve()))]
    rows = "".join(f"<dt>{escape(k)}</dt><dd>{escape(v)}</dd>" for k, v in items)
    if data.command:
        rows += f"<dt>command</dt><dd><code>{escape(data.command)}</code></dd>"
    return f'<dl class="meta">{rows}</dl>'


def _status(data: ReportData) -> str:
    out = []
    judged = [s for s in data.status if s.ok is not None]
    failed = data.failed
    if failed:
        out.append(f'<div class="banner bad">{len(failed)} of {len(judged)} '
                   f'{"run" if len(judged) == 1 else "runs"} did not complete</div>')
    elif judged:
        n = len(judged)
        warned = [s for s in judged if s.warnings]
        if warned:
            what = "the run completed with warnings" if n == 1 else \
                f"all {n} runs completed, {len(warned)} with warnings"
            out.append(f'<div class="banner warn">{what}: read them (below) before trusting '
                       "a result</div>")
        else:
            out.append(f'<div class="banner ok">{"the run" if n == 1 else f"all {n} runs"} '
                       "completed</div>")
    if data.status:
        rows = []
        for s in data.status:
            cls = "st-bad" if s.ok is False else ("st-warn" if s.warnings else
                                                  ("st-ok" if s.ok else ""))
            tr = ' class="failed"' if s.ok is False else ""
            word = s.status or "—"
            if s.warnings:
                word += f" · {s.warnings} warning{'s' if s.warnings > 1 else ''}"
            rows.append(f"<tr{tr}><th>{escape(s.where)}</th>"
                        f'<td class="{cls}">{escape(word)}</td>'
                        f'<td class="txt">{escape(s.message)}</td></tr>')
        out.append('<div class="scroll"><table><thead><tr><th>where</th><th>status</th>'
                   "<th>message</th></tr></thead><tbody>" + "".join(rows)
                   + "</tbody></table></div>")
    notes = [(w, m) for w, m in data.warnings] + [("report", p) for p in data.problems]
    if notes:
        items = "".join(f"<li><b>{escape(w)}</b>: {escape(m)}</li>" for w, m in notes)
        out.append(f'<h3>warnings</h3><ul class="warn">{items}</ul>')
    elif data.status:
        out.append('<p class="none">No warnings.</p>')
    return "".join(out)


def _figure(f: Figure) -> str:
    uri = "data:image/png;base64," + base64.b64encode(f.data).decode("ascii")
    return (f'<figure id="fig-{escape(f.name)}"><img src="{uri}" width="{f.width}" '
            f'height="{f.height}" alt="{escape(f.caption)}">'
            f"<figcaption>{escape(f.caption)} <code>({escape(f.name)})</code></figcaption>"
            "</figure>")


def _size(n: int | None) -> str:
    if n is None:
        return ""
    for unit in ("B", "kB", "MB", "GB"):
        if n < 1000 or unit == "GB":
            return f"{n} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1000
    return ""  # pragma: no cover


def _files(data: ReportData) -> str:
    if not data.files:
        return ""
    rows = "".join(f'<tr><th><a href="{escape(f.link)}">{escape(f.name)}</a></th>'
                   f"<td>{escape(f.kind)}</td><td class=\"num\">{_size(f.size)}</td></tr>"
                   for f in data.files)
    return ('<div class="scroll"><table><thead><tr><th>file</th><th>kind</th><th>size</th>'
            f"</tr></thead><tbody>{rows}</tbody></table></div>")
