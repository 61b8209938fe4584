"""Execute a validated plan in the simulator, step by step, stopping at the first failure.

After the last step the scene settles (servo targets and UAV setpoint held), then the task's
goal predicates are checked, non-target objects' displacement is measured and the VLA metrics
are computed. The steps run in :mod:`~vlm_bench.executor.step_execution`; an execution is one round
of a :class:`~vlm_bench.executor.live_episode.LiveEpisode` on a fresh scene.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from vlm_bench.executor.live_episode import LiveEpisode
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.executor.skills.scripted_skills import default_skills
from vlm_bench.executor.step_execution import (
    PlanExecution,
    SkillFactory,
    episode_scene,
    execute_move,
    next_arm_step,
    target_ids,
)
from vlm_bench.sim.scene import Scene
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionResult, ExecutorConfig
from vlm_bench.types.plan import PlanSteps

__all__ = [
    "PlanExecution",
    "PlanSteps",
    "SkillFactory",
    "episode_scene",
    "execute_move",
    "execute_plan",
    "next_arm_step",
    "target_ids",
]


def execute_plan(
    episode: Episode,
    plan: PlanSteps,
    config: ExecutorConfig | None = None,
    scene: Scene | None = None,
    arm_skills: SkillFactory = default_skills,
    observers: Sequence[Callable[[SimLoop], None]] = (),
) -> ExecutionResult:
    """Execute ``plan`` on ``episode``'s scene (built fresh unless ``scene`` is given).

    Args:
        episode: The episode (scene, goals, GT used for non-target objects).
        plan: Validated plan steps.
        config: Executor settings (default: the benchmark's), gusts and perturbations included.
        scene: A scene to run on instead of building one (it is modified).
        arm_skills: Makes the ARM skills for the loop (default: the scripted skills); a skill
            missing there fails its step with a reason. Hierarchical pipelines pass
            policy-driven skills here.
        observers: Called after every control step (e.g. a video recorder).

    Execution stops at the first failed step; later steps are skipped. The result is always
    returned (simulator blow-ups and a spent simulated-time budget,
    :meth:`~vlm_bench.types.execution.ExecutorConfig.sim_budget_s`, become failed steps).
    """
    live = LiveEpisode(episode, config, scene, arm_skills, observers)
    return live.execute(plan)
