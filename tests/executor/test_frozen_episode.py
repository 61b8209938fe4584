"""A frozen live episode, thawed, continues exactly as the original does."""

from __future__ import annotations

from vlm_bench.episodes import get_episode
from vlm_bench.executor.frozen_episode import freeze, thaw
from vlm_bench.executor.live_episode import LiveEpisode
from vlm_bench.executor.live_state import episode_now
from vlm_bench.sim.scene import build_spec
from vlm_bench.types.closed_loop import PerturbConfig
from vlm_bench.types.execution import ExecutorConfig
from vlm_bench.types.plan import ArmStep

TASK = "place_on_flat_surface"  # its GT flies with the object in the hand


def _dump(result: object) -> dict[str, object]:
    return result.model_dump(exclude={"wall_time_s"})  # type: ignore[attr-defined]


def test_a_thawed_episode_continues_bit_for_bit() -> None:
    episode = get_episode(TASK, 0)
    plan = list(episode.gt_plan)
    pick = next(i for i, s in enumerate(plan) if isinstance(s, ArmStep) and s.skill == "pick")
    first, rest = plan[: pick + 1], plan[pick + 1 :]
    live = LiveEpisode(episode, ExecutorConfig(perturb=PerturbConfig(slip=0.5, bump=0.5)))
    live.execute(first)  # the object is in the hand: the rest flies it (a seeded slip may fire)
    assert live.held is not None
    thawed = thaw(freeze(live), build_spec(episode))
    assert thawed.held == live.held and thawed.rounds == live.rounds == 1
    want, got = live.execute(rest), thawed.execute(rest)
    assert _dump(got) == _dump(want)  # steps, goals, displacement, pose, clock, perturbations
    assert episode_now(thawed) == episode_now(live)
    assert thawed.held == live.held
