"""Perturbations are keyed by what happens (docs/closed-loop.md#perturbations): the GT plan, the
GT plan with an extra put-down and pick-up of the held object, and the GT plan with its carry
split into two legs meet the same events on the ARM steps and carries they share."""

from __future__ import annotations

from collections import Counter

import pytest

from vlm_bench.episodes import get_episode
from vlm_bench.executor.live_episode import execute_plan
from vlm_bench.types.closed_loop import PerturbConfig, PerturbEvent
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutorConfig
from vlm_bench.types.plan import ArmStep, PlanSteps, UavStep

EPISODES = (
    ("stacking_box_on_wood", 3),
    ("place_on_flat_surface", 3),
    ("stacking_box_on_wood", 0),
    ("place_on_flat_surface", 0),
)
CONFIG = ExecutorConfig(perturb=PerturbConfig(slip=0.5, bump=0.5))

Occasion = tuple[str, ...]


def _pick(plan: PlanSteps) -> int:
    return next(i for i, s in enumerate(plan) if isinstance(s, ArmStep) and s.skill == "pick")


def put_down_and_pick_up(episode: Episode) -> list[UavStep | ArmStep]:
    """The GT plan with the picked object put back on its support and picked again."""
    plan = list(episode.gt_plan)
    i = _pick(plan)
    held = plan[i]
    assert isinstance(held, ArmStep)
    support = next(o.on for o in episode.objects if o.id == held.object)
    extra = [ArmStep(object=support, skill="place"), ArmStep(object=held.object, skill="pick")]
    return [*plan[: i + 1], *extra, *plan[i + 1 :]]


def split_carry(episode: Episode) -> list[UavStep | ArmStep]:
    """The GT plan with the carry's first flight flown in two legs."""
    plan = list(episode.gt_plan)
    i = _pick(plan) + 1
    leg = plan[i]
    assert isinstance(leg, UavStep)
    first = UavStep(direction=leg.direction, distance=0.1)
    return [*plan[:i], first, leg, *plan[i + 1 :]]


def occasions(
    plan: PlanSteps, events: tuple[PerturbEvent, ...]
) -> tuple[dict[Occasion, object], set[Occasion]]:
    """Each event by what it happened on: a bump by its ARM step (object, skill, target, n-th
    such step), a slip by its carry (object, destination, n-th such carry); and every occasion
    the plan offers."""
    seen: Counter[Occasion] = Counter()
    arm: dict[int, Occasion] = {}
    carry: dict[int, Occasion] = {}
    held, current = None, None
    for i, step in enumerate(plan):
        if isinstance(step, ArmStep):
            key = (step.object, step.skill, step.target or "")
            arm[i] = ("bump", *key, str(seen[key]))
            seen[key] += 1
            held = step.object if step.skill == "pick" else None
            current = None
        elif held is not None:
            if current is None:
                dest = next((s.object for s in plan[i:] if isinstance(s, ArmStep)), "")
                key = ("carry", held, dest)
                current = ("slip", held, dest, str(seen[key]))
                seen[key] += 1
            carry[i] = current
    out: dict[Occasion, object] = {}
    for e in events:
        if e.kind == "bump":
            out[arm[e.step]] = (e.object, e.shift)
        else:
            out[carry[e.step]] = e.object
    return out, {*arm.values(), *carry.values()}


@pytest.mark.slow
def test_plans_that_do_the_same_things_meet_the_same_events() -> None:
    fired = Counter[str]()
    for task, seed in EPISODES:
        episode = get_episode(task, seed)
        gt = list(episode.gt_plan)
        base, offered = occasions(gt, execute_plan(episode, gt, CONFIG).perturbations or ())
        fired.update(o[0] for o in base)
        for variant in (put_down_and_pick_up(episode), split_carry(episode)):
            run = execute_plan(episode, variant, CONFIG).perturbations or ()
            got, _ = occasions(variant, run)
            shared = {o: event for o, event in got.items() if o in offered}
            assert shared == base, (task, seed, variant)
    assert fired["bump"] > 0 and fired["slip"] > 0  # several episodes with events of both kinds
