"""Perturbations a good plan cannot avoid (``--perturb``; docs/closed-loop.md#perturbations):
one file per kind (:mod:`.slip`, :mod:`.bump`, :mod:`.gust`), each a
:class:`~.kind.PerturbationKind`, registered in :mod:`.registered`; :class:`~.perturber.Perturber`
fires a live episode's kinds and keeps their events.
"""

from vlm_bench.executor.perturbations.kind import PerturbationKind, event_rng
from vlm_bench.executor.perturbations.options import parse_perturb, perturb_options
from vlm_bench.executor.perturbations.perturber import Perturber
from vlm_bench.executor.perturbations.registered import PERTURBATIONS

__all__ = [
    "PERTURBATIONS",
    "PerturbationKind",
    "Perturber",
    "event_rng",
    "parse_perturb",
    "perturb_options",
]
