"""MuJoCo world: the aerial manipulator, objects, environments, scenes and rendering.

Importing this package sets ``MUJOCO_GL=egl`` when unset, so rendering works headless.
"""

import os

os.environ.setdefault("MUJOCO_GL", "egl")
