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
* :func:`support_heights`: whether each height support shows its top and its full height in a
  view, from its top down to the floor, so a model can judge how high it stands: its top is
  seen (as :func:`support_tops` judges it) and one vertical edge of the support at the bottom
  of its stack (:mod:`vlm_bench.sim.support_edges`: from a top corner down to the floor) is
  shown whole: the camera sees the edge from the side
  (:meth:`~vlm_bench.sim.support_edges.HeightEdge.seen_from`), the top corner and the floor
  point at the middle of its column (where a table's leg stands) project inside the image, at
  least :data:`~vlm_bench.sim.support_edges.MIN_EDGE_PX` rows apart, and, not hidden behind
  other things, the column shows that support off its projected top face (its top's side,
  apron, legs) in at least :data:`MIN_HEIGHT_SHARE` of the rows between them, and its
  standing parts (:func:`standing_parts`: legs, a body) in as many of the lower half of those
  rows, so it is seen to stand on the floor.
* :func:`label_overlaps`: the set-of-marks tags (placed as
  :func:`~vlm_bench.sim.snapshot_render.label_tags` and :func:`~vlm_bench.sim.labels.tag_layout`
  place them) that cover a task object's seen pixels.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from PIL import Image, ImageDraw

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.sim.cameras import task_objects
from vlm_bench.sim.constants import DEFAULT_IMAGE_SIZE, THIRD_PERSON_CAMERAS
from vlm_bench.sim.labels import project_points, tag_layout
from vlm_bench.sim.objects.bounds import subtree_geoms
from vlm_bench.sim.render import GeomIdImage, SnapshotRenderer
from vlm_bench.sim.scene import Scene
from vlm_bench.sim.snapshot_render import box_corners, label_tags
from vlm_bench.sim.support_edges import (
    MIN_EDGE_PX,
    floor_support,
    height_edges,
    height_supports,
)
from vlm_bench.types.episode import Episode, EpisodeObject

MIN_HEIGHT_SHARE = 0.8
"""Least share of an edge's projected rows in which its column shows the support (off its top
face), and of the lower half of them in which it shows its standing parts."""
STANDING_REACH = 0.5
"""Share of a support's height: its parts whose bottom lies this low are its standing parts."""
MIN_TOP_SHARE = 0.5
"""Least share of a support's projected top face that it, or what stands on it, must show."""
MIN_TOP_PIXELS = 50
"""Least area of a support's top face in the image (px at the checked size): about the square
of the legibility bound of the smallest objects (6-7 px), so a lidar that receives a camera
module counts when its top shows whole."""


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


def _hull_mask(points: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """Pixels inside the convex hull of image ``points`` (N × 2, in front of the camera)."""
    pts = sorted({(float(u), float(v)) for u, v in points})

    def half(seq: list[tuple[float, float]]) -> list[tuple[float, float]]:
        out: list[tuple[float, float]] = []
        for p in seq:
            while (
                len(out) >= 2
                and (
                    (out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                    - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])
                )
                <= 0
            ):
                out.pop()
            out.append(p)
        return out[:-1]

    hull = half(pts) + half(pts[::-1])
    height, width = shape
    mask = Image.new("1", (width, height), 0)
    ImageDraw.Draw(mask).polygon(hull or pts, fill=1)
    return np.asarray(mask, dtype=bool)


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


def standing_parts(scene: Scene, support: EpisodeObject) -> list[int]:
    """Geom ids of ``support``'s standing parts: those that reach down into the lower
    :data:`STANDING_REACH` of its height (a table's legs, a stove's body; not a table's top
    or apron)."""
    model, data = scene.model, scene.data
    reach = support.pos[2] + STANDING_REACH * object_kind(support.kind).size[2]
    out = []
    for geom in subtree_geoms(model, support.id):
        rot = data.geom_xmat[geom].reshape(3, 3)
        centre, half = model.geom_aabb[geom][:3], model.geom_aabb[geom][3:]
        if (data.geom_xpos[geom] + rot @ centre)[2] - np.abs(rot[2]) @ half <= reach:
            out.append(geom)
    return out


def support_heights(
    scene: Scene,
    renderer: SnapshotRenderer,
    size: int = DEFAULT_IMAGE_SIZE,
    views: Sequence[str] = THIRD_PERSON_CAMERAS,
    segs: dict[str, GeomIdImage] | None = None,
) -> dict[str, dict[str, bool]]:
    """For each height support (:func:`height_supports`), whether each view shows its top and
    its full height down to the floor (module doc)."""
    model, data = scene.model, scene.data
    segs = segs or view_segmentations(scene, renderer, size, views)
    tops = support_tops(scene, renderer, size, views, segs)

    def seen(support: EpisodeObject, seg: GeomIdImage, view: str) -> bool:
        if not tops[support.id][view]:
            return False
        base = floor_support(scene.episode, support.id)
        top = project_points(model, data, view, box_corners(base)[[1, 3, 7, 5]], size, size)[0]
        sides = np.isin(seg, subtree_geoms(model, base.id)) & ~_hull_mask(top, seg.shape)
        standing = np.isin(seg, standing_parts(scene, base))
        camera = data.cam_xpos[model.camera(view).id]
        for edge in height_edges(base):
            ends = np.stack([edge.top, edge.axis[0]])
            pix, inside = project_points(model, data, view, ends, size, size)
            if not (inside.all() and edge.seen_from(camera)):
                continue
            first, last = int(pix[:, 1].min()), int(pix[:, 1].max())
            if last - first + 1 < MIN_EDGE_PX:
                continue
            hull = project_points(model, data, view, edge.column, size, size)[0]
            column = _hull_mask(hull, seg.shape)[first : last + 1]
            rows = (sides[first : last + 1] & column).any(axis=1)
            low = (standing[first : last + 1] & column).any(axis=1)[len(column) // 2 :]
            if rows.mean() >= MIN_HEIGHT_SHARE and low.mean() >= MIN_HEIGHT_SHARE:
                return True
        return False

    return _per_support(scene, segs, seen)


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
