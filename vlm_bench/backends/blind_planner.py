"""``blind``: perfect language, no vision — the strongest planner that never looks at a scene.

It reads what a model without vision reads: the instruction (as the GT's ARM steps,
``RequestMeta.arm_steps``: what a perfect reader writes), the object list, the rules and the
altitude the user turn states, and it knows the benchmark's GT plans of the task's *other*
seeds (leave-one-seed-out, so never the episode's own geometry). Before each ARM step it puts
the moves that maximise the expected S_loc credit of that segment (the moves before one ARM
step), each other seed weighted by how close its stated altitude is to this one's
(:data:`ALTITUDE_BANDWIDTH`), so an altitude that told the vertical moves would be used:

* one horizontal move, the direction whose expected credit (100 for the same sector, the
  neighbour credit for the next one) over the other seeds' first horizontal moves there is
  highest, whenever any other seed has one;
* one ``up`` or ``down``, whichever the other seeds have more weight of, whenever any has one.

A predicted move with no GT partner costs nothing in S_loc, so it guesses in every segment
where some seed moves: its ``Move_ratio`` above 1 and its ``S_loc_prec`` show the padding. A
task with no other seed falls back to all tasks' segment k. A VLM must beat its S_loc to show
that it uses the images.
"""

from __future__ import annotations

import math
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
ALTITUDE_BANDWIDTH = 0.1
"""m: a seed whose stated altitude lies this much from the episode's weighs e^-1/2 as much."""
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


@cache
def stated_altitudes() -> dict[tuple[str, int], float]:
    """(task id, seed) → the start altitude the user turn states (m, two decimals)."""
    return {
        (task.id, episode.seed): round(episode.uav_start.pos[2], 2)
        for task in all_tasks()
        for episode in load_materialised(task).episodes
    }


def _credit(guess: Direction, gt: Direction) -> float:
    if guess == gt:
        return 100.0
    gap = abs(HORIZONTAL_DIRECTIONS.index(guess) - HORIZONTAL_DIRECTIONS.index(gt))
    return NEIGHBOUR_CREDIT if min(gap, len(HORIZONTAL_DIRECTIONS) - gap) == 1 else 0.0


def guess_moves(seen: Sequence[tuple[Moves, float]]) -> list[Direction]:
    """The moves of one segment that maximise the expected credit, from the moves other seeds
    have there, each with its weight (see module doc)."""
    level: dict[Direction, float] = defaultdict(float)
    climb: dict[Direction, float] = defaultdict(float)
    for other, weight in seen:
        first = next((d for d in other if d.is_horizontal), None)
        if first is not None:
            level[first] += weight
        for d in {d for d in other if not d.is_horizontal}:
            climb[d] += weight
    moves: list[Direction] = []
    if level:  # ties go to the earlier direction
        expected = {
            g: sum(w * _credit(g, d) for d, w in level.items()) for g in HORIZONTAL_DIRECTIONS
        }
        moves.append(max(HORIZONTAL_DIRECTIONS, key=lambda g: expected[g]))
    if climb:
        vertical = max((Direction.UP, Direction.DOWN), key=lambda d: climb[d])
        moves.insert(0 if vertical is Direction.UP else len(moves), vertical)
    return moves


def _weight(altitude: float | None, other: float | None) -> float:
    if altitude is None or other is None:
        return 1.0
    return math.exp(-0.5 * ((altitude - other) / ALTITUDE_BANDWIDTH) ** 2) + 1e-9


def blind_plan(
    task_id: str, seed: int | None, arm_steps: Sequence[ArmStep], first: int = 0
) -> list[UavStep | ArmStep]:
    """The blind plan of one episode (see module doc); ``first``: the GT index of the first
    of ``arm_steps`` (a replan's rest)."""
    table, altitudes = segment_table(), stated_altitudes()
    altitude = altitudes.get((task_id, seed)) if seed is not None else None
    plan: list[UavStep | ArmStep] = []
    for k, step in enumerate(arm_steps, start=first):
        by_seed = table.get((task_id, k), {})
        seen = [
            (m, _weight(altitude, altitudes.get((task_id, s))))
            for s, m in sorted(by_seed.items())
            if s != seed
        ]
        if not seen:
            seen = [
                (m, 1.0)
                for (_, j), seeds in sorted(table.items())
                if j == k
                for m in seeds.values()
            ]
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
