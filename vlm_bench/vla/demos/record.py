"""One demonstration: the scripted executor runs an episode's GT plan, varied and recorded."""

from __future__ import annotations

from dataclasses import dataclass

from vlm_bench.executor.live_episode import LiveEpisode
from vlm_bench.executor.sim_loop import SimLoop, Skill
from vlm_bench.executor.step_execution import SkillFactory
from vlm_bench.sim.render import SnapshotRenderer
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutionResult, SkillFailure
from vlm_bench.types.plan import ArmStep
from vlm_bench.vla.demos.recorder import DemoFrames, DemoRecorder
from vlm_bench.vla.demos.variation import VariedDemo, varied_config, varied_skills
from vlm_bench.vla.observation import ObservationConfig, ObservationRenderer


@dataclass(frozen=True)
class Demonstration:
    """A recorded execution of an episode's GT plan.

    Attributes:
        episode: The episode executed.
        draw: The variation it was executed with.
        frames: Observation and action of every control period (20 Hz).
        result: The execution's outcome (goals, VLA metrics).
    """

    episode: Episode
    draw: VariedDemo
    frames: DemoFrames
    result: ExecutionResult

    @property
    def kept(self) -> bool:
        """Whether it is a demonstration to learn from: it succeeded and every recorded action
        lies within the action space (a replay reproduces it)."""
        return self.result.exec_success and self.frames.out_of_bounds == 0


class _ArmStepMarks:
    """Tells the recorder which ARM step of the plan runs while a skill runs (the GT plan's
    ARM steps run once each, in order)."""

    def __init__(self, indices: list[int]) -> None:
        self.indices = indices
        self.calls = 0
        self.recorder: DemoRecorder | None = None

    def wrap(self, factory: SkillFactory) -> SkillFactory:
        def wrapped(loop: SimLoop) -> dict[str, Skill]:
            return {name: self._marked(skill) for name, skill in factory(loop).items()}

        return wrapped

    def _marked(self, skill: Skill) -> Skill:
        def run(episode: Episode, step: ArmStep) -> SkillFailure | None:
            index = self.indices[min(self.calls, len(self.indices) - 1)]
            self.calls += 1
            if self.recorder is not None:
                self.recorder.arm_step = index
            try:
                return skill(episode, step)
            finally:
                if self.recorder is not None:
                    self.recorder.arm_step = -1

        return run


def record_demo(
    episode: Episode,
    draw: VariedDemo,
    observation: ObservationConfig,
    renderer: SnapshotRenderer | None = None,
) -> Demonstration:
    """Execute ``episode``'s GT plan with the variation ``draw`` and record it.

    Args:
        episode: The episode (its GT plan is executed).
        draw: Speeds, hover offsets and grasp order of this demonstration.
        observation: The cameras and image size recorded.
        renderer: A renderer to share across demonstrations (kept open).
    """
    plan = episode.gt_plan
    marks = _ArmStepMarks([i for i, s in enumerate(plan) if isinstance(s, ArmStep)])
    live = LiveEpisode(episode, varied_config(draw), arm_skills=marks.wrap(varied_skills(draw)))
    observer = ObservationRenderer(observation, renderer)
    recorder = DemoRecorder(live.loop, observer)
    marks.recorder = recorder
    live.loop.observers.append(recorder)
    try:
        result = live.execute(plan)
    finally:
        observer.close()
    return Demonstration(episode=episode, draw=draw, frames=recorder.frames, result=result)
