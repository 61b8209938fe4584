"""Episode = task × seed: layout, UAV start, lighting, GT plan (docs/design.md#episodes).

Seed 0 is the canonical layout (objects exactly as in the task file); other seeds jitter movable
objects and draw each table's height. Every seed places the UAV start at a different
bearing/heading/distance so that at least one UAV move is needed; the first move's body-frame
sector and the first segment's vertical move are drawn as :mod:`vlm_bench.episodes.start` says,
so that the stated start altitude tells nothing about them. Sampling is deterministic in
(task id, seed).
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Iterator

import numpy as np

from vlm_bench.catalog.tasks import get_task
from vlm_bench.catalog.world_catalog import environment, object_kind
from vlm_bench.episodes.gt_builder import AmbiguousGeometry, GroundTruthBuilder
from vlm_bench.episodes.layout import part_refs, place_objects, support_kinds
from vlm_bench.episodes.plane_geometry import point_rect_distance, rect_corners
from vlm_bench.episodes.start import (
    first_sector,
    first_table_kind,
    start_altitude,
    start_sides,
)
from vlm_bench.errors import ConfigError, EpisodeGenerationError
from vlm_bench.rules import wrap_deg
from vlm_bench.sim.cameras import third_person_views
from vlm_bench.sim.height_views import camera_poses, shown_views
from vlm_bench.sim.legible_views import legible_views
from vlm_bench.sim.view_sizes import (
    frame_problem,
    hidden_from_above,
    legibility_score,
    object_pixel_sizes,
)
from vlm_bench.types.episode import Episode, EpisodeObject, Lighting, PartRef, UavPose
from vlm_bench.types.geometry import APPROACH
from vlm_bench.types.plan import ArmStep, UavStep
from vlm_bench.types.task import TaskSpec

MAX_ATTEMPTS = 500
LEGIBLE_TRIES = 40  # valid layouts drawn for a legible one before the most legible is kept
START_DISTANCE = (0.95, 1.6)  # m, horizontal distance to the first ARM object
CANONICAL_DISTANCE = (1.3, 2.0)  # m: the same for seed 0
BEARING_SPREAD = 12.0  # deg around the sector centre (boundaries are 22.5 deg away)
FRONT_CONE = 35.0  # deg, start cone for parts approached from the front (drawers)
WALL_CLEARANCE = 0.8  # m
TALL_CLEARANCE = 0.6  # m from fixtures taller than the stowed arm's lowest point
OBSERVE_DEPTH = 0.85  # m: the arm's start (observe) posture hangs this far below the UAV...
OBSERVE_CLEARANCE = 0.40  # m: ...within 0.28 m of it: a table top under it would be in contact
OBSERVE_GAP = 0.05  # m: least gap from the hanging arm down to anything under it


def _rng(task_id: str, seed: int, attempt: int) -> np.random.Generator:
    return np.random.default_rng([zlib.crc32(task_id.encode()), seed, attempt])


def _support_rng(task_id: str, seed: int, attempt: int) -> np.random.Generator:
    """Draws the tables' heights apart from the layout's jitter (same jitter, any heights)."""
    return np.random.default_rng([zlib.crc32(task_id.encode()), seed, attempt, 7_919])


def _lighting(task_id: str, seed: int) -> Lighting:
    if seed == 0:
        return Lighting(azimuth_deg=0.0, intensity=1.0)
    rng = np.random.default_rng([zlib.crc32(task_id.encode()), seed, 999_983])
    return Lighting(
        azimuth_deg=round(float(rng.uniform(-40, 40)), 2),
        intensity=round(float(rng.uniform(0.85, 1.15)), 3),
    )


def _sample_start(
    task: TaskSpec,
    seed: int,
    rng: np.random.Generator,
    target: np.ndarray,
    front: tuple[float, float] | None,
) -> UavPose:
    sector = first_sector(task.id, seed)
    body_bearing = 45.0 * sector + float(rng.uniform(-BEARING_SPREAD, BEARING_SPREAD))
    if front is not None:
        # World direction from UAV to target points against the part's front normal.
        normal = math.degrees(math.atan2(front[1], front[0]))
        world_bearing = normal + 180.0 + float(rng.uniform(-FRONT_CONE, FRONT_CONE))
    else:
        world_bearing = float(rng.uniform(-180.0, 180.0))
    yaw = wrap_deg(world_bearing - body_bearing)
    dist = float(rng.uniform(*(CANONICAL_DISTANCE if seed == 0 else START_DISTANCE)))
    x = target[0] - dist * math.cos(math.radians(world_bearing))
    y = target[1] - dist * math.sin(math.radians(world_bearing))
    return UavPose(pos=(round(x, 4), round(y, 4), 0.0), yaw_deg=round(yaw, 3))


def _check_start(task: TaskSpec, start: UavPose, objects: list) -> None:  # type: ignore[type-arg]
    half = environment(task.environment).room_half_size - WALL_CLEARANCE
    if max(abs(start.pos[0]), abs(start.pos[1])) > half:
        raise AmbiguousGeometry("UAV start is too close to the arena edge")
    for obj in objects:
        kind = object_kind(obj.kind)
        top = obj.pos[2] + kind.size[2]
        if top < start.pos[2] - OBSERVE_DEPTH - OBSERVE_GAP:
            continue
        corners = rect_corners(obj.pos, kind.size[:2], obj.yaw_deg)
        dist = point_rect_distance(start.pos, corners)
        if dist < OBSERVE_CLEARANCE or (top > start.pos[2] - 0.5 and dist < TALL_CLEARANCE):
            raise AmbiguousGeometry(f"UAV start is too close to {obj.id}")


def make_episode(task: TaskSpec | str, seed: int) -> Episode:
    """Materialise one episode; deterministic in (task id, seed).

    Layouts are drawn until one is legible in the standard framing (seeds 1-9; up to
    :data:`LEGIBLE_TRIES`, then the most legible is kept; seed 0 keeps its first). A kept
    episode still under the bound in the views it is shown with (the close-up,
    :mod:`vlm_bench.sim.legible_views`) is redrawn further, judged in those views: the next
    :data:`LEGIBLE_TRIES` layouts, the first legible one or else the most legible kept. The
    sizes it records are those of the views it is shown with
    (:func:`~vlm_bench.sim.height_views.shown_views`), which keep its legibility, and it
    records those views' cameras (``Episode.cameras``), which the scene builder then reads.
    """
    if isinstance(task, str):
        task = get_task(task)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ConfigError(f"seed must be a non-negative integer, got {seed!r}")
    reasons: dict[str, int] = {}
    best: tuple[float, Episode] | None = None  # the most legible episode short of the sizes
    for side in start_sides(task, seed):  # the drawn side; another where geometry rules it out
        candidates = _candidates(task, seed, side, reasons)
        for tries, (score, episode) in enumerate(candidates, start=1):
            if best is None or score > best[0]:
                best = (score, episode)
            if score >= 1.0 or seed == 0 or tries >= LEGIBLE_TRIES:
                break
        if best is not None:
            break
    if best is None:
        top = sorted(reasons.items(), key=lambda kv: -kv[1])[:3]
        raise EpisodeGenerationError(
            f"task {task.id!r} seed {seed}: no valid layout in {MAX_ATTEMPTS} attempts "
            f"(most common: {top})"
        )
    shown = _shown(*best)
    for tries, candidate in enumerate(candidates, start=1):
        if shown[0] >= 1.0 or tries > LEGIBLE_TRIES:
            break
        score, episode = _shown(*candidate)
        if score > shown[0]:
            shown = (score, episode)
    kept = shown[1]
    views = shown_views(kept)
    return kept.model_copy(
        update={
            "object_px": object_pixel_sizes(kept, views=views),
            "cameras": camera_poses(views),
        }
    )


def _candidates(
    task: TaskSpec, seed: int, side: int, reasons: dict[str, int]
) -> Iterator[tuple[float, Episode]]:
    """Valid episodes in attempt order, each with its sizes in the standard framing and its
    legibility there (the reasons attempts fail are counted into ``reasons``). Seed 0 keeps
    the canonical objects and draws only the UAV start."""
    for attempt in range(MAX_ATTEMPTS):
        rng = _rng(task.id, seed, attempt)
        try:
            kinds = support_kinds(task, None if seed == 0 else _support_rng(task.id, seed, attempt))
            first = first_table_kind(task, side)  # its height decides the first up/down
            if first is not None:
                kinds[first[0]] = first[1]
            objects = place_objects(task, None if seed == 0 else rng, kinds)
            parts = part_refs(objects)
            builder = GroundTruthBuilder(objects, parts)
            target, front = builder.first_reference(task.arm_steps)
            level = _sample_start(task, seed, rng, target, front)
        except (AmbiguousGeometry, ValueError) as exc:
            _count(reasons, exc)
            continue
        working = APPROACH.operating_altitude(float(target[2]))
        z = start_altitude(task, seed, attempt, working, side)
        start = UavPose(pos=(level.pos[0], level.pos[1], z), yaw_deg=level.yaw_deg)
        try:
            _check_start(task, start, objects)
            plan, poses = builder.build(start, task.arm_steps)
            episode = _episode(task, seed, objects, parts, start, plan, poses)
            views = third_person_views(episode)
            problem = frame_problem(episode, views)
            if problem is not None:
                raise AmbiguousGeometry(problem)
        except ValueError as exc:
            _count(reasons, exc)
            continue
        sizes = object_pixel_sizes(episode, views=views)
        score = legibility_score(episode, sizes, hidden_from_above(episode, views))
        yield score, episode.model_copy(update={"object_px": sizes})


def _shown(score: float, episode: Episode) -> tuple[float, Episode]:
    """``episode`` (legibility ``score`` in the standard framing) with the sizes of the views
    it is shown with (the close-up where the standard framing leaves a task object under the
    bound), and its legibility there."""
    if score >= 1.0:
        return score, episode
    views = legible_views(episode)
    sizes = object_pixel_sizes(episode, views=views)
    score = legibility_score(episode, sizes, hidden_from_above(episode, views))
    return score, episode.model_copy(update={"object_px": sizes})


def _count(reasons: dict[str, int], exc: ValueError) -> None:
    key = str(exc).split(" ")[0] if not isinstance(exc, AmbiguousGeometry) else str(exc)
    reasons[key] = reasons.get(key, 0) + 1


def _episode(
    task: TaskSpec,
    seed: int,
    objects: list[EpisodeObject],
    parts: list[PartRef],
    start: UavPose,
    plan: list[UavStep | ArmStep],
    poses: list[UavPose],
) -> Episode:
    return Episode(
        task_id=task.id,
        seed=seed,
        suite=task.suite,
        environment=task.environment,
        instructions=task.instructions,
        objects=tuple(objects),
        parts=tuple(parts),
        uav_start=start,
        lighting=_lighting(task.id, seed),
        gt_plan=tuple(plan),
        gt_uav_poses=tuple(poses),
        goals=task.goals,
    )
