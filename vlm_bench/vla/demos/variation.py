"""Seeded variation that makes scripted demonstrations differ the way teleoperated ones do.

One :class:`DemoVariation` (the ranges) and a demonstration's seed give a :class:`VariedDemo`
(the drawn values): the setpoint's cruise speed and acceleration, the arm's stow duration, a
hover offset and heading change made before every ARM step (the UAV hovers elsewhere and
the arm approaches from another side), and the order in which the grasp candidates are
tried (the first reachable one in that order is taken: a choice among the valid grasps).
Every value is drawn from ``numpy``'s generator seeded by the task, the episode seed and
the demonstration index, so an export is reproducible.
"""

from __future__ import annotations

import math
import zlib

import numpy as np
from pydantic import Field

from vlm_bench.executor.motion.base_move import BaseMove
from vlm_bench.executor.sim_loop import SimLoop, Skill
from vlm_bench.executor.skills.articulation import articulation_skills
from vlm_bench.executor.skills.grasp_points import GraspPoint
from vlm_bench.executor.skills.grasping import grasp_skills
from vlm_bench.executor.skills.hand import Hand
from vlm_bench.executor.skills.pushing import push_skills
from vlm_bench.executor.step_execution import SkillFactory
from vlm_bench.types.base import Frozen
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutorConfig, FlightConfig, SkillFailure
from vlm_bench.types.plan import ArmStep

MAX_SETPOINT_SPEED = 0.5  # m/s: FlightConfig's bound (a 50 ms step stays within the action's)


class DemoVariation(Frozen):
    """Ranges the variation of each demonstration is drawn from (uniform)."""

    speed: tuple[float, float] = Field(
        default=(0.3, 0.5), description="Cruise speed of the UAV setpoint (m/s), at most 0.5."
    )
    accel: tuple[float, float] = Field(
        default=(0.35, 0.7), description="Acceleration of the UAV setpoint (m/s²)."
    )
    stow_s: tuple[float, float] = Field(
        default=(1.2, 2.0), description="Duration of the arm's stow motion (s)."
    )
    hover_xy_m: float = Field(
        default=0.04, ge=0, le=0.15, description="Largest horizontal hover offset per ARM step (m)."
    )
    hover_z_m: float = Field(
        default=0.03, ge=0, le=0.1, description="Largest vertical hover offset per ARM step (m)."
    )
    heading_deg: float = Field(
        default=8.0, ge=0, le=30, description="Largest heading change per ARM step (deg)."
    )
    shuffle_grasps: bool = Field(
        default=True, description="Try the grasp candidates in a random order."
    )

    @classmethod
    def none(cls) -> DemoVariation:
        """No variation: the benchmark's executor exactly (its speeds, no offsets)."""
        flight = FlightConfig()
        return cls(
            speed=(flight.speed, flight.speed),
            accel=(flight.accel, flight.accel),
            stow_s=(flight.stow_s, flight.stow_s),
            hover_xy_m=0.0,
            hover_z_m=0.0,
            heading_deg=0.0,
            shuffle_grasps=False,
        )


class VariedDemo(Frozen):
    """The values drawn for one demonstration."""

    speed: float = Field(gt=0, le=MAX_SETPOINT_SPEED, description="Setpoint cruise speed (m/s).")
    accel: float = Field(gt=0, description="Setpoint acceleration (m/s²).")
    stow_s: float = Field(gt=0, description="Stow duration (s).")
    hover_seed: int = Field(description="Seed of the per-ARM-step hover offsets.")
    grasp_seed: int | None = Field(description="Seed of the grasp order; None: best first.")
    variation: DemoVariation = Field(description="The ranges the offsets are drawn from.")


def demo_seed(task_id: str, seed: int, index: int = 0) -> int:
    """A stable 32-bit seed of one demonstration (the same on every machine and run)."""
    return zlib.crc32(f"demo/{task_id}/{seed}/{index}".encode())


def draw_variation(variation: DemoVariation, task_id: str, seed: int, index: int = 0) -> VariedDemo:
    """The variation of demonstration ``index`` of episode ``task_id``/``seed``."""
    rng = np.random.default_rng(demo_seed(task_id, seed, index))

    def pick(bounds: tuple[float, float]) -> float:
        lo, hi = sorted(bounds)
        return float(rng.uniform(lo, hi)) if hi > lo else float(lo)

    speed = min(MAX_SETPOINT_SPEED, pick(variation.speed))
    accel, stow_s = pick(variation.accel), pick(variation.stow_s)
    hover_seed, grasp_seed = (int(x) for x in rng.integers(0, 2**31, size=2))
    return VariedDemo(
        speed=speed,
        accel=accel,
        stow_s=stow_s,
        hover_seed=hover_seed,
        grasp_seed=grasp_seed if variation.shuffle_grasps else None,
        variation=variation,
    )


def varied_config(draw: VariedDemo, base: ExecutorConfig | None = None) -> ExecutorConfig:
    """``base`` (default: the benchmark's) with the drawn flight speed, acceleration, stow."""
    base = base or ExecutorConfig()
    flight = base.flight.model_copy(
        update={"speed": draw.speed, "accel": draw.accel, "stow_s": draw.stow_s}
    )
    return base.model_copy(update={"flight": flight})


class _HoverThenSkill:
    """Shifts the hover point and heading by a drawn offset, then runs the skill."""

    def __init__(self, hand: Hand, skill: Skill, rng: np.random.Generator, v: DemoVariation):
        self.hand, self.skill, self.rng, self.v = hand, skill, rng, v

    def __call__(self, episode: Episode, step: ArmStep) -> SkillFailure | None:
        v, rng = self.v, self.rng
        r, a = v.hover_xy_m * math.sqrt(rng.uniform()), rng.uniform(0.0, 2 * math.pi)
        xyz = np.array([r * math.cos(a), r * math.sin(a), rng.uniform(-v.hover_z_m, v.hover_z_m)])
        yaw = math.radians(rng.uniform(-v.heading_deg, v.heading_deg))
        # a held object is carried as the pick left it: only the empty hand's hover varies
        if self.hand.loop.held is None and (np.any(xyz) or yaw):
            self.hand.shift_base(BaseMove(xyz, yaw))
        return self.skill(episode, step)


def varied_skills(draw: VariedDemo) -> SkillFactory:
    """The scripted ARM skills with the drawn hover offsets and grasp order."""

    def factory(loop: SimLoop) -> dict[str, Skill]:
        hand = Hand(loop)
        grasp_rng = np.random.default_rng(draw.grasp_seed)

        def order(candidates: list[GraspPoint]) -> list[GraspPoint]:
            return [candidates[i] for i in grasp_rng.permutation(len(candidates))]

        skills: dict[str, Skill] = {
            **grasp_skills(loop, hand, order if draw.grasp_seed is not None else None),
            **push_skills(loop, hand),
            **articulation_skills(loop, hand),
        }
        rng = np.random.default_rng(draw.hover_seed)
        return {name: _HoverThenSkill(hand, s, rng, draw.variation) for name, s in skills.items()}

    return factory
