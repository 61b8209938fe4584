"""Hierarchical VLM+VLA use (docs/design.md#hierarchical-use): a plan whose ARM steps a user
policy drives.

The planner's UAV ``move`` steps are flown by the executor; during every ARM step the policy is
called once per 50 ms control step (20 Hz) with a :class:`VlaObservation` and returns a
:class:`VlaAction` (12-D: 4 UAV setpoint deltas, 7 joint targets, gripper), which is applied for
one control period. Returning ``None``, or an action with ``done=True`` (applied first), ends
the step; it then counts as ``ok`` and the task's goals judge the outcome after the plan. A
policy that does not end the step within ``max_steps`` fails it::

    result = execute_plan(episode, plan, arm_skills=policy_skills(my_policy, render_size=64))

After each policy-driven step, the object both fingers touch (if any) becomes the loop's held
object, so the next UAV move and ``place`` reference it as the scripted skills would.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from vlm_bench.catalog.skills import arm_skill_names
from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.errors import ConfigError
from vlm_bench.executor.sim_loop import SimLoop, Skill
from vlm_bench.executor.step_execution import SkillFactory
from vlm_bench.sim.constants import CAMERAS, CONTROL_DT, LEFT_FINGER_BODY, RIGHT_FINGER_BODY
from vlm_bench.sim.objects.bounds import subtree_geoms
from vlm_bench.sim.render import SnapshotRenderer
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import FailureCode, SkillFailure
from vlm_bench.types.plan import ArmStep
from vlm_bench.types.task import InstructionVariant
from vlm_bench.vla.action import (
    VlaAction,
    apply_action,
)
from vlm_bench.vla.observation import (
    DEFAULT_RENDER_SIZE,
    ObservationConfig,
    ObservationRenderer,
    VlaObservation,
)

PolicyOutput = VlaAction | NDArray[np.floating] | Sequence[float] | None
DEFAULT_MAX_STEPS = 600  # control steps (30 s) a policy may take for one ARM step


class Policy(Protocol):
    """A low-level policy: called every control step (20 Hz) during an ARM step."""

    def __call__(self, observation: VlaObservation, step: ArmStep, /) -> PolicyOutput:
        """The next action (a :class:`VlaAction` or its 12-value array form, clipped like
        :meth:`VlaAction.from_array`), or ``None`` to end the step (it then counts as done)."""
        ...


def grasped_object(loop: SimLoop, episode: Episode) -> str | None:
    """The graspable object both fingers touch now, if any."""
    model, data = loop.model, loop.data
    fingers = [
        set(subtree_geoms(model, model.body(name).id))
        for name in (LEFT_FINGER_BODY, RIGHT_FINGER_BODY)
    ]
    touched: list[set[int]] = [set(), set()]  # geoms each finger touches
    for i in range(data.ncon):
        g1, g2 = int(data.contact.geom[i][0]), int(data.contact.geom[i][1])
        for side, geoms in enumerate(fingers):
            if g1 in geoms:
                touched[side].add(g2)
            elif g2 in geoms:
                touched[side].add(g1)
    if not (touched[0] and touched[1]):
        return None
    for obj in episode.objects:
        if object_kind(obj.kind).graspable:
            geoms = set(subtree_geoms(model, model.body(obj.id).id))
            if geoms & touched[0] and geoms & touched[1]:
                return obj.id
    return None


class _PolicyStep:
    """Runs one ARM step under the policy, rendering the observation every control step."""

    def __init__(
        self,
        loop: SimLoop,
        policy: Policy,
        max_steps: int,
        observer: ObservationRenderer,
        variant: InstructionVariant,
    ) -> None:
        self.loop = loop
        self.policy = policy
        self.max_steps = max_steps
        self.observer = observer
        self.variant = variant

    def __call__(self, episode: Episode, step: ArmStep) -> SkillFailure | None:
        loop = self.loop
        instruction = episode.instruction(self.variant)
        try:
            for k in range(self.max_steps):
                obs = self.observer.observe(loop, instruction, step, k)
                output = self.policy(obs, step)
                if output is None:
                    return None
                action = output if isinstance(output, VlaAction) else VlaAction.from_array(output)
                apply_action(loop, action)
                if action.done:
                    return None
        finally:
            loop.held = grasped_object(loop, episode)
            self.observer.close()  # frees a private GL context between steps
        seconds = self.max_steps * CONTROL_DT
        return SkillFailure(
            FailureCode.POLICY_TIMEOUT,
            f"policy did not finish {step.skill} {step.object} within {self.max_steps} "
            f"control steps ({seconds:g} s)",
        )


def policy_skills(
    policy: Policy,
    max_steps: int = DEFAULT_MAX_STEPS,
    render_size: int = DEFAULT_RENDER_SIZE,
    views: Sequence[str] = CAMERAS,
    *,
    shadows: bool = False,
    variant: InstructionVariant = "explicit",
    skills: Collection[str] | None = None,
    renderer: SnapshotRenderer | None = None,
) -> SkillFactory:
    """ARM skills for :func:`~vlm_bench.executor.live_episode.execute_plan` driven by ``policy``.

    Args:
        policy: Called every control step of every ARM step.
        max_steps: Control steps (50 ms each) a step may take before it fails.
        render_size: Side of the observation images (px).
        views: Cameras rendered into each observation; fewer views are faster (``()``: none).
        shadows: Render shadows (about 2.5x slower on CPU).
        variant: Which instruction text the observation carries.
        skills: Skill names the policy handles (default: every ARM skill of the library);
            any other skill fails its step as unavailable.
        renderer: A renderer to share (kept open); otherwise one is made and freed per step.

    Returns:
        A factory to pass as ``arm_skills``.
    """
    if max_steps < 1:
        raise ConfigError(f"max_steps must be >= 1, got {max_steps}")
    config = ObservationConfig(views=tuple(views), size=render_size, shadows=shadows)
    names = tuple(arm_skill_names() if skills is None else skills)

    def factory(loop: SimLoop) -> dict[str, Skill]:
        run = _PolicyStep(loop, policy, max_steps, ObservationRenderer(config, renderer), variant)
        return dict.fromkeys(names, run)

    return factory
