"""docs/design.md#layers draws the layer contract pyproject.toml gives import-linter."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = {p.parent.name for p in (ROOT / "vlm_bench").glob("*/__init__.py")} | {
    p.stem for p in (ROOT / "vlm_bench").glob("*.py")
}


def contract_layers() -> list[list[set[str]]]:
    """The layers contract: each layer as its independent groups of modules, top first."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]
    (contract,) = [c for c in config["contracts"] if c["type"] == "layers"]
    return [
        [{part.strip().removeprefix("vlm_bench.")} for part in layer.split("|")]
        for layer in contract["layers"]
    ]


def diagram_layers() -> list[list[set[str]]]:
    """The diagram under ``## Layers``: the package names of each row (before its description,
    which follows two or more spaces), per ``|`` group."""
    text = (ROOT / "docs" / "design.md").read_text()
    block = re.search(r"^## Layers\n.*?^```\n(.*?)^```", text, re.S | re.M)
    assert block is not None, "design.md has no layer diagram"
    rows = []
    for line in block.group(1).splitlines():
        groups = [
            {word for word in re.findall(r"[a-z_]+", part) if word in PACKAGES}
            for part in re.split(r"\s{2,}", line.strip())[0].split("|")
        ]
        rows.append([g for g in groups if g])
    return rows


def test_the_layer_diagram_is_the_import_linter_contract() -> None:
    assert diagram_layers() == contract_layers()
