"""The self-contained HTML report of an output directory (``clutchsim report DIR``).

>>> from clutchsim.report import build_report
>>> build_report("launch/")                        # doctest: +SKIP
PosixPath('launch/report.html')

Modules: :mod:`.gather` reads a directory into plain data, :mod:`.tables` turns JSON
documents into tables, :mod:`.html` draws the page, :mod:`.build` writes it atomically,
:mod:`.notebook` gives :func:`result_html` for a single result.
"""

from .build import build_report
from .gather import REPORT_NAME, ReportData, gather
from .html import render
from .notebook import result_html

__all__ = ["REPORT_NAME", "ReportData", "build_report", "gather", "render", "result_html"]
