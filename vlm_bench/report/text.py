"""Any small display table (strings) as Markdown or a rich table; numbers with intervals."""

from __future__ import annotations

import math

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs
from rich import box
from rich.table import Table


def with_ci(value: float, lo: float, hi: float) -> str:
    """``76.5 [70.1, 82.3]``; without an interval just the value; – when missing."""
    if math.isnan(value):
        return "–"
    if math.isnan(lo) or math.isnan(hi):
        return f"{value:.1f}"
    return f"{value:.1f} [{lo:.1f}, {hi:.1f}]"


def p_value(p: float) -> str:
    """A p-value with two significant digits (``<0.001`` below that)."""
    return "<0.001" if p < 0.001 else f"{p:.2g}"


def frame_markdown(frame: pd.DataFrame, numeric: tuple[str, ...] = ()) -> str:
    """``frame`` (already formatted) as a GitHub Markdown table; ``numeric`` columns flush right."""
    head = [str(c) for c in frame.columns]
    align = ["--:" if c in numeric else ":--" for c in frame.columns]
    lines = ["| " + " | ".join(head) + " |", "|" + "|".join(align) + "|"]
    for row in frame.itertuples(index=False, name=None):
        lines.append("| " + " | ".join(str(v).replace("|", "\\|") for v in row) + " |")
    return "\n".join(lines) + "\n"


def frame_rich(
    frame: pd.DataFrame,
    title: str | None = None,
    caption: str | None = None,
    numeric: tuple[str, ...] = (),
) -> Table:
    """``frame`` (already formatted) as a rich table."""
    table = Table(
        title=title,
        caption=caption,
        box=box.SIMPLE_HEAD,
        title_justify="left",
        collapse_padding=True,
        pad_edge=False,
    )
    for col in frame.columns:
        table.add_column(str(col), justify="right" if col in numeric else "left")
    for row in frame.itertuples(index=False, name=None):
        table.add_row(*(str(v) for v in row))
    return table
