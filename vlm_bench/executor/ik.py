"""Damped-least-squares IK of the arm's TCP, on a scratch copy of the state.

Only the 7 arm joints move (the floating base and the objects stay as they are). A top-down
target fixes the TCP's z axis to world −z and its x axis to a horizontal heading. The hanging
arm reaches down with an "elbow-up" posture, so solutions are seeded from a known top-down pose
(joint 2 near its lower limit) and pulled towards it in the Jacobian's null space.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
from numpy.typing import NDArray

from vlm_bench.sim import constants as c

Vec = NDArray[np.float64]
TOP_DOWN_SEED = (-1.5, -1.76, 1.6, -2.54, -1.44, 1.71, 2.8)  # a known top-down grasp posture
POS_TOL = 0.004  # m
ROT_TOL = 0.03  # rad


class ArmIk:
    """IK solver for one scene's arm (keeps its own ``MjData`` as scratch space)."""

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self.scratch = mujoco.MjData(model)
        self.qadr = np.array([model.joint(j).qposadr[0] for j in c.ARM_JOINTS])
        self.dofs = np.array([model.joint(j).dofadr[0] for j in c.ARM_JOINTS])
        self.lo = np.array([model.joint(j).range[0] for j in c.ARM_JOINTS]) + 0.01
        self.hi = np.array([model.joint(j).range[1] for j in c.ARM_JOINTS]) - 0.01
        self.site = int(model.site(c.TCP_SITE).id)

    def solve(
        self,
        data: mujoco.MjData,
        pos: Vec,
        heading_rad: float,
        seed: Vec,
        iterations: int = 300,
        damping: float = 0.05,
    ) -> tuple[Vec, float]:
        """Joint angles putting the TCP at ``pos`` pointing down, x axis along ``heading_rad``.

        Returns the solution and its residual (position error in m plus rotation error in rad);
        the caller decides whether it is good enough.
        """
        s = self.scratch
        s.qpos[:] = data.qpos
        q = np.clip(np.asarray(seed, dtype=np.float64), self.lo, self.hi)
        ch, sh = math.cos(heading_rad), math.sin(heading_rad)
        target_rot = np.array([[ch, sh, 0.0], [sh, -ch, 0.0], [0.0, 0.0, -1.0]])
        jacp = np.zeros((3, self.model.nv))
        jacr = np.zeros((3, self.model.nv))
        anchor = q.copy()
        residual = math.inf
        for _ in range(iterations):
            s.qpos[self.qadr] = q
            mujoco.mj_kinematics(self.model, s)
            mujoco.mj_comPos(self.model, s)
            rot = s.site_xmat[self.site].reshape(3, 3)
            e_pos = pos - s.site_xpos[self.site]
            e_rot = 0.5 * sum(np.cross(rot[:, i], target_rot[:, i]) for i in range(3))
            residual = float(np.linalg.norm(e_pos)) + float(np.linalg.norm(e_rot))
            if np.linalg.norm(e_pos) < POS_TOL and np.linalg.norm(e_rot) < ROT_TOL:
                break
            mujoco.mj_jacSite(self.model, s, jacp, jacr, self.site)
            jac = np.vstack([jacp[:, self.dofs], jacr[:, self.dofs]])
            err = np.concatenate([e_pos, e_rot])
            jjt = jac @ jac.T + damping**2 * np.eye(6)
            dq = jac.T @ np.linalg.solve(jjt, err)
            null = np.eye(7) - jac.T @ np.linalg.solve(jjt, jac)
            dq += null @ (0.1 * (anchor - q))
            q = np.clip(q + np.clip(dq, -0.2, 0.2), self.lo, self.hi)
        return q, residual

    def tcp_pose(self, data: mujoco.MjData, q: Vec) -> tuple[Vec, Vec]:
        """TCP position and rotation matrix for arm angles ``q`` (scratch forward kinematics)."""
        s = self.scratch
        s.qpos[:] = data.qpos
        s.qpos[self.qadr] = q
        mujoco.mj_kinematics(self.model, s)
        return s.site_xpos[self.site].copy(), s.site_xmat[self.site].reshape(3, 3).copy()
