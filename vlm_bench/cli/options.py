"""Option parsing shared by commands, with one-line errors."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

from vlm_bench.errors import ConfigError, UnknownNameError
from vlm_bench.types.closed_loop import PerturbConfig
from vlm_bench.types.task import INSTRUCTION_VARIANTS, InstructionVariant, Suite

if TYPE_CHECKING:
    from rich.console import Console

PIPE_WIDTH = 200
"""Columns of tables printed to a pipe or file (no terminal width to respect): nothing is cut."""


def table_console(console: Console) -> Console:
    """``console`` where it writes to a terminal, else one :data:`PIPE_WIDTH` wide without colour.

    Decided by the file's own ``isatty()``, not rich's ``is_terminal``, which ``FORCE_COLOR`` or
    ``TTY_COMPATIBLE`` turn on for a redirected stream (and would then wrap a log at 80 columns).
    """
    from rich.console import Console

    isatty = getattr(console.file, "isatty", None)
    try:
        tty = bool(isatty()) if isatty is not None else False
    except ValueError:  # a closed stream
        tty = False
    return console if tty else Console(file=console.file, width=PIPE_WIDTH, color_system=None)


MAX_SEED = 2**32 - 1
"""Largest episode seed (seeds are stored as integers every reader handles)."""

MAX_SEEDS = 10_000
"""Most seeds one run takes (each seed is 120 episodes)."""


def parse_seed(text: str) -> int:
    """A seed: an integer in 0..MAX_SEED."""
    try:
        value = int(text)
    except ValueError:
        raise ConfigError(f"seed must be a non-negative integer, got {text!r}") from None
    if not 0 <= value <= MAX_SEED:
        raise ConfigError(f"seed must be an integer in 0..{MAX_SEED}, got {text!r}")
    return value


def parse_seeds(text: str) -> list[int]:
    """Seeds as ``0,1,5`` or a range ``0-9`` (at most MAX_SEEDS in all)."""
    out: set[int] = set()
    for part in text.split(","):
        part = part.strip()
        if "-" in part[1:]:
            lo, hi = part.split("-", 1)
            a, b = parse_seed(lo), parse_seed(hi)
            if b < a:
                raise ConfigError(f"empty seed range {part!r}")
            if b - a + 1 + len(out) > MAX_SEEDS:
                raise ConfigError(f"too many seeds in {text!r}: at most {MAX_SEEDS} per run")
            out.update(range(a, b + 1))
        elif part:
            out.add(parse_seed(part))
            if len(out) > MAX_SEEDS:
                raise ConfigError(f"too many seeds in {text!r}: at most {MAX_SEEDS} per run")
    if not out:
        raise ConfigError("no seeds given")
    return sorted(out)


def finite(option: str, value: float) -> float:
    """``value`` when it is a finite number (JSON and the simulator have no NaN or infinity).

    Raises:
        ConfigError: Names the option, e.g. ``--uav-noise must be a finite number, got inf``.
    """
    if not math.isfinite(value):
        raise ConfigError(f"{option} must be a finite number, got {value}")
    return value


def writable_folder(option: str, folder: Path) -> None:
    """Check that ``folder`` is, or can be made, a folder (before any work is done).

    Raises:
        ConfigError: ``folder`` or a folder above it is a file (names the option and the path).
    """
    if folder.exists() and not folder.is_dir():
        raise ConfigError(f"{option} {folder} is a file, not a folder")
    blocking = next((p for p in folder.parents if p.exists() and not p.is_dir()), None)
    if blocking is not None:
        raise ConfigError(f"{option} {folder}: {blocking} is a file, not a folder")


def writable_file(option: str, path: Path, *, make_folder: bool) -> None:
    """Check that ``path`` can be written as a file: not a folder, and its folder exists (or
    can be made, when ``make_folder``).

    Raises:
        ConfigError: Names the option and the path.
    """
    if path.is_dir():
        raise ConfigError(f"{option} {path} is a folder; give a file name")
    if make_folder:
        writable_folder(option, path.parent)
    elif not path.parent.is_dir():
        raise ConfigError(f"{option} {path}: folder {path.parent} does not exist")


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


def image_file(option: str, path: Path) -> None:
    """Check that ``path`` names an image format Pillow writes (``.png``, ``.jpg``, ...).

    Raises:
        ConfigError: Names the option and the suffix.
    """
    from PIL import Image

    if path.suffix.lower() not in Image.registered_extensions():
        raise ConfigError(f"{option} {path}: unknown image format {path.suffix!r}; use .png")


def perturb_options(text: str | None, uav_noise: float) -> tuple[PerturbConfig | None, float]:
    """``--perturb`` as perturbations, and the gust std from its ``gust`` or ``--uav-noise``
    (:func:`vlm_bench.executor.perturbations.perturb_options`, which the API calls too).

    Raises:
        ConfigError: A bad ``--perturb``, or a ``gust`` and a different ``--uav-noise``.
    """
    from vlm_bench.executor.perturbations import perturb_options as parsed

    return parsed(text, uav_noise)
