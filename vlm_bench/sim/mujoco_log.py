"""MuJoCo's warnings go to Python logging, never to ``MUJOCO_LOG.TXT`` in the working folder.

By default MuJoCo prints every warning (an unstable simulation: "Nan, Inf or huge value in QACC")
and appends it to ``MUJOCO_LOG.TXT`` in the current directory, a file the user never asked for.
:func:`route_mujoco_log` sends warnings to the ``vlm_bench.sim.mujoco`` logger instead and turns
the log file off (errors already reach Python as ``mujoco.FatalError``). The executor records an
unstable simulation in the episode's outcome; the log keeps MuJoCo's own words.
"""

from __future__ import annotations

import logging

LOGGER = logging.getLogger("vlm_bench.sim.mujoco")
"""Where MuJoCo's warnings go."""


def _warn(message: str) -> None:
    LOGGER.warning("MuJoCo: %s", message.strip())


def route_mujoco_log() -> None:
    """Send MuJoCo's warnings to :data:`LOGGER` and write no log file (idempotent, per process;
    MuJoCo's handlers are process-wide)."""
    import mujoco

    if mujoco.get_mju_user_warning() is not _warn:
        mujoco.set_mju_user_warning(_warn)
    config = mujoco.MjLogConfig.get()
    if config.logto_file:
        config.logto_file = False
        config.set()
