"""Procedural builders for every object kind of the world catalogue.

Importing this package registers one builder per kind in :data:`OBJECT_BUILDERS`
(the family modules below register theirs when imported).
"""

from vlm_bench.sim.objects import (  # noqa: F401  (imported to register their builders)
    articulated,
    containers,
    furniture,
    groceries,
    industrial,
    tableware,
    toys,
)
from vlm_bench.sim.objects.bounds import geom_bounds, object_bounds
from vlm_bench.sim.objects.builder_kit import OBJECT_BUILDERS, ObjectBuilder, free_joint_name
from vlm_bench.sim.objects.placement import add_object, apply_initial_state

__all__ = [
    "OBJECT_BUILDERS",
    "ObjectBuilder",
    "add_object",
    "apply_initial_state",
    "free_joint_name",
    "geom_bounds",
    "object_bounds",
]
