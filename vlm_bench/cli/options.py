"""Option parsing shared by commands, with one-line errors."""

from __future__ import annotations

from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.types.task import INSTRUCTION_VARIANTS, InstructionVariant, Suite


def parse_seed(text: str) -> int:
    """A non-negative integer seed."""
    try:
        value = int(text)
    except ValueError:
        raise ConfigError(f"seed must be a non-negative integer, got {text!r}") from None
    if value < 0:
        raise ConfigError(f"seed must be a non-negative integer, got {text!r}")
    return value


def parse_seeds(text: str) -> list[int]:
    """Seeds as ``0,1,5`` or a range ``0-9``."""
    out: list[int] = []
    for part in text.split(","):
        part = part.strip()
        if "-" in part[1:]:
            lo, hi = part.split("-", 1)
            a, b = parse_seed(lo), parse_seed(hi)
            if b < a:
                raise ConfigError(f"empty seed range {part!r}")
            out.extend(range(a, b + 1))
        elif part:
            out.append(parse_seed(part))
    if not out:
        raise ConfigError("no seeds given")
    return out


def parse_suite(text: str | None) -> Suite | None:
    """A suite by value (``long_horizon``) or short alias (``lh``, ``long-horizon``)."""
    if text is None:
        return None
    norm = text.strip().lower().replace("-", "_").replace(" ", "_")
    aliases = {
        "base": Suite.BASE,
        "bm": Suite.BASE,
        "os": Suite.OBJECT_SPATIAL,
        "object": Suite.OBJECT_SPATIAL,
        "semantic": Suite.SEMANTIC,
        "su": Suite.SEMANTIC,
        "lh": Suite.LONG_HORIZON,
        "long": Suite.LONG_HORIZON,
    }
    for suite in Suite:
        if norm == suite.value:
            return suite
    if norm in aliases:
        return aliases[norm]
    raise UnknownNameError("suite", text, [s.value for s in Suite])


def parse_variant(text: str) -> InstructionVariant:
    """``explicit`` or ``implicit``."""
    norm = text.strip().lower()
    for variant in INSTRUCTION_VARIANTS:
        if norm == variant:
            return variant
    raise UnknownNameError("instruction variant", text, INSTRUCTION_VARIANTS)
