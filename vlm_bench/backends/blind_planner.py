"""``blind``: perfect language, no vision — the strongest planner that never looks at a scene.

It writes the GT's ARM steps (``RequestMeta.arm_steps``: what a perfect reader of the instruction
writes) and, before each, the UAV moves it can only guess: what the benchmark's GT most often
has at that position of that task, learned from the materialised GT plans of the task's *other*
seeds (leave-one-out, so never from the episode's own geometry). Per segment (the moves before
ARM step k): a horizontal move when most other seeds have one, in their most frequent
direction; ``up`` or ``down`` when that is the most frequent vertical move; ordered as the
prompt's rules order them (``up`` first, ``down`` last). A task with no other seed falls back
to all tasks' segment k. A VLM must beat its S_loc to show that it uses the images.
"""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Sequence
from functools import cache

from vlm_bench.backends.builtin import PlannerBackend
from vlm_bench.catalog.gt_episodes import load_materialised
from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.rules import remaining_arm_steps
from vlm_bench.types.generation import GenerationRequest
from vlm_bench.types.plan import ArmStep, Direction, UavStep

Moves = tuple[Direction, ...]
SegmentTable = dict[tuple[str, int], dict[int, Moves]]
"""(task id, segment index) → seed → the GT's moves before that ARM step."""


def segments(plan: Sequence[UavStep | ArmStep]) -> list[Moves]:
    """The UAV moves before each ARM step of ``plan`` (trailing moves dropped)."""
    out: list[Moves] = []
    pending: list[Direction] = []
    for step in plan:
        if isinstance(step, UavStep):
            pending.append(step.direction)
        else:
            out.append(tuple(pending))
            pending = []
    return out


@cache
def segment_table() -> SegmentTable:
    """The moves of every materialised GT plan, by task, segment and seed (cached)."""
    table: SegmentTable = defaultdict(dict)
    for task in all_tasks():
        for episode in load_materialised(task).episodes:  # their GT plans only
            for k, moves in enumerate(segments(episode.gt_plan)):
                table[(task.id, k)][episode.seed] = moves
    return dict(table)


def _most_common(counts: Counter[Direction | None]) -> Direction | None:
    order = [*Direction, None]  # ties go to the earlier direction, then to no move
    return max(counts, key=lambda d: (counts[d], -order.index(d))) if counts else None


def guess_moves(seen: Sequence[Moves]) -> list[Direction]:
    """The moves of one segment guessed from the moves other seeds have there."""
    if not seen:
        return []
    horizontal = [next((d for d in m if d.is_horizontal), None) for m in seen]
    vertical = Counter(next((d for d in m if not d.is_horizontal), None) for m in seen)
    level = None
    if 2 * sum(d is not None for d in horizontal) > len(seen):
        level = _most_common(Counter(d for d in horizontal if d is not None))
    climb = _most_common(vertical)
    moves = [d for d in (level,) if d is not None]
    if climb is Direction.UP:
        moves.insert(0, climb)
    elif climb is Direction.DOWN:
        moves.append(climb)
    return moves


def blind_plan(
    task_id: str, seed: int | None, arm_steps: Sequence[ArmStep], first: int = 0
) -> list[UavStep | ArmStep]:
    """The blind plan of one episode (see module doc); ``first``: the GT index of the first
    of ``arm_steps`` (a replan's rest)."""
    table = segment_table()
    plan: list[UavStep | ArmStep] = []
    for k, step in enumerate(arm_steps, start=first):
        by_seed = table.get((task_id, k), {})
        seen = [m for s, m in sorted(by_seed.items()) if s != seed]
        if not seen:
            seen = [m for (_, j), seeds in sorted(table.items()) if j == k for m in seeds.values()]
        plan.extend(UavStep(direction=d) for d in guess_moves(seen))
        plan.append(step)
    return plan


class BlindBackend(PlannerBackend):
    """GT ARM steps with the UAV moves guessed from other seeds (see module doc)."""

    name = "blind"

    def plan(self, request: GenerationRequest) -> Sequence[UavStep | ArmStep] | str:
        """The blind plan from ``meta.task_id``, ``meta.seed`` and ``meta.arm_steps``; in a
        replan, of the ARM steps left (read from the feedback, never from the views)."""
        meta = request.meta
        if meta is None or meta.arm_steps is None or not meta.task_id:
            return "blind: request has no meta.task_id and meta.arm_steps"
        if meta.round == 0:
            return blind_plan(meta.task_id, meta.seed, meta.arm_steps)
        first, rest = remaining_arm_steps(meta.arm_steps, meta.done_steps, meta.held)
        return blind_plan(meta.task_id, meta.seed, rest, first)
