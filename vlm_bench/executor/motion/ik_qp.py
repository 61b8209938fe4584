"""One IK iteration's QP for the arm-only model, assembled directly: the numbers of
``mink.solve_ik`` with a frame task, a posture task and a configuration limit, bit for bit.

``mink.solve_ik`` rebuilds every part of the QP on each call through generic task, limit and
``qpsolvers`` layers (about 100 µs a call, most of the planner's IK time). Here the parts that do
not change between iterations (the posture task's weighted Jacobian, the limits' constraint
matrix) are built once, the rest with the same numpy operations in the same order, and the QP
goes to DAQP as ``qpsolvers`` hands it over, so every velocity is the one ``solve_ik`` returns
(``tests/executor/test_ik_qp.py`` compares them).
"""

from __future__ import annotations

from ctypes import c_int

import daqp
import mink
import mujoco
import numpy as np

from vlm_bench.types.base import FloatArray

_INF = 1e30
"""The lower bound ``qpsolvers`` gives DAQP for one-sided inequalities."""


class IkQp:
    """The QP of one IK iteration (``frame`` and ``posture`` tasks, ``limit``) at ``config``.

    Args:
        config: The configuration the solver integrates (read at each :meth:`velocity`).
        frame: The TCP's frame task.
        posture: The posture task (its target may change between solves).
        limit: The joint limits (hinge joints only: the arm-only model has no ball joints).
        damping: Levenberg-Marquardt damping on every dof (``solve_ik``'s ``damping``).
    """

    def __init__(
        self,
        config: mink.Configuration,
        frame: mink.FrameTask,
        posture: mink.PostureTask,
        limit: mink.ConfigurationLimit,
        damping: float,
    ) -> None:
        if len(limit._ball_qposadr) or limit.projection_matrix is None:
            raise ValueError("IkQp handles hinge-joint limits only")
        self.config, self.frame, self.posture, self.limit = config, frame, posture, limit
        self.damping = damping
        self.nv = config.model.nv
        # Constant across iterations: the same values mink computes on each call.
        self._posture_jacobian = posture.cost[:, None] * posture.compute_jacobian(config)
        projection = limit.projection_matrix
        self._g = np.vstack([projection, -projection])
        self._lower_bound = np.full(self._g.shape[0], -_INF)
        self._sense = np.zeros(self._g.shape[0], dtype=c_int)
        # Buffers the stacked arrays are written into (np.vstack, concatenate and hstack made
        # new ones each iteration; the values and layouts are the same).
        rows = frame.cost.shape[0]
        self._rows = rows
        self._w = np.empty((rows + self._posture_jacobian.shape[0], self.nv))
        self._w[rows:] = self._posture_jacobian
        self._e = np.empty(self._w.shape[0])
        n = len(limit.indices)
        self._upper = np.empty(2 * n)
        self._to_upper = np.empty((self.nv,))
        self._from_lower = np.empty((self.nv,))
        self._posture_err = np.empty((self.nv,))

    def _posture_error(self) -> FloatArray:
        """``posture.compute_error(config)``: the same call, positional, into a buffer."""
        qvel = self._posture_err
        target = self.posture.target_q
        mujoco.mj_differentiatePos(self.config.model, qvel, 1.0, target, self.config.data.qpos)
        if self.posture._v_ids is not None:
            qvel[self.posture._v_ids] = 0.0
        return qvel

    def velocity(self, frame_error: FloatArray, dt: float) -> FloatArray:
        """The tangent velocity ``solve_ik`` returns at the configuration now, given the frame
        task's error there (``frame.compute_error``, which the caller has computed already).

        Raises:
            mink.NoSolutionFound: DAQP found no solution.
        """
        config, frame, posture = self.config, self.frame, self.posture
        # Frame task: cost-weighted Jacobian and error, and its LM term (Task._weighted_residual).
        jacobian = frame.compute_jacobian(config)
        frame_error_w = frame.cost * (-frame.gain * frame_error)
        rows, w, e = self._rows, self._w, self._e
        np.multiply(frame.cost[:, None], jacobian, out=w[:rows])  # the weighted Jacobian
        frame_mu = frame.lm_damping * float(frame_error_w @ frame_error_w)
        posture_error_w = posture.cost * (-posture.gain * self._posture_error())
        posture_mu = posture.lm_damping * float(posture_error_w @ posture_error_w)
        # Objective (solve_ik's _compute_qp_objective).
        h_matrix = w.T @ w
        e[:rows] = frame_error_w
        e[rows:] = posture_error_w
        c = -(e @ w)
        mu_total = 0.0
        mu_total += frame_mu
        mu_total += posture_mu
        h_matrix.flat[:: self.nv + 1] += self.damping + mu_total
        # Inequalities (ConfigurationLimit.compute_qp_inequalities).
        limit, q = self.limit, config.data.qpos
        to_upper, from_lower = self._to_upper, self._from_lower
        mujoco.mj_differentiatePos(limit.model, to_upper, 1.0, q, limit.upper)
        mujoco.mj_differentiatePos(limit.model, from_lower, 1.0, limit.lower, q)
        upper, n = self._upper, len(limit.indices)
        np.multiply(limit.gain, to_upper[limit.indices], out=upper[:n])
        np.multiply(limit.gain, from_lower[limit.indices], out=upper[n:])
        x, _, exitflag, _ = daqp.solve(
            h_matrix, c, self._g, upper, self._lower_bound, self._sense, primal_start=None
        )
        if exitflag <= 0:
            raise mink.NoSolutionFound("daqp")
        v: FloatArray = x / dt
        return v
