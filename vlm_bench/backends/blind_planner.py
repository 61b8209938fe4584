"""``blind``: perfect language, no vision — the strongest planner that never looks at a scene.

It reads what a model without vision reads: the instruction (as the GT's ARM steps,
``RequestMeta.arm_steps``: what a perfect reader writes), the object list and the rules, and it
knows the benchmark's GT plans of the *other* seeds (leave one seed out: no GT plan of the
episode's own seed, of any task, is read). Before each ARM step k it puts the moves of highest
expected S_loc credit:

* one horizontal move, the direction whose expected credit (100 for the same sector, the
  neighbour credit for the next one) is highest over the first horizontal moves that segment k
  has in every task's other seeds. Pooled over tasks, because a task's sectors are drawn
  independently per seed: its own other seeds tell nothing, and leaving one seed out of an
  exactly balanced count would favour every direction but the episode's own;
* one ``up`` or ``down``, whichever more of the task's other seeds have in segment k (all
  tasks' other seeds where the task has none): a place on a stack climbs, a drop into a low
  bin descends, whatever the scene.

A predicted move with no GT partner costs nothing in S_loc, so it guesses in every segment: its
``Move_ratio`` above 1 and its ``S_loc_prec`` show the padding. The stated start altitude is not
read: on version 3's GT it tells nothing about the moves (weighting the other seeds by it scores
lower). A VLM must beat its S_loc to show that it uses the images; ``python
benchmarks/text_only_planners.py`` puts the other text-only planners beside it.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from functools import cache

from vlm_bench.backends.builtin import PlannerBackend
from vlm_bench.catalog.gt_episodes import load_materialised
from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.rules import remaining_arm_steps
from vlm_bench.types.generation import GenerationRequest
from vlm_bench.types.plan import HORIZONTAL_DIRECTIONS, ArmStep, Direction, UavStep

Moves = tuple[Direction, ...]
SegmentTable = dict[tuple[str, int], dict[int, Moves]]
"""(task id, segment index) → seed → the GT's moves before that ARM step."""
NEIGHBOUR_CREDIT = 40.0
"""S_loc's default credit for a neighbouring sector (``ScoringConfig.neighbour_credit``)."""


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


def _credit(guess: Direction, gt: Direction) -> float:
    if guess == gt:
        return 100.0
    gap = abs(HORIZONTAL_DIRECTIONS.index(guess) - HORIZONTAL_DIRECTIONS.index(gt))
    return NEIGHBOUR_CREDIT if min(gap, len(HORIZONTAL_DIRECTIONS) - gap) == 1 else 0.0


def guess_horizontal(seen: Sequence[Moves]) -> list[Direction]:
    """The horizontal move of highest expected credit over the first horizontal moves of
    ``seen`` (ties to the earlier direction); none when no segment of ``seen`` has one."""
    level: dict[Direction, int] = defaultdict(int)
    for moves in seen:
        first = next((d for d in moves if d.is_horizontal), None)
        if first is not None:
            level[first] += 1
    if not level:
        return []
    expected = {g: sum(n * _credit(g, d) for d, n in level.items()) for g in HORIZONTAL_DIRECTIONS}
    return [max(HORIZONTAL_DIRECTIONS, key=lambda g: expected[g])]


def guess_vertical(seen: Sequence[Moves]) -> list[Direction]:
    """``up`` or ``down``, whichever more segments of ``seen`` have (``up`` on a tie); none
    when no segment has either."""
    counts = {d: sum(d in moves for moves in seen) for d in (Direction.UP, Direction.DOWN)}
    if not any(counts.values()):
        return []
    return [max((Direction.UP, Direction.DOWN), key=lambda d: counts[d])]


def _other_seeds(table: SegmentTable, k: int, seed: int | None, task_id: str | None) -> list[Moves]:
    """Segment k's moves in the seeds other than ``seed``: of ``task_id``, or of every task."""
    return [
        moves
        for (task, j), by_seed in sorted(table.items())
        if j == k and task_id in (None, task)
        for s, moves in sorted(by_seed.items())
        if s != seed
    ]


def blind_plan(
    task_id: str, seed: int | None, arm_steps: Sequence[ArmStep], first: int = 0
) -> list[UavStep | ArmStep]:
    """The blind plan of one episode (see module doc); ``first``: the GT index of the first
    of ``arm_steps`` (a replan's rest)."""
    table = segment_table()
    plan: list[UavStep | ArmStep] = []
    for k, step in enumerate(arm_steps, start=first):
        pooled = _other_seeds(table, k, seed, None)
        own = _other_seeds(table, k, seed, task_id)
        vertical = guess_vertical(own if any(own) else pooled)
        level = guess_horizontal(pooled)
        if vertical == [Direction.UP]:
            plan.extend(UavStep(direction=d) for d in (*vertical, *level))
        else:
            plan.extend(UavStep(direction=d) for d in (*level, *vertical))
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
