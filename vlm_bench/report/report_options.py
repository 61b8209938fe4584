"""What a report shows and where it goes: :class:`ReportOptions`, validated in one place."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

from pydantic import Field, ValidationError, model_validator

from vlm_bench.errors import option_error
from vlm_bench.types.base import Frozen

N_BOOT = 2000
"""Bootstrap replicates of every interval a report gives, unless asked otherwise."""
BOOT_SEED = 0
"""The bootstrap's resampling seed: the same runs give the same intervals."""
CI_LEVEL = 0.95
"""Coverage of the intervals."""

ReportFormat = Literal["terminal", "markdown", "csv", "parquet", "latex"]
FORMATS: tuple[ReportFormat, ...] = ("terminal", "markdown", "csv", "parquet", "latex")
GroupingChoice = Literal["suites", "paper", "both"]
GROUPING_CHOICES: tuple[GroupingChoice, ...] = ("suites", "paper", "both")
LayoutChoice = Literal["paper", "column", "wide"]
LAYOUT_CHOICES: tuple[LayoutChoice, ...] = ("paper", "column", "wide")
SortChoice = Literal["given", "total"]
SORT_CHOICES: tuple[SortChoice, ...] = ("given", "total")


class ReportOptions(Frozen):
    """Options of ``vlm-bench report`` (and :func:`vlm_bench.report.make_report`)."""

    runs: tuple[str, ...] = Field(min_length=1, description="Run folders or glob patterns.")
    by: tuple[str, ...] = Field(
        default=("model",), min_length=1, description="Episode column(s) naming a table row."
    )
    grouping: GroupingChoice = Field(
        default="both", description="Column groups: our suites, the paper's columns, or both."
    )
    format: ReportFormat = Field(default="terminal", description="Output format of the tables.")
    out: Path | None = Field(default=None, description="Write the tables here (else stdout).")
    standalone: bool = Field(default=False, description="LaTeX: a whole document, not a float.")
    fit_width: bool = Field(
        default=False, description="LaTeX: scale each table to the text width (\\resizebox)."
    )
    layout: LayoutChoice = Field(
        default="paper",
        description="LaTeX: the paper's full table (table*), a column-wide table (table) or a "
        "page-wide one (table*), the last two at natural size for a two-column paper.",
    )
    columns: tuple[str, ...] = Field(
        default=(), description="LaTeX: the metrics shown (names or headers: S_total, Tot, Succ)."
    )
    labels: dict[str, str] = Field(
        default_factory=dict,
        description="Display name per run (or row value), in every table, plot and gallery.",
    )
    suites: tuple[str, ...] = Field(default=(), description="Only episodes of these suites.")
    tasks: tuple[str, ...] = Field(default=(), description="Only episodes of these tasks.")
    common: bool = Field(
        default=False, description="Only the episodes every run has (the same episodes per row)."
    )
    sort: SortChoice = Field(
        default="given", description="Row order: as given, or by overall Tot (the paper's)."
    )
    stats: bool = Field(
        default=True, description="Intervals, parse tiers, error codes, blind floor."
    )
    paired: str | None = Field(
        default=None, description="Compare every other row system with this one."
    )
    episodes: Path | None = Field(
        default=None, description="Also write the per-episode frame (.csv or .parquet)."
    )
    plots: Path | None = Field(default=None, description="Write PNG plots into this folder.")
    gallery: Path | None = Field(
        default=None, description="Write an HTML gallery per run into this folder."
    )
    inline_images: bool = Field(
        default=False, description="Gallery: images inside the HTML (else files beside it)."
    )
    render_missing: bool = Field(
        default=True,
        description="Gallery: render views missing from the snapshot cache (the CLI's view "
        "source does; the report itself reads run folders only).",
    )
    n_boot: int = Field(default=N_BOOT, ge=100, le=100_000, description="Bootstrap replicates.")
    seed: int = Field(default=BOOT_SEED, ge=0, description="Bootstrap seed.")
    level: float = Field(default=CI_LEVEL, gt=0.5, lt=1.0, description="Interval coverage.")
    mixed_versions: bool = Field(
        default=False, description="Accept runs of different benchmark versions in one table."
    )

    @model_validator(mode="after")
    def _consistent(self) -> ReportOptions:
        if self.format == "parquet" and self.out is None:
            raise ValueError("--format parquet writes a binary file: give --out FILE")
        if self.standalone and self.format != "latex":
            raise ValueError("--standalone applies to --format latex only")
        if self.fit_width and self.format != "latex":
            raise ValueError("--fit-width applies to --format latex only")
        if self.layout != "paper" and self.format != "latex":
            raise ValueError("--layout applies to --format latex only")
        if self.columns and self.format != "latex":
            raise ValueError("--columns applies to --format latex only")
        if self.fit_width and self.layout != "paper":
            raise ValueError(
                "--fit-width scales the paper layout; --layout column/wide fit as they are"
            )
        if self.episodes is not None and self.episodes.suffix not in (".csv", ".parquet"):
            raise ValueError("--episodes must end in .csv or .parquet")
        return self


def report_options(**fields: Any) -> ReportOptions:
    """Build :class:`ReportOptions`, turning validation errors into a one-line ConfigError.

    Raises:
        ConfigError: Names the first invalid option and why (with the valid choices).
    """
    try:
        return ReportOptions(**fields)
    except ValidationError as exc:
        raise option_error(exc, "report option") from None
