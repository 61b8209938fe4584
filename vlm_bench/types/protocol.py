"""The stated protocols: which episodes and settings a number quoted as "vlm-bench" means.

A protocol fixes the episode set (all tasks × :attr:`ProtocolSpec.seeds` × both instructions)
and every setting that changes a score; it leaves free what only identifies or serves the model
(the model string, backend arguments, ``max_new_tokens``, batch size) and, for the open-loop
``paper`` protocol, whether plans are also executed (the paper's metrics do not depend on it).
A run is *of* a protocol when its settings equal the protocol's and its episodes are a subset of
the protocol's; :class:`ProtocolMark` says which share of them it ran. Any other run is
``custom``. The matching itself is :func:`vlm_bench.types.protocol_match.protocol_of`.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from vlm_bench.types.base import Frozen
from vlm_bench.types.closed_loop import PerturbConfig
from vlm_bench.types.prompt import VIEWS
from vlm_bench.types.task import INSTRUCTION_VARIANTS

ProtocolName = Literal["paper", "closed", "custom"]
"""A protocol's name; ``custom`` = no stated protocol."""

CUSTOM: ProtocolName = "custom"
QUOTED: ProtocolName = "paper"
"""The protocol a paper should quote (the AIR-VLA paper's open-loop VLM evaluation)."""


class ProtocolSpec(Frozen):
    """One stated protocol: its episodes and the run settings it fixes."""

    name: ProtocolName = Field(description="Protocol name (--protocol).")
    description: str = Field(description="One line: what it measures.")
    seeds: tuple[int, ...] = Field(description="Episode seeds (with every task, both variants).")
    settings: dict[str, Any] = Field(
        description="RunConfig fields it fixes beyond their defaults (every other scored field "
        "keeps its default)."
    )


_PAPER: dict[str, Any] = {
    "views": VIEWS,
    "resolution": 448,
    "k_shot": 2,
    "loop": "open",
}
_CLOSED: dict[str, Any] = {
    **_PAPER,
    "loop": "closed",
    "max_rounds": 3,
    "execute": True,
    "perturb": PerturbConfig(slip=0.3, bump=0.3),
}

PROTOCOLS: dict[str, ProtocolSpec] = {
    "paper": ProtocolSpec(
        name="paper",
        description="the AIR-VLA paper's VLM evaluation: seeds 0-9, both instructions, four "
        "views at 448 px, 2-shot, greedy, open loop",
        seeds=tuple(range(10)),
        settings=_PAPER,
    ),
    "closed": ProtocolSpec(
        name="closed",
        description="paper + closed loop: up to 3 replans, perturbations slip=0.3,bump=0.3",
        seeds=tuple(range(10)),
        settings=_CLOSED,
    ),
}
"""The stated protocols by name (the one place they are defined)."""

PROTOCOL_INSTRUCTIONS = INSTRUCTION_VARIANTS
"""Instruction variants of every protocol's episode set."""


class ProtocolMark(Frozen):
    """The protocol of a run, recorded in its manifest and shown beside its numbers."""

    name: ProtocolName = Field(description="paper, closed, or custom (no stated protocol).")
    episodes: int | None = Field(
        default=None, ge=0, description="Episodes the run evaluates (None: not recorded)."
    )
    protocol_episodes: int | None = Field(
        default=None,
        ge=1,
        description="Episodes of the full protocol (None for custom or when not recorded).",
    )

    @property
    def complete(self) -> bool:
        """Whether the run covers the protocol's every episode (False for custom)."""
        return (
            self.name != CUSTOM
            and self.episodes is not None
            and self.episodes == self.protocol_episodes
        )

    @property
    def fraction(self) -> float | None:
        """Share of the protocol's episodes the run evaluates (None: custom or unknown)."""
        if self.name == CUSTOM or self.episodes is None or not self.protocol_episodes:
            return None
        return self.episodes / self.protocol_episodes

    def label(self) -> str:
        """``paper``, ``paper (240 of 1,200 episodes, 20%)`` or ``custom``."""
        fraction = self.fraction
        if fraction is None or self.complete:
            return self.name
        percent = 100 * fraction
        shown = f"{percent:.0f}" if percent >= 10 or percent == int(percent) else f"{percent:.1f}"
        return f"{self.name} ({self.episodes:,} of {self.protocol_episodes:,} episodes, {shown}%)"
