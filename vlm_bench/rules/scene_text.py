"""The scene as text: what a perfect perceiver reads off the images, in the UAV's body frame.

Each object and part is one line giving its working point (an object's centre, a part's handle)
as metres right / forward / up of the UAV's centre at the start, its height above the floor,
and what the rules need besides: an object's height and where things placed on or in it rest;
a drawer's opening, the way it pulls out and its stand-off. :func:`format_scene` writes the
lines (``--scene-as-text``) and :func:`parse_scene` reads them back (the ``rules`` planner and
the few-shot examples), so the text is the only channel between the scene and a planner.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Literal

from pydantic import Field

from vlm_bench.catalog.world_catalog import object_kind
from vlm_bench.rules.frame import rotate_xy
from vlm_bench.rules.work import (
    DRAWER_FLOOR_BELOW_HANDLE,
    DRAWER_INSIDE_BEHIND_HANDLE,
    rest_height,
)
from vlm_bench.types.base import Frozen
from vlm_bench.types.episode import Episode

Body3 = tuple[float, float, float]
"""(right, forward, up) in metres from the UAV's centre."""


class SceneEntry(Frozen):
    """One object or part of a scene, in the UAV's body frame at the start."""

    id: str = Field(description="Object or part id.")
    kind: Literal["object", "drawer", "knob"] = Field(description="What the line describes.")
    point: Body3 = Field(description="Working point: an object's centre, a part's handle.")
    floor_height: float = Field(description="Height of the working point above the floor (m).")
    tall: float | None = Field(default=None, description="An object's height (m).")
    rest: Body3 | None = Field(
        default=None, description="Where the bottom of an object placed on or in it rests."
    )
    owner: str | None = Field(default=None, description="A part's object.")
    opening: float | None = Field(default=None, description="How far a drawer is open (m).")
    pull: tuple[float, float] | None = Field(
        default=None, description="Unit (right, forward) direction a drawer pulls out."
    )
    standoff: float | None = Field(default=None, description="Stand-off if not the default (m).")


def _body(uav_pos: Sequence[float], yaw_deg: float, p: Sequence[float]) -> Body3:
    fx, fy = rotate_xy(p[0] - uav_pos[0], p[1] - uav_pos[1], -yaw_deg)
    return round(-fy, 2), round(fx, 2), round(p[2] - uav_pos[2], 2)


def scene_entries(episode: Episode) -> list[SceneEntry]:
    """Every object and part of ``episode`` at its start, in scene order."""
    uav, yaw = episode.uav_start.pos, episode.uav_start.yaw_deg
    out: list[SceneEntry] = []
    for obj in episode.objects:
        kind = object_kind(obj.kind)
        tall = kind.size[2]
        x, y, z = obj.pos
        rest = rest_height(z, tall, container=kind.container, support=kind.support)
        out.append(
            SceneEntry(
                id=obj.id,
                kind="object",
                point=_body(uav, yaw, (x, y, z + tall / 2)),
                floor_height=round(z + tall / 2, 2),
                tall=round(tall, 2),
                rest=_body(uav, yaw, (x, y, rest)),
            )
        )
    owners = {o.id: o for o in episode.objects}
    for part in episode.parts:
        owner = owners[part.parent]
        spec = next(p for p in object_kind(owner.kind).parts if p.name == part.id)
        hx, hy, hz = part.handle
        entry = SceneEntry(
            id=part.id,
            kind="drawer" if part.kind == "drawer" else "knob",
            point=_body(uav, yaw, part.handle),
            floor_height=round(hz, 2),
            owner=owner.id,
            standoff=spec.standoff,
        )
        if part.kind == "drawer":
            bx, by = rotate_xy(-DRAWER_INSIDE_BEHIND_HANDLE, 0.0, owner.yaw_deg)
            fx, fy = rotate_xy(1.0, 0.0, owner.yaw_deg - yaw)
            entry = entry.model_copy(
                update={
                    "rest": _body(uav, yaw, (hx + bx, hy + by, hz - DRAWER_FLOOR_BELOW_HANDLE)),
                    "opening": round(owner.initial.get(part.id, 0.0), 2),
                    "pull": (round(-fy, 3), round(fx, 3)),
                }
            )
        out.append(entry)
    return out


def _vec(v: Body3) -> str:
    return f"(right {v[0]:.2f}, forward {v[1]:.2f}, up {v[2]:.2f})"


def format_entry(e: SceneEntry) -> str:
    """One line of the scene text."""
    what = "centre" if e.kind == "object" else "handle"
    head = e.id if e.owner is None else f"{e.id} ({e.kind} of {e.owner})"
    text = f"- {head}: {what} {_vec(e.point)}, {e.floor_height:.2f} m above the floor"
    if e.tall is not None:
        text += f"; {e.tall:.2f} m tall"
    if e.opening is not None and e.pull is not None:
        text += (
            f"; open {e.opening:.2f} m, pulls out towards "
            f"(right {e.pull[0]:.3f}, forward {e.pull[1]:.3f})"
        )
    if e.rest is not None:
        if e.kind == "object":
            text += f"; objects placed on or in it rest at up {e.rest[2]:.2f}"
        else:
            text += f"; objects placed in it rest at {_vec(e.rest)}"
    if e.standoff is not None:
        text += f"; stand-off {e.standoff:.2f} m"
    return text


def format_scene(entries: Sequence[SceneEntry], uav_height: float) -> str:
    """The scene text: the UAV's height, then one line per entry."""
    head = (
        "The UAV's centre: (right 0.00, forward 0.00, up 0.00), "
        f"{uav_height:.2f} m above the floor."
    )
    return "\n".join([head, *(format_entry(e) for e in entries)])


_NUM = r"(-?\d+(?:\.\d+)?)"
_VEC = rf"\(right {_NUM}, forward {_NUM}, up {_NUM}\)"
_LINE = re.compile(
    rf"^- (?P<id>[a-z0-9_]+)(?: \((?P<kind>drawer|knob) of (?P<owner>[a-z0-9_]+)\))?: "
    rf"(?:centre|handle) {_VEC}, {_NUM} m above the floor"
    rf"(?:; {_NUM} m tall)?"
    rf"(?:; open {_NUM} m, pulls out towards \(right {_NUM}, forward {_NUM}\))?"
    rf"(?:; objects placed on or in it rest at up {_NUM})?"
    rf"(?:; objects placed in it rest at {_VEC})?"
    rf"(?:; stand-off {_NUM} m)?$"
)


def parse_scene(text: str) -> list[SceneEntry]:
    """Read back the entries of every scene line in ``text`` (other lines are ignored)."""
    out: list[SceneEntry] = []
    for line in text.splitlines():
        m = _LINE.match(line.strip())
        if m is None:
            continue
        g = [None if v is None else float(v) for v in m.groups()[3:]]
        point = (g[0], g[1], g[2])
        entry = SceneEntry.model_validate(
            {
                "id": m["id"],
                "kind": m["kind"] or "object",
                "owner": m["owner"],
                "point": point,
                "floor_height": g[3],
                "tall": g[4],
                "opening": g[5],
                "pull": None if g[6] is None else (g[6], g[7]),
                "rest": (point[0], point[1], g[8])
                if g[8] is not None
                else (None if g[9] is None else (g[9], g[10], g[11])),
                "standoff": g[12],
            }
        )
        out.append(entry)
    return out
