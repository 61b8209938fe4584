"""What every report format says about the runs' protocols (docs/protocols.md): which protocol
each run follows and what share of it it ran, and a warning when runs of different protocols
share a report or a table row."""

from __future__ import annotations

from pathlib import Path

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.report.summary import By, by_columns
from vlm_bench.storage import RunPaths, read_manifest
from vlm_bench.types.protocol_match import manifest_protocol


def run_protocols(frame: pd.DataFrame) -> dict[str, str]:
    """Run name → its protocol label (``paper (240 of 1,200 episodes, 20%)``, ``custom``)."""
    if frame.empty or "run_dir" not in frame.columns:
        return {}
    out = {}
    for run, run_dir in frame[["run", "run_dir"]].drop_duplicates().itertuples(index=False):
        out[str(run)] = manifest_protocol(read_manifest(RunPaths(Path(run_dir)))).label()
    return out


def protocol_note(frame: pd.DataFrame) -> str:
    """``Protocol: paper (all runs)`` or one label per run."""
    labels = run_protocols(frame)
    if not labels:
        return ""
    if len(set(labels.values())) == 1:
        return f"Protocol: {next(iter(labels.values()))}."
    return "Protocols: " + "; ".join(f"{run}: {label}" for run, label in labels.items()) + "."


def row_protocols(frame: pd.DataFrame, by: By) -> pd.DataFrame:
    """Per system (the ``by`` values) the protocols of its runs, joined by ``+``."""
    keys = by_columns(by)
    if frame.empty or "protocol" not in frame.columns:
        return pd.DataFrame(columns=[*keys, "protocol"])
    joined = frame.groupby(keys, sort=False, dropna=False)["protocol"].agg(
        lambda s: "+".join(dict.fromkeys(map(str, s)))
    )
    return joined.reset_index()


def protocol_warnings(frame: pd.DataFrame, by: By) -> list[str]:
    """Warnings when the report mixes protocols: across its runs, and within a table row."""
    if frame.empty or "protocol" not in frame.columns:
        return []
    runs = frame[["run", "protocol"]].drop_duplicates()
    if runs["protocol"].nunique() < 2:
        return []
    groups = "; ".join(
        f"{name}: {', '.join(map(str, part['run']))}"
        for name, part in runs.groupby("protocol", sort=False)
    )
    out = [f"Runs of different protocols ({groups}): their numbers are not comparable."]
    rows = row_protocols(frame, by)
    pooled = rows[rows["protocol"].str.contains("+", regex=False)]
    for _, row in pooled.iterrows():
        name = " ".join(str(row[k]) for k in by_columns(by))
        out.append(
            f"Row {name} pools runs of protocols {row['protocol'].replace('+', ' and ')}; "
            "give --by run (or protocol) to keep them apart."
        )
    return out
