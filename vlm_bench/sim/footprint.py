"""Pixel footprints: how large a body or the heading arrow appears in a segmentation render.

Measures work on geom-id images from
:meth:`~vlm_bench.sim.render.SnapshotRenderer.render_segmentation`, so they count only the pixels
where a thing is actually seen (occlusion included). :func:`measure_legibility` measures an
episode's third-person views at its start and :func:`legibility_failures` judges them.

Legibility criterion, at :data:`~vlm_bench.sim.constants.DEFAULT_IMAGE_SIZE` px (the rendered
check of :mod:`vlm_bench.sim.view_sizes`, which the episode generator applies from geometry):
the heading arrow is at least :data:`MIN_ARROW_PX` long in each third-person view; each task
object (:func:`~vlm_bench.sim.cameras.task_objects`) shows in each view (with the robot hidden),
a movable one wholly (its pixels keep off the image's border; a fixture is framed by the parts
the plan names), and it is at least :func:`~vlm_bench.sim.view_sizes.min_pixels` across (the
shorter side of its pixel bounding box, as rendered) in one of the views.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.sim import constants as c
from vlm_bench.sim.cameras import task_objects
from vlm_bench.sim.labels import project_points
from vlm_bench.sim.objects.bounds import subtree_geoms
from vlm_bench.sim.render import GeomIdImage, SnapshotRenderer
from vlm_bench.sim.scene import Scene
from vlm_bench.sim.view_sizes import min_pixels

Mask = NDArray[np.bool_]
IntArray = NDArray[np.int64]


def named_geoms(model: mujoco.MjModel, names: tuple[str, ...]) -> IntArray:
    """Ids of the named geoms."""
    return np.array([model.geom(name).id for name in names], dtype=np.int64)


def pixel_mask(seg: GeomIdImage, geoms: Sequence[int] | IntArray) -> Mask:
    """Pixels that show one of ``geoms``."""
    mask: Mask = np.isin(seg, geoms)
    return mask


def box_min_side(mask: Mask) -> int:
    """Shorter side (px) of the bounding box of a mask's pixels; 0 for an empty mask."""
    rows, cols = np.nonzero(mask)
    if rows.size == 0:
        return 0
    return int(min(rows.max() - rows.min(), cols.max() - cols.min()) + 1)


def box_max_side(mask: Mask) -> int:
    """Longer side (px) of the bounding box of a mask's pixels; 0 for an empty mask."""
    rows, cols = np.nonzero(mask)
    if rows.size == 0:
        return 0
    return int(max(rows.max() - rows.min(), cols.max() - cols.min()) + 1)


def touches_border(mask: Mask) -> bool:
    """Whether a mask has pixels in the image's outermost rows or columns."""
    return bool(mask[0].any() or mask[-1].any() or mask[:, 0].any() or mask[:, -1].any())


def extent_along(mask: Mask, direction: NDArray[np.float64]) -> float:
    """Length (px) of a mask's pixels along an image direction ``(du, dv)``: the spread of the
    pixel centres projected on it, plus one pixel; 0 for an empty mask."""
    rows, cols = np.nonzero(mask)
    if rows.size == 0:
        return 0.0
    unit = direction / np.linalg.norm(direction)
    along = (cols + 0.5) * unit[0] + (rows + 0.5) * unit[1]
    return float(along.max() - along.min() + 1.0)


def heading_arrow_axis(
    model: mujoco.MjModel, data: mujoco.MjData, camera: str, size: int
) -> NDArray[np.float64]:
    """Image direction ``(du, dv)`` from the heading arrow's tail to its tip, at its current pose
    (px; may be near zero when the arrow points at the camera)."""
    uav = model.body(c.UAV_BODY).id
    rot = data.xmat[uav].reshape(3, 3)
    ends = np.array(
        [[c.UAV_HEADING_TAIL_X, 0.0, c.UAV_HEADING_Z], [c.UAV_HEADING_TIP_X, 0.0, c.UAV_HEADING_Z]]
    )
    world = data.xpos[uav] + ends @ rot.T
    uv, _ = project_points(model, data, camera, world, size, size)
    axis: NDArray[np.float64] = uv[1] - uv[0]
    return axis


def heading_arrow_length(
    model: mujoco.MjModel, data: mujoco.MjData, seg: GeomIdImage, camera: str
) -> float:
    """Seen length (px) of the heading arrow in ``seg`` (rendered from ``camera``): the extent of
    its pixels along its projected tail-to-tip axis, or the diagonal of their bounding box when
    the axis is shorter than a pixel (the arrow points at the camera)."""
    mask = pixel_mask(seg, named_geoms(model, c.UAV_HEADING_GEOMS))
    axis = heading_arrow_axis(model, data, camera, seg.shape[0])
    if np.linalg.norm(axis) >= 1.0:
        return extent_along(mask, axis)
    rows, cols = np.nonzero(mask)
    if rows.size == 0:
        return 0.0
    return float(np.hypot(rows.max() - rows.min() + 1, cols.max() - cols.min() + 1))


MIN_ARROW_PX = 12  # least seen length of the heading arrow in a third-person view at 448²
_HIDDEN_GROUP = 5  # a geom group the renderer does not draw (MjvOption shows groups 0-2)


@dataclass(frozen=True)
class ObjectFootprint:
    """How large one object appears in one view (px)."""

    seen: int  # shorter side of its pixel bounding box as rendered
    clear: int  # the same with the robot (UAV and arm) hidden
    covered: bool  # the robot hides some of its pixels
    long: int  # longer side of its pixel bounding box as rendered
    edge: bool = False  # with the robot hidden, its pixels touch the image's border


@dataclass(frozen=True)
class Legibility:
    """An episode's third-person views at its start, measured."""

    task: str
    seed: int
    size: int
    arrow: dict[str, float]  # view -> seen length of the heading arrow (px)
    objects: dict[str, dict[str, ObjectFootprint]]  # object -> view -> footprint
    need: dict[str, int]  # object -> least size (px) in its better view
    whole: tuple[str, ...] = ()  # objects that must lie wholly inside every view (movable ones)

    def to_json(self) -> dict[str, object]:
        """A JSON-able dict of the measures and the failures."""
        row = asdict(self)
        row["failures"] = legibility_failures(self)
        return row


def measure_legibility(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    renderer: SnapshotRenderer,
    task: str,
    seed: int,
    objects: Sequence[str],
    views: Sequence[str] = c.THIRD_PERSON_CAMERAS,
    size: int = c.DEFAULT_IMAGE_SIZE,
    need: dict[str, int] | None = None,
    whole: tuple[str, ...] = (),
) -> Legibility:
    """Measure the heading arrow and ``objects`` (body names) in ``views``, as rendered and with
    the robot hidden (its geoms moved to a group the renderer skips; restored after).
    ``need``: least size of each object in its better view (default 1 px); ``whole``: the
    objects that must keep off the image's border."""
    robot = subtree_geoms(model, c.UAV_BODY)
    bodies = {name: subtree_geoms(model, name) for name in objects}
    seen = {view: renderer.render_segmentation(model, data, view, size) for view in views}
    groups = model.geom_group[robot].copy()
    try:
        model.geom_group[robot] = _HIDDEN_GROUP
        clear = {view: renderer.render_segmentation(model, data, view, size) for view in views}
    finally:
        model.geom_group[robot] = groups
    footprints: dict[str, dict[str, ObjectFootprint]] = {}
    for name, geoms in bodies.items():
        footprints[name] = {}
        for view in views:
            mask, bare = pixel_mask(seen[view], geoms), pixel_mask(clear[view], geoms)
            footprints[name][view] = ObjectFootprint(
                seen=box_min_side(mask),
                clear=box_min_side(bare),
                covered=bool((bare & ~mask).any()),
                long=box_max_side(mask),
                edge=touches_border(bare),
            )
    arrow = {view: round(heading_arrow_length(model, data, seen[view], view), 2) for view in views}
    return Legibility(
        task=task,
        seed=seed,
        size=size,
        arrow=arrow,
        objects=footprints,
        need=need if need is not None else dict.fromkeys(objects, 1),
        whole=whole,
    )


def measure_scene_legibility(
    scene: Scene, renderer: SnapshotRenderer, size: int = c.DEFAULT_IMAGE_SIZE
) -> Legibility:
    """:func:`measure_legibility` of a built scene at its current state, over its episode's task
    objects in both third-person views, each held to its kind's least size."""
    ep = scene.episode
    kinds = {o.id: o.kind for o in ep.objects}
    names = task_objects(ep)
    return measure_legibility(
        scene.model,
        scene.data,
        renderer,
        ep.task_id,
        ep.seed,
        names,
        size=size,
        need={name: min_pixels(kinds[name]) for name in names},
        whole=tuple(name for name in names if object_kind(kinds[name]).movable),
    )


def legibility_failures(measured: Legibility, min_arrow: float = MIN_ARROW_PX) -> list[str]:
    """What breaks the legibility criterion (module docstring), one line each; empty if none."""
    out = [f"arrow {view} {px:g}px" for view, px in measured.arrow.items() if px < min_arrow]
    for name, prints in measured.objects.items():
        for view, fp in prints.items():
            if fp.clear == 0:
                out.append(f"{name} is not in the {view} view")
            elif fp.edge and name in measured.whole:
                out.append(f"{name} is cut off by the {view} view's border")
        best = max((fp.seen for fp in prints.values()), default=0)
        if best < measured.need.get(name, 1):
            out.append(f"{name} {best}px, needs {measured.need[name]}px")
    return out
