"""Text-only planners beside ``blind``: how much of S_loc the prompt's text alone gives.

Usage: ``python benchmarks/text_only_planners.py [--seeds 0-9]``

Every planner writes the GT's ARM steps (a perfect reader of the instruction) and guesses the
UAV moves from what a model without vision has: the instruction, the object list, the rules,
the stated start altitude and, for the learned ones, the task's *other* seeds' GT plans
(leave-one-seed-out). Printed per planner, as means over the episodes of both instructions
(they share their GT plans): S_plan, S_loc, S_loc_prec, Move_ratio and S_total.

* ``blind``: the builtin floor (:mod:`vlm_bench.backends.blind_planner`): in every segment the
  horizontal move of highest expected credit over all tasks' other seeds and the ``up``/``down``
  most of the task's other seeds have.
* ``constant``: no benchmark data: ``front`` then ``down`` before every ARM step.
* ``altitude_weighted``: the version-3 ``blind`` of its first measurement: expected-credit
  guesses from the task's own other seeds only, each weighted by how close its stated altitude
  is (Gaussian, 0.1 m). Leaving one seed out of a task whose sectors are balanced over its
  seeds favours every direction but the held-out one.
* ``altitude_rule``: no benchmark data. Assumes the first object stands on a 0.75 m table, so
  the arm works from about 1.5 m: ``down`` above 1.7 m, ``up`` below 1.3 m, in the first segment;
  one ``front`` move before every ARM step.
* ``task_threshold``: per task, the two altitude thresholds that best split the other seeds'
  first vertical moves into ``up`` / none / ``down``, applied to the stated altitude; every
  other move the most frequent one of the other seeds (the version-2 ``blind``).
* ``majority``: the version-2 ``blind``: the most frequent moves of the other seeds, no padding.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
from collections import Counter
from collections.abc import Callable, Sequence
from functools import cache

from vlm_bench.backends.blind_planner import (
    Moves,
    blind_plan,
    guess_horizontal,
    guess_vertical,
    segment_table,
)
from vlm_bench.catalog.gt_episodes import load_materialised
from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.parsing import parse_plan
from vlm_bench.scoring import score_plan
from vlm_bench.types.episode import Episode
from vlm_bench.types.plan import ArmStep, Direction, UavStep, plan_to_json

Plan = list[UavStep | ArmStep]
Planner = Callable[[Episode], Plan]
RULE_HIGH, RULE_LOW = 1.7, 1.3  # m: the altitude rule's down / up thresholds


def _most_common(items: Sequence[Direction | None]) -> Direction | None:
    order = [*Direction, None]
    counts = Counter(items)
    return max(counts, key=lambda d: (counts[d], -order.index(d))) if counts else None


def majority_moves(seen: Sequence[Moves], vertical: bool = True) -> list[Direction]:
    """The most frequent horizontal move (when most seeds have one) and vertical move."""
    if not seen:
        return []
    level = [next((d for d in m if d.is_horizontal), None) for m in seen]
    moves = []
    if 2 * sum(d is not None for d in level) > len(seen):
        moves.append(_most_common([d for d in level if d is not None]))
    climb = _most_common([next((d for d in m if not d.is_horizontal), None) for m in seen])
    if vertical and climb is Direction.UP:
        moves.insert(0, climb)
    elif vertical and climb is Direction.DOWN:
        moves.append(climb)
    return [d for d in moves if d is not None]


def _other_seeds(episode: Episode, k: int) -> list[Moves]:
    by_seed = segment_table().get((episode.task_id, k), {})
    return [m for s, m in sorted(by_seed.items()) if s != episode.seed]


def _assemble(episode: Episode, moves: Callable[[int], list[Direction]]) -> Plan:
    plan: Plan = []
    for k, step in enumerate(episode.arm_steps()):
        plan.extend(UavStep(direction=d) for d in moves(k))
        plan.append(step)
    return plan


@cache
def stated_altitudes() -> dict[tuple[str, int], float]:
    """(task id, seed) → the start altitude the user turn states (m, two decimals)."""
    return {
        (task.id, episode.seed): round(episode.uav_start.pos[2], 2)
        for task in all_tasks()
        for episode in load_materialised(task).episodes
    }


def _altitude(episode: Episode) -> float:
    return stated_altitudes()[(episode.task_id, episode.seed)]


def constant(episode: Episode) -> Plan:
    return _assemble(episode, lambda k: [Direction.FRONT, Direction.DOWN])


def altitude_weighted(episode: Episode, bandwidth: float = 0.1) -> Plan:
    """Each other seed of the task counted as often as exp(-½(Δaltitude / bandwidth)²) says,
    rounded to hundredths (the guesses' weighted counts)."""
    z = _altitude(episode)

    def moves(k: int) -> list[Direction]:
        seen: list[Moves] = []
        for s, m in sorted(segment_table().get((episode.task_id, k), {}).items()):
            if s != episode.seed:
                gap = (stated_altitudes()[(episode.task_id, s)] - z) / bandwidth
                seen.extend([m] * max(1, round(100 * math.exp(-0.5 * gap * gap))))
        vertical = guess_vertical(seen)
        level = guess_horizontal(seen)
        return [*vertical, *level] if vertical == [Direction.UP] else [*level, *vertical]

    return _assemble(episode, moves)


def blind(episode: Episode) -> Plan:
    return blind_plan(episode.task_id, episode.seed, episode.arm_steps())


def altitude_rule(episode: Episode) -> Plan:
    z = _altitude(episode)
    first = [Direction.UP] if z < RULE_LOW else [Direction.DOWN] if z > RULE_HIGH else []

    def moves(k: int) -> list[Direction]:
        vertical = first if k == 0 else []
        up = [d for d in vertical if d is Direction.UP]
        return [*up, Direction.FRONT, *(d for d in vertical if d is Direction.DOWN)]

    return _assemble(episode, moves)


def first_vertical(moves: Moves) -> int:
    """-1 ``up``, 0 none, +1 ``down``: where the start lay from the working altitude."""
    return next((-1 if d is Direction.UP else 1 for d in moves if not d.is_horizontal), 0)


def fit_thresholds(pairs: Sequence[tuple[float, int]]) -> tuple[float, float]:
    """(lo, hi) maximising the seeds whose side is -1 below lo, +1 above hi, else 0."""
    cuts = sorted({z for z, _ in pairs})
    candidates = [-1e9, *((a + b) / 2 for a, b in itertools.pairwise(cuts)), 1e9]

    def hits(lo: float, hi: float) -> int:
        return sum((-1 if z < lo else 1 if z > hi else 0) == side for z, side in pairs)

    return max(
        ((lo, hi) for lo in candidates for hi in candidates if lo <= hi),
        key=lambda c: (hits(*c), -abs(c[1] - c[0])),
    )


def task_threshold(episode: Episode) -> Plan:
    table, altitudes = segment_table(), stated_altitudes()
    pairs = [
        (altitudes[(episode.task_id, s)], first_vertical(m))
        for s, m in table.get((episode.task_id, 0), {}).items()
        if s != episode.seed
    ]
    lo, hi = fit_thresholds(pairs)
    z = _altitude(episode)
    side = -1 if z < lo else 1 if z > hi else 0

    def moves(k: int) -> list[Direction]:
        if k > 0:
            return majority_moves(_other_seeds(episode, k))
        level = majority_moves(_other_seeds(episode, 0), vertical=False)
        return [Direction.UP, *level] if side < 0 else [*level, Direction.DOWN] if side else level

    return _assemble(episode, moves)


def majority(episode: Episode) -> Plan:
    return _assemble(episode, lambda k: majority_moves(_other_seeds(episode, k)))


PLANNERS: dict[str, Planner] = {
    "blind": blind,
    "constant": constant,
    "altitude_weighted": altitude_weighted,
    "altitude_rule": altitude_rule,
    "task_threshold": task_threshold,
    "majority": majority,
}


def evaluate(planner: Planner, seeds: Sequence[int]) -> dict[str, float]:
    """Mean scores of ``planner`` over every task's episodes of ``seeds``, both instructions."""
    rows = []
    for task in all_tasks():
        for episode in load_materialised(task).episodes:
            if episode.seed not in seeds:
                continue
            ids = sorted({r for s in episode.arm_steps() for r in (s.object, s.target) if r})
            parsed = parse_plan(json.dumps(plan_to_json(planner(episode))), ids)
            scores = score_plan(parsed, episode.gt_plan)
            ratio = scores.n_move_pred / scores.n_move if scores.n_move else 1.0
            row = (scores.s_plan, scores.s_loc, scores.s_loc_precision, ratio, scores.s_total)
            rows.extend([row, row])  # the explicit and implicit instructions share the plan
    names = ("S_plan", "S_loc", "S_loc_prec", "Move_ratio", "S_total")
    return {
        "episodes": len(rows),
        **{n: sum(r[i] for r in rows) / len(rows) for i, n in enumerate(names)},
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", default="0-9", help="seed range, e.g. 0-9")
    args = parser.parse_args()
    lo, _, hi = args.seeds.partition("-")
    seeds = list(range(int(lo), int(hi or lo) + 1))
    print("planner          episodes  S_plan  S_loc  S_loc_prec  Move_ratio  S_total")
    for name, planner in PLANNERS.items():
        r = evaluate(planner, seeds)
        print(
            f"{name:<16} {r['episodes']:>8.0f}  {r['S_plan']:6.1f}  {r['S_loc']:5.1f}  "
            f"{r['S_loc_prec']:10.1f}  {r['Move_ratio']:10.2f}  {r['S_total']:7.1f}"
        )


if __name__ == "__main__":
    main()
