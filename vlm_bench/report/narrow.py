"""Which episodes a report covers: ``--suite``, ``--task`` and ``--common`` (only the episodes
every run has), applied to the episode frame before any table is computed.

``--common`` makes the rows comparable: a full run beside runs of one suite is cut to that
suite (no partial Overall), and runs with different seeds to their shared seeds. An episode is
(task, seed, instruction); a run "has" it when it holds its record, answered or not (a backend
error stays in the table's ``n_error``).
"""

from __future__ import annotations

from collections.abc import Sequence

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.types.task import Suite

EPISODE = ["task_id", "seed", "instruction"]
"""The columns that name an episode across runs."""


def _suite(text: str) -> str:
    for suite in Suite:
        short = "".join(w[0] for w in suite.value.split("_"))
        if text in (suite.value, short):
            return suite.value
    raise UnknownNameError("suite", text, [s.value for s in Suite])


def narrow(
    frame: pd.DataFrame,
    suites: Sequence[str] = (),
    tasks: Sequence[str] = (),
    common: bool = False,
) -> pd.DataFrame:
    """The episodes of ``frame`` a report covers (see the module docstring).

    Args:
        frame: Episode rows (:func:`vlm_bench.report.load`), with a ``run`` column.
        suites: Keep these suites (values or initials: ``lh``); empty = all.
        tasks: Keep these tasks; empty = all.
        common: Keep only the episodes every run has.

    Raises:
        UnknownNameError: A suite that does not exist, or a task no run has.
        ConfigError: No episode is left.
    """
    out = frame
    if suites:
        wanted = {_suite(s.strip().lower()) for s in suites}
        out = out[out["suite"].isin(wanted)]
    if tasks:
        known = list(dict.fromkeys(frame["task_id"]))
        for task in tasks:
            if task not in known:
                raise UnknownNameError("--task (in these runs)", task, known)
        out = out[out["task_id"].isin(set(tasks))]
    if common and not out.empty:
        runs = out["run"].nunique()
        held = out.drop_duplicates(["run", *EPISODE]).groupby(EPISODE).size()
        shared = held[held == runs].index
        out = out.set_index(EPISODE).loc[lambda f: f.index.isin(shared)].reset_index()
        out = out[frame.columns]
    if out.empty:
        asked = [
            *(f"--suite {s}" for s in suites),
            *(f"--task {t}" for t in tasks),
            *(["--common"] if common else []),
        ]
        raise ConfigError(f"no episode of these runs is left after {' '.join(asked)}")
    return out.reset_index(drop=True)
