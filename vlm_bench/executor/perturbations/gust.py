"""``gust=N``: random wind on the UAV, a force of standard deviation N newtons (``--uav-noise``).

A gust acts through the UAV controller for the whole execution, so it has no hook: its value is
the run's ``uav_noise`` and the scene is built with it (:func:`gust_config`), seeded per episode
as every run is.
"""

from __future__ import annotations

from vlm_bench.executor.perturbations.kind import PerturbationKind
from vlm_bench.sim.uav_control import GustConfig
from vlm_bench.types.episode import Episode
from vlm_bench.types.execution import ExecutorConfig


class Gust(PerturbationKind):
    """Wind on the UAV (module doc); its value is ``uav_noise``, not a probability."""

    name = "gust"
    maximum = None


def gust_config(episode: Episode, config: ExecutorConfig) -> GustConfig | None:
    """The gusts of ``episode``'s scene (None: calm)."""
    if config.uav_noise <= 0:
        return None
    return GustConfig(
        force_std=config.uav_noise,
        torque_std=0.05 * config.uav_noise,
        seed=config.gust_seed(episode.task_id, episode.seed),
    )
