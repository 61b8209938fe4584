"""A perturbation kind is a plug-in: one class defined outside the package (here, in this test
file) and registered once runs end to end, from ``perturb="nudge=1"`` to the run's records,
without touching the loop that calls it (docs/design.md#how-to-add-a-perturbation-kind)."""

from __future__ import annotations

from pathlib import Path

import pytest

import vlm_bench
from vlm_bench.errors import ConfigError
from vlm_bench.executor.perturbations import PERTURBATIONS, PerturbationKind, event_rng
from vlm_bench.executor.sim_loop import SimLoop
from vlm_bench.types.closed_loop import PerturbEvent
from vlm_bench.types.execution import ExecutionOptions
from vlm_bench.types.plan import ArmStep

TASK = "standard_pick_place"


class Nudge(PerturbationKind):
    """Before an ARM step, with probability ``rate``, records a nudge of its object."""

    name = "nudge"

    def before_arm_step(self, loop: SimLoop, index: int, step: ArmStep) -> None:
        if event_rng(self.episode, self.name, step.object, index).random() < self.rate:
            self.emit(PerturbEvent(kind=self.name, step=index, object=step.object))


PERTURBATIONS.add(Nudge.name, Nudge)


def test_a_kind_defined_outside_the_package_runs_end_to_end(tmp_path: Path) -> None:
    result = vlm_bench.run(
        model="oracle",
        tasks=(TASK,),
        seeds=(0,),
        instructions=("explicit",),
        resolution=32,
        perturb="nudge=1",
        out=tmp_path / "run",
        execution=ExecutionOptions(workers=0),
        snapshot_cache=False,
    )
    (record,) = result.records
    assert record.execution is not None and record.execution.exec_success
    events = record.execution.perturbations or ()
    arm = [
        (i, s.object)
        for i, s in enumerate(result.records[0].parse.valid_steps())  # type: ignore[union-attr]
        if isinstance(s, ArmStep)
    ]
    assert [(e.kind, e.step, e.object) for e in events] == [("nudge", i, o) for i, o in arm]
    assert result.manifest.config.perturb is not None
    assert result.manifest.config.perturb.rates()["nudge"] == 1.0


def test_an_unknown_kind_is_refused_with_the_valid_names() -> None:
    with pytest.raises(ConfigError, match="slip=P,bump=P,gust=N"):
        vlm_bench.run(model="oracle", perturb="wind=1", out="unused")


def test_the_api_parses_perturb_as_the_cli_does() -> None:
    with pytest.raises(ConfigError, match="disagree"):
        vlm_bench.run(model="oracle", perturb="gust=2", uav_noise=1.0, out="unused")
