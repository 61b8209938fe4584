"""What every LaTeX table shares: escaping, cell text (bold best, partial marks, executed
counts) and an estimate of a tabular's natural width."""

from __future__ import annotations

import math
import re
from collections.abc import Sequence

_SPECIAL = re.compile(r"([\\&%$#_{}~^])")
_REPLACE = {"\\": r"\textbackslash{}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}
PARTIAL_MARK = r"\textsuperscript{\dag}"
"""The LaTeX form of the partial-Overall mark (†)."""


def escape(text: str) -> str:
    """``text`` with LaTeX's special characters escaped (``†`` as a superscript dagger)."""
    out = _SPECIAL.sub(lambda m: _REPLACE.get(m.group(1), "\\" + m.group(1)), text)
    return out.replace("†", PARTIAL_MARK)


def best_value(values: Sequence[float]) -> float:
    """The column's best (largest) value; NaN when there is no best (all equal, or one row)."""
    finite = [round(v, 1) for v in values if not math.isnan(v)]
    return max(finite) if len(set(finite)) > 1 else math.nan


def cell(value: float, best: float, partial: bool = False, count: str = "") -> str:
    """A number with one decimal: bold where it is the column's best, † on a partial Overall,
    the executed count beside an execution value over only some episodes (never bold)."""
    if math.isnan(value):
        return "--"
    text = f"{value:.1f}"
    if count:  # execution over only some of the cell's episodes: never the best either
        return rf"{text}\,{{\scriptsize({count})}}" + (PARTIAL_MARK if partial else "")
    if partial:  # a partial Overall is never the best
        return text + PARTIAL_MARK
    return (
        rf"\textbf{{{text}}}"
        if not math.isnan(best) and round(value, 1) == round(best, 1)
        else text
    )


_CHAR_PT = 4.2
"""Mean width of a character of the table's type (footnotesize digits 4.25 pt, period 2.4 pt)."""


def _plain(text: str) -> str:
    """The visible text of a cell, roughly: commands and braces dropped."""
    text = re.sub(r"\\raisebox\{[^}]*\}\[0pt\]\[0pt\]", "", text)
    text = re.sub(r"\\(textbf|textsuperscript|scriptsize|dag|,)", "", text)
    return text.replace("{", "").replace("}", "").replace("\\", "")


def natural_width(rows: Sequence[Sequence[str]], tabcolsep: str = "6pt") -> float:
    """An upper estimate of a tabular's natural width in points from its body cells, at
    ``\\footnotesize`` with column padding ``tabcolsep`` on each side."""
    sep = 2 * float(tabcolsep.removesuffix("pt"))
    columns = zip(*rows, strict=True)
    return sum(sep + _CHAR_PT * max(len(_plain(c)) for c in col) for col in columns)
