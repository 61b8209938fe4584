"""Every perturbation kind, registered in one place (``--perturb`` reads its names here)."""

from __future__ import annotations

from vlm_bench.executor.perturbations.bump import Bump
from vlm_bench.executor.perturbations.gust import Gust
from vlm_bench.executor.perturbations.kind import PerturbationKind
from vlm_bench.executor.perturbations.slip import Slip
from vlm_bench.registry import Registry

PERTURBATIONS: Registry[type[PerturbationKind]] = Registry("perturbation kind")
"""Kinds by ``--perturb`` key; a new kind is added here (or by ``PERTURBATIONS.add``)."""

for _kind in (Slip, Bump, Gust):
    PERTURBATIONS.add(_kind.name, _kind)
