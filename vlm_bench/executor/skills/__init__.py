"""The scripted ARM skills, one file per family over a shared hand core.

Every skill implements :class:`~vlm_bench.executor.sim_loop.Skill` (the step in, a typed
failure or None out): a family is built on one :class:`~.hand.Hand` and its factory hands out
its bound methods by skill name.

``hand`` (the arm and fingers every skill uses on one loop), ``grasp_points`` (where each kind
is held), ``grasping`` (``pick``, and ``pick``/``place`` bound to one hand), ``placing``
(``place``), ``release_points`` (where a held object is let go), ``carry_raise`` (the hand
raised to carrying height), ``pushing`` (``push``), ``articulation`` (``pull``, ``close``,
``rotate``) and ``scripted_skills`` (:func:`default_skills`, all bound to one loop).
"""
