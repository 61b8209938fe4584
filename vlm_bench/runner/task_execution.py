"""Execute one plan on one episode (the ``execute`` command), optionally filming it.

The gusts (``uav_noise``) use the same per-episode seed as runs, so executing a run's plan here
reproduces the run's execution. The simulator is imported only when something is executed.
"""

from __future__ import annotations

from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path

from vlm_bench.episodes import get_episode
from vlm_bench.errors import ConfigError
from vlm_bench.parsing import parse_plan
from vlm_bench.parsing.schema import MAX_PLAN_STEPS
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionResult, ExecutorConfig
from vlm_bench.types.parse import ParseCode
from vlm_bench.types.plan import ArmStep, PlanSteps, UavStep
from vlm_bench.types.task import InstructionVariant


@dataclass(frozen=True)
class VideoOptions:
    """What to film during an execution."""

    path: Path
    """Output file: ``.mp4`` (needs the ``video`` extra) or ``.gif``."""
    camera: str = "side"
    """Camera name (``uav``, ``wrist``, ``overhead``, ``side``, ...)."""
    fps: float = 10.0
    """Wanted frames per second (rounded to a divisor of the 20 Hz control rate)."""
    size: int = 480
    """Frame side in pixels."""
    shadows: bool = True
    """Render shadows (2–3× the cost per frame on a CPU)."""


@dataclass(frozen=True)
class ExecutedPlan:
    """One executed plan and what came of it."""

    episode: Episode
    """The episode (scene, goals, GT plan)."""
    variant: InstructionVariant
    """Instruction variant the plan answers (both share the scene and the goals)."""
    plan: tuple[UavStep | ArmStep, ...]
    """The executed steps."""
    source: str
    """Where the plan came from: ``GT`` or the file name."""
    uav_noise: float
    """Gust force std on the UAV (N)."""
    result: ExecutionResult
    """Per-step outcomes, goals, VLA metrics."""
    goal_labels: tuple[str, ...]
    """``predicate(object[, target])`` of each goal, in the order of ``result.goals``."""
    video: Path | None = None
    """The video file, if one was recorded."""
    frames: int = 0
    """Frames in the video."""


def plan_from_text(text: str, episode: Episode, source: str) -> list[UavStep | ArmStep]:
    """The steps of a plan written in the paper's JSON format (any repairable form).

    Raises:
        ConfigError: No plan in the text, or an invalid step (names the step and its codes).
    """
    parsed = parse_plan(text, episode.object_ids())
    if ParseCode.TOO_LONG in parsed.errors:
        raise ConfigError(
            f"{source}: the plan has more than {MAX_PLAN_STEPS} steps, the most a plan may have"
        )
    if not parsed.usable:
        codes = ", ".join(str(c) for c in parsed.errors) or "no plan"
        raise ConfigError(f"{source}: no plan in the paper's JSON format found ({codes})")
    for step in parsed.steps:
        if not step.valid:
            codes = ", ".join(str(c) for c in step.errors) or "invalid"
            raise ConfigError(f"{source}: step {step.index} is invalid ({codes})")
    return parsed.valid_steps()


def execute_task_plan(
    task_id: str,
    seed: int,
    plan: str | PlanSteps | None = None,
    *,
    source: str = "plan",
    variant: InstructionVariant = "explicit",
    uav_noise: float = 0.0,
    video: VideoOptions | None = None,
) -> ExecutedPlan:
    """Execute a plan on an episode.

    Args:
        task_id: Task id.
        seed: Episode seed.
        plan: Plan text in the paper's JSON format, typed steps, or None for the GT plan.
        source: Name of the plan's origin in error messages (e.g. the file name).
        variant: Instruction variant (a label: both variants share scene and goals).
        uav_noise: Gust force std on the UAV (N); the gust seed is the episode's, as in runs.
        video: Record a video.

    Raises:
        UnknownNameError: Unknown task or camera. ConfigError: Invalid plan or options.
        MissingExtraError: MP4 without the ``video`` extra.
    """
    from vlm_bench.executor.goals import describe_goal
    from vlm_bench.executor.live_episode import execute_plan
    from vlm_bench.executor.step_execution import episode_scene
    from vlm_bench.executor.video import VideoRecorder

    if uav_noise < 0:
        raise ConfigError(f"uav_noise must be >= 0, got {uav_noise:g}")
    episode = get_episode(task_id, seed)
    if plan is None:
        steps, source = list(episode.gt_plan), "GT"
    elif isinstance(plan, str):
        steps = plan_from_text(plan, episode, source)
    else:
        steps = list(plan)
    config = ExecutorConfig(uav_noise=uav_noise)
    scene = episode_scene(episode, config)
    with ExitStack() as stack:
        recorder = None
        if video is not None:
            recorder = stack.enter_context(
                VideoRecorder(
                    video.path, video.camera, video.size, video.fps, shadows=video.shadows
                )
            )
            recorder.start(scene)
        result = execute_plan(
            episode,
            steps,
            config,
            scene,
            observers=(recorder,) if recorder is not None else (),
        )
    return ExecutedPlan(
        episode=episode,
        variant=variant,
        plan=tuple(steps),
        source=source,
        uav_noise=uav_noise,
        result=result,
        goal_labels=tuple(describe_goal(g) for g in episode.goals),
        video=recorder.path if recorder is not None else None,
        frames=recorder.frames if recorder is not None else 0,
    )
