"""The benchmark version: which tasks, ground truth, prompts and metrics a run evaluates.

The version changes when a change to the task specs, the materialised GT, the prompt text or the
metrics changes what a score means; docs/benchmark-versions.md says what changed in each and
why. Every run records the version in its manifest (``RunConfig.benchmark_version``), where it
enters the config hash; scores of different versions are not comparable, so reports refuse to put
them in one table unless asked, and a run or rescore happens only in the version this release
evaluates.
"""

from __future__ import annotations

from collections.abc import Sequence

from vlm_bench.errors import ConfigError

BENCHMARK_VERSION = 3
"""The benchmark version this release evaluates (the one place it is defined)."""

FIRST_VERSION = 1
"""The version of every run written before versions were recorded: a manifest without one."""


class BenchmarkVersionError(ConfigError):
    """Runs of different benchmark versions where one version is needed."""


def version_label(version: int) -> str:
    """``2``, or ``1, from before versions were recorded`` (what version 1 is)."""
    return (
        f"{version}, from before versions were recorded"
        if version == FIRST_VERSION
        else str(version)
    )


def check_one_version(runs: Sequence[tuple[str, int]], *, hint: str) -> None:
    """Refuse runs (name, version) of more than one benchmark version.

    Args:
        runs: Each run's name and benchmark version.
        hint: How to proceed anyway (ends the message), e.g. ``pass --mixed-versions``.

    Raises:
        BenchmarkVersionError: One line naming every run with its version.
    """
    if len({version for _, version in runs}) <= 1:
        return
    listed = ", ".join(f"{name} (version {version_label(v)})" for name, v in runs)
    raise BenchmarkVersionError(
        f"runs of different benchmark versions cannot share a table: {listed}; {hint}"
    )


def require_current_version(version: int, what: str) -> None:
    """Refuse to evaluate anything but :data:`BENCHMARK_VERSION` with this release.

    Args:
        version: The version asked for (a run config's or a stored run's).
        what: What asks for it, e.g. ``run results/qwen`` (starts the message).

    Raises:
        BenchmarkVersionError: One line naming both versions.
    """
    if version != BENCHMARK_VERSION:
        raise BenchmarkVersionError(
            f"{what} is benchmark version {version_label(version)}; this release evaluates "
            f"version {BENCHMARK_VERSION} (other tasks, ground truth, prompts or metrics; "
            "docs/benchmark-versions.md): use the release that made it, or run the model again"
        )
