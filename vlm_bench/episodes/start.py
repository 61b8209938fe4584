"""Where the UAV starts: the first move's sector and the start altitude (docs/design.md#episodes).

The start must tell a planner without vision nothing about the first segment's moves:

* **Altitude.** The UAV starts within :data:`START_JITTER` of the working altitude the first
  ARM step would have if the table under its object were the standard one (top 0.75 m). Which
  vertical move the first segment needs is set by that table's height instead: a high table
  (the UAV starts below: ``up``), the standard one (no vertical move) or a low one (``down``).
  So the stated altitude has the same distribution whatever the first vertical move is, and
  only the table's height in the views tells it. A first object with no table under it (a
  cabinet's drawer, a stove's knob) is worked at the start altitude.
* **Sector.** The first move's body-frame sector is drawn per seed by a hash-seeded permutation
  of the tasks, as is the vertical side: each seed spreads them evenly over the 60 tasks, while
  per task the seeds are independent draws (a balance over one task's seeds would tell a
  planner that knows the other seeds the held-out one: the value they miss).

Seed 0 keeps the canonical layout, standard tables included, so it starts level.
"""

from __future__ import annotations

import itertools
import zlib
from functools import cache

import numpy as np

from vlm_bench.catalog.tasks import all_tasks, task_index
from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.episodes.layout import TABLE_KINDS
from vlm_bench.rules.approach import VERTICAL_MARGIN
from vlm_bench.types.geometry import APPROACH
from vlm_bench.types.task import TaskSpec

START_JITTER = 0.04
"""m: the start altitude lies this close to the first working altitude on a standard table."""
SECTOR_SALT = 0x5EC7
SIDE_SALT = 0x51DE
ALTITUDE_SALT = 31_337


@cache
def table_step() -> float:
    """Height (m) between consecutive table kinds' tops (:data:`~.layout.TABLE_KINDS`);
    raises ``ValueError`` when they are not evenly spaced clear of the vertical threshold."""
    tops = [object_kind(kind).size[2] for kind in TABLE_KINDS]
    steps = {round(b - a, 6) for a, b in itertools.pairwise(tops)}
    step = steps.pop()
    move = APPROACH.vertical_threshold + VERTICAL_MARGIN
    stay = APPROACH.vertical_threshold - VERTICAL_MARGIN
    if steps or step - START_JITTER < move or stay < START_JITTER:
        raise ValueError(f"table tops {tops} do not decide the vertical move clearly")
    return step


def _seed_permutation(seed: int, salt: int) -> np.ndarray:
    """A hash-seeded permutation of the task indices for one seed."""
    return np.random.default_rng([seed, salt]).permutation(len(all_tasks()))


def first_sector(task_id: str, seed: int) -> int:
    """Body-frame sector (0 = front, CCW) of the first move (see module doc)."""
    return int(_seed_permutation(seed, SECTOR_SALT)[task_index(task_id)]) % 8


def vertical_start(task_id: str, seed: int) -> int:
    """The first segment's vertical move as where the start lies from the first working
    altitude: -1 below (``up``), 0 level, +1 above (``down``); 0 at seed 0 (see module doc)."""
    if seed == 0:
        return 0
    return int(_seed_permutation(seed, SIDE_SALT)[task_index(task_id)]) % 3 - 1


def bearing_table(task: TaskSpec) -> str | None:
    """Id of the table under the first ARM step's object (following what it rests on), or
    None when it stands on no table (a part's fixture, the floor)."""
    on = {o.id: o.on for o in task.objects}
    kinds = {o.id: o.kind for o in task.objects}
    oid: str | None = task.arm_steps[0].object
    seen: set[str] = set()
    while oid is not None and oid in on and oid not in seen:
        if kinds[oid] == "table":
            return oid
        seen.add(oid)
        oid = on[oid]
    return None


def start_sides(task: TaskSpec, seed: int) -> list[int]:
    """Sides to try in turn: :func:`vertical_start`'s, then the next ones round (a layout
    whose geometry rules a side out, e.g. a later move's altitude near its threshold over
    that table, takes the next); only 0 when no table bears the first object."""
    if bearing_table(task) is None:
        return [0]
    first = vertical_start(task.id, seed)
    return [(first + 1 + k) % 3 - 1 for k in range(3)]


def first_table_kind(task: TaskSpec, side: int) -> tuple[str, str] | None:
    """(table id, kind) the first ARM step's table is built as for ``side``, or None."""
    table = bearing_table(task)
    if table is None:
        return None
    return table, TABLE_KINDS[1 - side]


def start_altitude(task: TaskSpec, seed: int, attempt: int, working: float, side: int) -> float:
    """The start altitude (m) of one attempt for ``side``, given the first working altitude
    ``working`` of the attempt's layout (see module doc)."""
    rng = np.random.default_rng([zlib.crc32(task.id.encode()), seed, attempt, ALTITUDE_SALT])
    return round(working + side * table_step() + float(rng.uniform(-START_JITTER, START_JITTER)), 4)
