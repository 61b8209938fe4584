"""Rendered checks of what the third-person views let a model read: table heights and labels.

All three work on segmentation renders
(:meth:`~vlm_bench.sim.render.SnapshotRenderer.render_segmentation`) of the scene's
``overhead`` and ``side`` cameras, as the model is shown them:

* :func:`support_tops`: whether each *height support* (a support under a task object, or one
  a place step puts an object on) shows its top in a view: a corner of its box's top face
  projects inside the image, so the view shows where the surface ends and its edge drops, and
  at least :data:`MIN_TOP_SHARE` of the top face's pixels in the image (at
  least :data:`MIN_TOP_PIXELS` of them) show the support or what stands on it, not something
  in front of it. A table is wider than the tight framing of the work area, so its far corners
  may lie out of frame.
* :func:`support_visibility`: whether each height support shows its top and its full height in
  a view: all eight corners of its box project inside the image, and its seen pixels span at
  least :data:`MIN_HEIGHT_SHARE` of the rows its box spans there (not hidden behind other
  things).
* :func:`label_overlaps`: the set-of-marks tags (placed as
  :func:`~vlm_bench.sim.snapshot_render.label_tags` and :func:`~vlm_bench.sim.labels.tag_layout`
  place them) that cover a task object's seen pixels.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from PIL import Image, ImageDraw

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.sim.cameras import plan_references, task_objects
from vlm_bench.sim.constants import DEFAULT_IMAGE_SIZE, THIRD_PERSON_CAMERAS
from vlm_bench.sim.labels import project_points, tag_layout
from vlm_bench.sim.objects.bounds import subtree_geoms
from vlm_bench.sim.render import GeomIdImage, SnapshotRenderer
from vlm_bench.sim.scene import Scene
from vlm_bench.sim.snapshot_render import box_corners, label_tags
from vlm_bench.types.episode import Episode, EpisodeObject

MIN_HEIGHT_SHARE = 0.8
"""Least share of a support's projected rows that its seen pixels must span."""
MIN_TOP_SHARE = 0.5
"""Least share of a support's projected top face that it, or what stands on it, must show."""
MIN_TOP_PIXELS = 50
"""Least area of a support's top face in the image (px at the checked size): about the square
of the legibility bound of the smallest objects (6-7 px), so a lidar that receives a camera
module counts when its top shows whole."""


def height_supports(episode: Episode) -> tuple[str, ...]:
    """Ids of the supports whose height a plan's vertical moves depend on: every support under
    a task object (down to the floor) and every support the plan names (a place destination)."""
    by_id = {o.id: o for o in episode.objects}
    wanted: list[str] = []
    referenced = plan_references(episode)
    for oid in task_objects(episode):
        on = by_id[oid].on
        while on in by_id:
            if on not in wanted and object_kind(by_id[on].kind).support:
                wanted.append(on)
            on = by_id[on].on
    for oid in referenced:
        if oid in by_id and oid not in wanted and object_kind(by_id[oid].kind).support:
            wanted.append(oid)
    return tuple(o.id for o in episode.objects if o.id in wanted)


def view_segmentations(
    scene: Scene,
    renderer: SnapshotRenderer,
    size: int = DEFAULT_IMAGE_SIZE,
    views: Sequence[str] = THIRD_PERSON_CAMERAS,
) -> dict[str, GeomIdImage]:
    """The segmentation render of each of ``views``, for the checks below to share."""
    return {
        view: renderer.render_segmentation(scene.model, scene.data, view, size) for view in views
    }


def _standing_on(episode: Episode, support: str) -> list[str]:
    """``support`` and every object resting on it, directly or on something that does."""
    out = [support]
    for obj in episode.objects:  # scene order: a thing comes after what it stands on
        if obj.on in out:
            out.append(obj.id)
    return out


def _top_seen(seg: GeomIdImage, quad: np.ndarray, corners_in: np.ndarray, geoms: list[int]) -> bool:
    """Whether the projected top face ``quad`` (4 × 2, round the face) is seen (module doc)."""
    if not corners_in.any():
        return False
    height, width = seg.shape
    mask = Image.new("1", (width, height), 0)
    ImageDraw.Draw(mask).polygon([(float(u), float(v)) for u, v in quad], fill=1)
    inside = np.asarray(mask, dtype=bool)
    total = int(inside.sum())
    shown = int(np.isin(seg[inside], geoms).sum())
    return total >= MIN_TOP_PIXELS and shown >= MIN_TOP_SHARE * total


def _per_support(
    scene: Scene,
    segs: dict[str, GeomIdImage],
    seen: Callable[[EpisodeObject, GeomIdImage, str], bool],
) -> dict[str, dict[str, bool]]:
    """``seen(support, segmentation, view)`` for each height support and view of ``segs``."""
    by_id = {o.id: o for o in scene.episode.objects}
    return {
        sid: {view: seen(by_id[sid], seg, view) for view, seg in segs.items()}
        for sid in height_supports(scene.episode)
    }


def support_tops(
    scene: Scene,
    renderer: SnapshotRenderer,
    size: int = DEFAULT_IMAGE_SIZE,
    views: Sequence[str] = THIRD_PERSON_CAMERAS,
    segs: dict[str, GeomIdImage] | None = None,
) -> dict[str, dict[str, bool]]:
    """For each height support (:func:`height_supports`), whether each view shows its top
    (module doc)."""

    def seen(support: EpisodeObject, seg: GeomIdImage, view: str) -> bool:
        on = _standing_on(scene.episode, support.id)
        geoms = [g for oid in on for g in subtree_geoms(scene.model, oid)]
        top = box_corners(support)[[1, 3, 7, 5]]  # the z = top corners, round the face
        pix, inside = project_points(scene.model, scene.data, view, top, size, size)
        return _top_seen(seg, pix, inside, geoms)

    return _per_support(scene, segs or view_segmentations(scene, renderer, size, views), seen)


def support_visibility(
    scene: Scene,
    renderer: SnapshotRenderer,
    size: int = DEFAULT_IMAGE_SIZE,
    views: Sequence[str] = THIRD_PERSON_CAMERAS,
    segs: dict[str, GeomIdImage] | None = None,
) -> dict[str, dict[str, bool]]:
    """For each height support (:func:`height_supports`), whether each view shows its top and
    full height (module doc)."""

    def seen(support: EpisodeObject, seg: GeomIdImage, view: str) -> bool:
        geoms = subtree_geoms(scene.model, support.id)
        corners = box_corners(support)
        pix, inside = project_points(scene.model, scene.data, view, corners, size, size)
        rows = np.nonzero(np.isin(seg, geoms).any(axis=1))[0]
        span = float(pix[:, 1].max() - pix[:, 1].min()) if inside.all() else 0.0
        shown = float(rows.max() - rows.min() + 1) if rows.size else 0.0
        return bool(inside.all() and shown >= MIN_HEIGHT_SHARE * span)

    return _per_support(scene, segs or view_segmentations(scene, renderer, size, views), seen)


def label_overlaps(
    scene: Scene,
    renderer: SnapshotRenderer,
    size: int = DEFAULT_IMAGE_SIZE,
    views: Sequence[str] = THIRD_PERSON_CAMERAS,
    segs: dict[str, GeomIdImage] | None = None,
) -> list[tuple[str, str, str, int]]:
    """``(view, tag text, task object, pixels)`` for every tag that covers seen pixels of a
    task object (empty when no tag does)."""
    segs = segs or view_segmentations(scene, renderer, size, views)
    objects = {oid: subtree_geoms(scene.model, oid) for oid in task_objects(scene.episode)}
    out = []
    for view in views:
        tags, avoid = label_tags(scene, view, size)
        for text, _, box in tag_layout((size, size), tags, avoid):
            u0, v0 = max(0, int(box[0])), max(0, int(box[1]))
            u1, v1 = min(size, int(np.ceil(box[2])) + 1), min(size, int(np.ceil(box[3])) + 1)
            patch = segs[view][v0:v1, u0:u1]
            for oid, geoms in objects.items():
                covered = int(np.isin(patch, geoms).sum())
                if covered:
                    out.append((view, text, oid, covered))
    return out
