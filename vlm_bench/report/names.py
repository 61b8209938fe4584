"""Display names of table rows: ``--label RUN=NAME``, else the model card's name, else the value.

A system (a table row) is a tuple of ``--by`` values. Its display name is, in order: a label
given for one of its values or for a run it holds (``--label results/qwen-7b-1a2b=Qwen 7B``
takes the run's folder name, as in the ``run`` column); the title of the model card its model
names (``qwen2.5-vl-7b`` → "Qwen2.5-VL-7B-Instruct") when it holds one model; a local model
path by its last component (``openai//models/tiny-llava`` → "tiny-llava"); else its values
joined by '/'.

LaTeX rows use these names. :func:`relabel` puts the labels and the shortened paths (not the
card titles: the other formats print model ids, which name a model exactly) into the episode
frame itself, so that every table, plot and gallery shows them.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import PurePosixPath

import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # no pandas-stubs

from vlm_bench.catalog.model_cards import card_of
from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.report.summary import By, by_columns, system_order, system_rows


def parse_labels(items: tuple[str, ...]) -> dict[str, str]:
    """``RUN=NAME`` items as a mapping.

    Raises:
        ConfigError: An item without '=' or with an empty side.
    """
    out = {}
    for item in items:
        key, sep, name = item.partition("=")
        if not sep or not key.strip() or not name.strip():
            raise ConfigError(f"--label {item!r}: give RUN=NAME (e.g. qwen-7b-1a2b=Qwen 7B)")
        out[key.strip()] = name.strip()
    return out


def display_names(
    frame: pd.DataFrame, by: By, labels: Mapping[str, str] | None = None
) -> dict[tuple[object, ...], str]:
    """The display name of every system of ``frame`` (see the module docstring).

    Raises:
        UnknownNameError: A label for no run or system of the frame (lists them).
    """
    keys, labels = by_columns(by), dict(labels or {})
    out: dict[tuple[object, ...], str] = {}
    known: list[str] = []
    for system in system_order(frame, keys):
        rows = system_rows(frame, keys, system)
        candidates = [*(str(v) for v in system), "/".join(map(str, system))]
        if "run" in rows.columns:
            candidates += [str(r) for r in dict.fromkeys(rows["run"])]
        known += candidates
        given = [labels[c] for c in candidates if c in labels]
        models = list(dict.fromkeys(rows["model"])) if "model" in rows.columns else []
        card = card_of(str(models[0])) if len(models) == 1 else None
        if given:
            out[system] = given[0]
        elif card is not None and keys == ["model"]:
            out[system] = card.title
        else:
            out[system] = "/".join(local_path_name(str(v)) for v in system)
    for key in labels:
        if key not in known:
            raise UnknownNameError("--label run", key, dict.fromkeys(known))
    return out


def local_path_name(value: str) -> str:
    """A model named by a local path (``/m/tiny``, ``./m/tiny``, ``openai//m/tiny``) as its
    last component; any other value (``Qwen/Qwen2.5-VL-7B-Instruct``) as it is."""
    _, sep, rest = value.partition("/")
    path = rest if sep and rest.startswith(("/", "./", "~")) else value
    if not path.startswith(("/", "./", "../", "~")):
        return value
    return PurePosixPath(path.rstrip("/")).name or value


def relabel(frame: pd.DataFrame, by: By, labels: Mapping[str, str]) -> pd.DataFrame:
    """``frame`` with the given labels and shortened local paths in place of the raw values:
    in the ``run`` column (a label given for the run's folder name) and, with one ``--by``
    column, in that column (a label for the system, or its path's last component). Names that
    two systems would share stay raw.

    Raises:
        UnknownNameError: A label for no run or system of the frame (lists them).
    """
    keys = by_columns(by)
    display_names(frame, keys, labels)  # checks every label
    out = frame.copy()
    if "run" in out.columns and labels:
        runs = {r: labels.get(str(r), r) for r in dict.fromkeys(out["run"])}
        if len(set(runs.values())) == len(runs):
            out["run"] = out["run"].map(runs)
    if len(keys) != 1:
        return out
    key = keys[0]
    names: dict[object, object] = {}
    for (value,) in system_order(frame, keys):
        rows = system_rows(frame, keys, (value,))
        candidates = [str(value), *(str(r) for r in dict.fromkeys(rows.get("run", [])))]
        given = [labels[c] for c in candidates if c in labels]
        short = local_path_name(str(value))
        names[value] = given[0] if given else (short if short != str(value) else value)
    if len(set(names.values())) == len(names):
        out[key] = frame[key].map(names)
    return out
