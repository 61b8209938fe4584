"""The paper's VLA metrics (Appendix A.3) from an execution's measured traces.

Per ARM step *i* of the executed plan (N of them; skipped and unknown-object steps score 0):

* ``s_pos = 100`` if the step succeeded, else ``100·G(d; λ_act)`` when the arm moved towards the
  object (≥ 5 cm closer), ``100·G(d; λ_hov)`` when it only hovered, with
  ``G(d; λ) = λ·exp(−(d−μ)²/2σ²)·𝟙(d_min ≤ d ≤ d_max)`` and *d* the arm-base distance to the
  step's reference point when the step began; ``S_pos`` is their mean.
* ``S_arm = 100·(β·S_ori + (1−β)/N·Σ s_int)`` with ``s_int = exp(−d_ee²/2σ_arm²)·𝟙(d_ee ≤
  d_thresh)``, *d_ee* the closest approach of the TCP to the object's box (of the held object's
  centre to its resting point for a place), and ``S_ori = 1`` iff at every ARM step's closest
  approach the TCP axis was within ``ori_max_tilt_deg`` of straight down.
* ``S_safe = 100·exp(−Δ²/2σ_safe²)·𝟙(Δ < Δ_limit)`` with Δ the total displacement of non-target
  movable objects (100 for Δ ≤ the dead band).
* ``S_task = 100·done/K`` over the task's K goals.

A plan without ARM steps scores 0 on ``S_pos`` and ``S_arm``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from vlm_bench.types.execution import ArmTrace, StepOutcome, VlaMetricConfig, VlaScores


def position_kernel(d: float, lam: float, cfg: VlaMetricConfig) -> float:
    """``G(d; λ)`` of the paper, in [0, λ]."""
    if not cfg.pos_min <= d <= cfg.pos_max:
        return 0.0
    return lam * math.exp(-((d - cfg.pos_mu) ** 2) / (2 * cfg.pos_sigma**2))


def step_position_score(outcome: StepOutcome, cfg: VlaMetricConfig) -> float:
    """``s_pos`` of one ARM step (0–100)."""
    arm = outcome.arm
    if outcome.status == "ok":
        return 100.0
    if outcome.status == "skipped" or arm is None or arm.base_distance is None:
        return 0.0
    lam = cfg.lambda_act if arm.attempted else cfg.lambda_hov
    return 100.0 * position_kernel(arm.base_distance, lam, cfg)


def interaction_score(arm: ArmTrace | None, cfg: VlaMetricConfig) -> float:
    """``s_int`` of one ARM step (0–1)."""
    if arm is None or arm.ee_distance is None or arm.ee_distance > cfg.arm_thresh:
        return 0.0
    return math.exp(-(arm.ee_distance**2) / (2 * cfg.arm_sigma**2))


def orientation_ok(arms: Sequence[ArmTrace | None], cfg: VlaMetricConfig) -> bool:
    """``S_ori``: every ARM step reached its object with the TCP pointing down."""
    return bool(arms) and all(
        a is not None and a.tilt_deg is not None and a.tilt_deg <= cfg.ori_max_tilt_deg
        for a in arms
    )


def safety_score(total_displacement: float, cfg: VlaMetricConfig) -> float:
    """``S_safe`` (0–100) of a total non-target displacement in metres."""
    if total_displacement <= cfg.safe_deadband:
        return 100.0
    if total_displacement >= cfg.safe_limit:
        return 0.0
    return 100.0 * math.exp(-(total_displacement**2) / (2 * cfg.safe_sigma**2))


def vla_scores(
    outcomes: Sequence[StepOutcome],
    goals: Sequence[bool],
    displacement: dict[str, float],
    cfg: VlaMetricConfig | None = None,
) -> VlaScores:
    """All four metrics and their weighted total for one execution."""
    cfg = cfg or VlaMetricConfig()
    arm_steps = [o for o in outcomes if o.agent == "ARM"]
    arms = [o.arm for o in arm_steps]
    if arm_steps:
        s_pos = sum(step_position_score(o, cfg) for o in arm_steps) / len(arm_steps)
        s_int = sum(interaction_score(a, cfg) for a in arms) / len(arms)
        s_arm = 100.0 * (cfg.arm_beta * orientation_ok(arms, cfg) + (1 - cfg.arm_beta) * s_int)
    else:
        s_pos = s_arm = 0.0
    s_safe = safety_score(sum(displacement.values()), cfg)
    s_task = 100.0 * sum(goals) / len(goals) if goals else 0.0
    weights = cfg.w_pos + cfg.w_arm + cfg.w_safe + cfg.w_task
    total = (
        cfg.w_pos * s_pos + cfg.w_arm * s_arm + cfg.w_safe * s_safe + cfg.w_task * s_task
    ) / weights
    return VlaScores(
        s_pos=_clip(s_pos),
        s_arm=_clip(s_arm),
        s_safe=_clip(s_safe),
        s_task=_clip(s_task),
        total=_clip(total),
    )


def _clip(v: float) -> float:
    return min(100.0, max(0.0, v))
