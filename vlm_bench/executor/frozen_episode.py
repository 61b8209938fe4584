"""A frozen episode: a live episode frozen to bytes and thawed again, to continue exactly where
it stopped (distinct from the cached PNG views of an episode).

A closed-loop replan continues the simulation its last round left. :func:`freeze` writes the
whole :class:`~vlm_bench.executor.live_episode.LiveEpisode` object graph (the simulator's
``MjData`` and ``MjModel``, the UAV controller's integrator and gusts, the skills' hand and
planner caches, the perturbations' random streams, what the robot believes it holds) with
cloudpickle, which also takes the skills' closures; :func:`thaw` in any process gives a live
episode whose next :meth:`~vlm_bench.executor.live_episode.LiveEpisode.execute` returns what
the original's would, bit for bit (tests/executor/test_frozen_episode.py).

Two pieces are not plain pickles:

* ``MjData``'s own pickle drops the sleeping islands' counters (``nbody_awake``,
  ``ntree_awake``, ``nv_awake``, ``nl``) and the per-island solver statistics; with sleeping
  enabled (``sim.constants.SLEEP``) the thawed data would stop with "found sleeping tree".
  They are written beside it and set again.
* The scene's ``MjSpec`` (uncompiled description, not picklable) is only read when a scene is
  built: the caller passes the episode's (:func:`~vlm_bench.sim.scene.build_spec`).
"""

from __future__ import annotations

import io
import pickle
import zlib
from typing import Any

import cloudpickle
import mujoco
import numpy as np

from vlm_bench.executor.live_episode import LiveEpisode

_SPEC = "mjspec"
_LEVEL = 1
"""zlib level: the pickle (about 20 MB: the scene's and the arm planners' models and data)
shrinks about tenfold in some 60 ms; snapshots queue in the parent for replans to start."""
_DATA_COUNTERS = ("nbody_awake", "ntree_awake", "nv_awake", "nl")
_DATA_ARRAYS = ("solver_niter", "solver_nnz")


def _thaw_data(blob: bytes, counters: dict[str, int], arrays: dict[str, Any]) -> mujoco.MjData:
    data: mujoco.MjData = pickle.loads(blob)
    for name, value in counters.items():
        setattr(data, name, value)
    for name, value in arrays.items():
        getattr(data, name)[...] = value
    return data


class _Pickler(cloudpickle.Pickler):  # type: ignore[misc]
    def persistent_id(self, obj: object) -> str | None:
        return _SPEC if isinstance(obj, mujoco.MjSpec) else None

    def reducer_override(self, obj: object) -> Any:
        if isinstance(obj, mujoco.MjData):
            counters = {n: int(getattr(obj, n)) for n in _DATA_COUNTERS}
            arrays = {n: np.array(getattr(obj, n)) for n in _DATA_ARRAYS}
            return _thaw_data, (pickle.dumps(obj, protocol=5), counters, arrays)
        return super().reducer_override(obj)


class _Unpickler(pickle.Unpickler):
    def __init__(self, blob: bytes, spec: mujoco.MjSpec) -> None:
        super().__init__(io.BytesIO(blob))
        self.spec = spec

    def persistent_load(self, pid: object) -> mujoco.MjSpec:
        if pid != _SPEC:
            raise pickle.UnpicklingError(f"unknown persistent id {pid!r}")
        return self.spec


def freeze(live: LiveEpisode) -> bytes:
    """``live`` as bytes (see module doc); ``live`` itself is left as it is."""
    out = io.BytesIO()
    _Pickler(out, protocol=5).dump(live)
    return zlib.compress(out.getbuffer(), _LEVEL)


def thaw(blob: bytes, spec: mujoco.MjSpec) -> LiveEpisode:
    """The live episode :func:`freeze` wrote, its scene's spec ``spec``."""
    live = _Unpickler(zlib.decompress(blob), spec).load()
    if not isinstance(live, LiveEpisode):
        raise TypeError(f"not a frozen live episode: {type(live).__name__}")
    return live
