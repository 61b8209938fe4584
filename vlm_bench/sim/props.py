"""Static decorative props that make each environment variant recognisable: the builder of each
variant (:mod:`~vlm_bench.sim.props_indoor`, :mod:`~vlm_bench.sim.props_outdoor`), picked by
variant name, else by environment type. The kit they are built with (names, the keep-out rule,
wall fixtures) is :mod:`~vlm_bench.sim.prop_kit`.
"""

from __future__ import annotations

from collections.abc import Callable

import mujoco

from vlm_bench.sim import props_indoor, props_outdoor
from vlm_bench.types.world import EnvironmentSpec

_BY_NAME: dict[str, Callable[[mujoco.MjSpec, EnvironmentSpec], None]] = {
    "household_kitchen": props_indoor.kitchen,
    "household_living_room": props_indoor.living_room,
    "industrial_workshop": props_indoor.workshop,
    "industrial_warehouse": props_indoor.warehouse,
    "outdoor_garden": props_outdoor.garden,
    "outdoor_yard": props_outdoor.yard,
}
_BY_TYPE = {
    "household": props_indoor.living_room,
    "industrial": props_indoor.workshop,
    "outdoor": props_outdoor.garden,
}


def add_props(spec: mujoco.MjSpec, env: EnvironmentSpec) -> None:
    """Add the decorative props of an environment variant (by variant name, else by type)."""
    builder = _BY_NAME.get(env.name, _BY_TYPE[env.type])
    builder(spec, env)
