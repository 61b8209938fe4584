"""Every task's scene builds and renders: non-blank views that differ from each other."""

from __future__ import annotations

import numpy as np
import pytest

from vlm_bench.catalog.tasks import all_tasks
from vlm_bench.episodes import get_episode
from vlm_bench.sim.constants import CAM_OVERHEAD, CAMERAS
from vlm_bench.sim.labels import project_points
from vlm_bench.sim.render import SnapshotRenderer
from vlm_bench.sim.scene import build_scene
from vlm_bench.sim.snapshot_render import render_scene

SIZE = 96


@pytest.fixture(scope="module")
def renderer() -> SnapshotRenderer:
    rend = SnapshotRenderer()
    yield rend
    rend.close()


def _check_views(views: dict[str, np.ndarray], key: str) -> None:
    assert set(views) == set(CAMERAS), key
    for name, img in views.items():
        assert img.shape == (SIZE, SIZE, 3), (key, name)
        assert img.std() > 8.0, f"{key}: {name} view is blank"
    names = list(views)
    for i, a in enumerate(names):
        for b in names[i + 1 :]:
            diff = np.abs(views[a].astype(int) - views[b].astype(int)).mean()
            assert diff > 5.0, f"{key}: {a} and {b} views look the same"


@pytest.mark.parametrize("task", all_tasks(), ids=lambda t: t.id)
def test_task_scene_builds_and_renders_seed0(task: object, renderer: SnapshotRenderer) -> None:
    scene = build_scene(get_episode(task, 0))  # type: ignore[arg-type]
    _check_views(render_scene(scene, size=SIZE, renderer=renderer), f"{scene.episode.task_id}/0")


@pytest.mark.parametrize("seed", [3, 7])
def test_sample_of_other_seeds(seed: int, renderer: SnapshotRenderer) -> None:
    for task in all_tasks()[seed::12]:
        scene = build_scene(get_episode(task, seed))
        _check_views(render_scene(scene, size=SIZE, renderer=renderer), f"{task.id}/{seed}")


def test_overhead_view_frames_plan_objects_and_uav() -> None:
    """The third-person overhead camera sees every object the plan touches and the UAV."""
    for task in all_tasks()[::5]:
        ep = get_episode(task, 1)
        scene = build_scene(ep)
        referenced = {s.object for s in ep.arm_steps()}
        pts = [o.pos for o in ep.objects if o.id in referenced]
        pts += [p.handle for p in ep.parts if p.id in referenced]
        pts.append(ep.uav_start.pos)
        _, visible = project_points(scene.model, scene.data, CAM_OVERHEAD, np.array(pts), 224, 224)
        assert visible.all(), task.id
