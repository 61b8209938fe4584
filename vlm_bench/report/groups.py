"""Column groupings of the paper table: our four suites, or the paper's own three columns.

The paper's VLM table (AIR-VLA ``tab:vlm_planning_comprehensive``) groups tasks as Base
Manipulation / Distractor Interference / Long-Horizon without listing which task goes where. Our
task-to-column mapping is data, ``vlm_bench/report/paper_columns.json``, validated by
:class:`PaperColumns` against the task catalogue (every task exactly once). It lives beside the
report code, not under ``ground_truth/``, because it changes no episode: a file there would change
the ground-truth digest every run manifest records, and older runs would refuse to resume.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Literal

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs
from pydantic import Field, model_validator

from vlm_bench.catalog.files import load_model
from vlm_bench.errors import ConfigError, DataFileError, UnknownNameError
from vlm_bench.types.base import Frozen
from vlm_bench.types.task import SUITE_TITLES, Suite
from vlm_bench.types.world import SNAKE

PAPER_COLUMNS_FILE = Path(__file__).with_name("paper_columns.json")
"""The paper-column mapping shipped with the package."""

OVERALL = "overall"
"""Group value of overall rows (the unweighted mean of the group cells)."""

GroupingName = Literal["suites", "paper"]
GROUPINGS: tuple[GroupingName, ...] = ("suites", "paper")


class PaperColumn(Frozen):
    """One column group of the paper's VLM table."""

    id: str = Field(pattern=SNAKE, description="Value in the ``paper_column`` frame column.")
    title: str = Field(min_length=1, description="Title as printed in the paper.")
    short: str = Field(min_length=1, max_length=4, description="Header abbreviation.")
    tasks: tuple[str, ...] = Field(min_length=1, description="Task ids in this column.")


class PaperColumns(Frozen):
    """``paper_columns.json``: the paper's columns, in table order."""

    description: str = Field(default="", description="Where the mapping comes from.")
    columns: tuple[PaperColumn, ...] = Field(min_length=1, description="Columns, in order.")

    @model_validator(mode="after")
    def _tasks_once(self) -> PaperColumns:
        ids = [c.id for c in self.columns]
        if len(set(ids)) != len(ids):
            raise ValueError(f"column ids must be unique, got {ids}")
        twice = [t for t, n in Counter(t for c in self.columns for t in c.tasks).items() if n > 1]
        if twice:
            raise ValueError(f"task {twice[0]!r} is in more than one column")
        return self

    def column_of(self) -> dict[str, str]:
        """Task id → column id."""
        return {t: c.id for c in self.columns for t in c.tasks}


@cache
def paper_columns(path: Path = PAPER_COLUMNS_FILE) -> PaperColumns:
    """Load and check the mapping: every catalogue task in exactly one column.

    Raises:
        DataFileError: Invalid file, or a task missing or unknown (names the task).
    """
    from vlm_bench.catalog.tasks import all_tasks

    columns = load_model(path, PaperColumns)
    known = {t.id for t in all_tasks()}
    listed = set(columns.column_of())
    if unknown := sorted(listed - known):
        raise DataFileError(str(path), f"unknown task {unknown[0]!r}")
    if missing := sorted(known - listed):
        raise DataFileError(str(path), f"task {missing[0]!r} is in no column")
    return columns


@dataclass(frozen=True)
class Grouping:
    """How the table's column groups are formed from episode rows."""

    name: str
    """``suites``, ``paper``, or any name of a grouping built for a plot."""
    column: str
    """Frame column holding each episode's group (added by :meth:`assign` when missing)."""
    order: tuple[str, ...]
    """Group values in table order."""
    titles: dict[str, str] = field(default_factory=dict)
    """Group value → title as printed in the paper."""
    short: dict[str, str] = field(default_factory=dict)
    """Group value → header abbreviation (``OVERALL`` → "Overall")."""
    task_map: dict[str, str] | None = None
    """Task id → group value, for groupings not held in the records."""

    def assign(self, frame: pd.DataFrame) -> pd.DataFrame:
        """``frame`` with :attr:`column` filled in (a copy when it had to be added).

        Raises:
            ConfigError: A task without a group (custom tasks are not in the paper mapping).
        """
        if self.column in frame.columns or self.task_map is None:
            return frame
        groups = frame["task_id"].map(self.task_map)
        if groups.isna().any():
            task = frame.loc[groups.isna(), "task_id"].iloc[0]
            raise ConfigError(
                f"task {task!r} has no column in {PAPER_COLUMNS_FILE.name}; "
                "use the suites grouping for custom tasks"
            )
        out = frame.copy()
        out[self.column] = groups
        return out

    def position(self, value: str) -> int:
        """Sort key of a group value (overall last)."""
        return len(self.order) if value == OVERALL else self.order.index(value)


SUITES = Grouping(
    name="suites",
    column="suite",
    order=tuple(s.value for s in Suite),
    titles={s.value: SUITE_TITLES[s] for s in Suite},
    short={
        Suite.BASE.value: "BM",
        Suite.OBJECT_SPATIAL.value: "OS",
        Suite.SEMANTIC.value: "SU",
        Suite.LONG_HORIZON.value: "LH",
        OVERALL: "Overall",
    },
)
"""Our four suites (the default)."""


@cache
def paper_grouping() -> Grouping:
    """The paper's three columns, from :data:`PAPER_COLUMNS_FILE`."""
    columns = paper_columns()
    return Grouping(
        name="paper",
        column="paper_column",
        order=tuple(c.id for c in columns.columns),
        titles={c.id: c.title for c in columns.columns},
        short={**{c.id: c.short for c in columns.columns}, OVERALL: "Overall"},
        task_map=columns.column_of(),
    )


def grouping(name: str) -> Grouping:
    """The grouping called ``name`` (``suites`` or ``paper``).

    Raises:
        UnknownNameError: Another name (lists the valid ones).
    """
    if name == "suites":
        return SUITES
    if name == "paper":
        return paper_grouping()
    raise UnknownNameError("grouping", name, GROUPINGS)
