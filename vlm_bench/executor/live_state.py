"""What a live episode looks like now: the episode as it stands (objects where they are, drawers
as open as they are, the UAV where it is) and its camera views.

The state is an :class:`~vlm_bench.types.episode.Episode` whose layout is the current one, so
the prompt's scene text (``--scene-as-text``) and the set-of-marks labels are written by the
same code as at the start. Its UAV pose is the UAV's position now with the start heading: the
moves' body frame is the start heading for the whole episode.
"""

from __future__ import annotations

import hashlib
import math

import mujoco
import numpy as np

from vlm_bench.executor.live_episode import LiveEpisode
from vlm_bench.sim.constants import part_handle_site, part_joint
from vlm_bench.sim.objects.bounds import object_bounds
from vlm_bench.sim.scene import Scene
from vlm_bench.sim.snapshot_render import render_scene
from vlm_bench.storage.png import to_png
from vlm_bench.types.episode import Episode, EpisodeObject, PartRef, UavPose


def _yaw_deg(xmat: np.ndarray) -> float:
    m = np.asarray(xmat, dtype=np.float64).reshape(3, 3)
    return round(math.degrees(math.atan2(m[1, 0], m[0, 0])), 2)


def _object_now(live: LiveEpisode, obj: EpisodeObject) -> EpisodeObject:
    data = live.loop.data
    x, y, _ = (float(v) for v in data.body(obj.id).xpos)
    lo, _ = object_bounds(live.loop.model, data, obj.id, solid_only=True)
    initial = dict(obj.initial)
    for part in live.episode.parts:
        if part.parent == obj.id and part.id in initial:
            initial[part.id] = float(data.joint(part_joint(part.id)).qpos[0])
    return obj.model_copy(
        update={
            "pos": (round(x, 4), round(y, 4), round(float(lo[2]), 4)),
            "yaw_deg": _yaw_deg(data.body(obj.id).xmat),
            "initial": initial,
        }
    )


def _part_now(live: LiveEpisode, part: PartRef) -> PartRef:
    site = live.loop.data.site(part_handle_site(part.id)).xpos
    return part.model_copy(update={"handle": tuple(round(float(v), 4) for v in site)})


def episode_now(live: LiveEpisode) -> Episode:
    """The episode as it stands now (see module doc)."""
    pos = live.loop.uav_position()
    uav = UavPose(
        pos=(round(float(pos[0]), 4), round(float(pos[1]), 4), round(float(pos[2]), 4)),
        yaw_deg=live.episode.uav_start.yaw_deg,
    )
    return live.episode.model_copy(
        update={
            "objects": tuple(_object_now(live, o) for o in live.episode.objects),
            "parts": tuple(_part_now(live, p) for p in live.episode.parts),
            "uav_start": uav,
        }
    )


def state_digest(live: LiveEpisode) -> str:
    """sha256 of the simulator's configuration now (joint positions, mocap poses): what the
    views show, so a replan's prompt hash is the same whether they were rendered or not."""
    data = live.loop.data
    digest = hashlib.sha256()
    for array in (data.qpos, data.mocap_pos, data.mocap_quat):
        digest.update(np.ascontiguousarray(array, dtype=np.float64).tobytes())
    return digest.hexdigest()


def render_now(
    live: LiveEpisode, now: Episode, views: tuple[str, ...], size: int, labels: bool
) -> dict[str, bytes]:
    """PNG bytes of ``views`` of the live scene, labels where the objects are ``now``.

    Renders a copy of the simulation's data: rendering recomputes positions in the data it
    draws, which must not reach the simulation that continues (every driver of the closed
    loop then continues from the same state, whether or not it rendered)."""
    if not views:
        return {}
    loop, scene = live.loop, live.loop.scene
    scratch = mujoco.MjData(loop.model)
    mujoco.mj_copyData(scratch, loop.model, loop.data)
    state = Scene(now, scene.spec, loop.model, scratch, loop.controller)
    return {v: to_png(img) for v, img in render_scene(state, views, size, labels).items()}
