"""Backends that need no weights: ``oracle`` (GT ceiling), ``random`` (floor), ``mock`` (scripted).

``oracle`` and ``random`` read :class:`~vlm_bench.types.generation.RequestMeta`, which the runner
fills from the episode (``gt_plan``, ``object_ids``); a request without it gets an error result.
"""

from __future__ import annotations

import hashlib
import json
import random
import time
from abc import abstractmethod
from collections.abc import Callable, Sequence
from pathlib import Path

from pydantic import Field, model_validator

from vlm_bench.backends.backend import Backend, BackendArgs
from vlm_bench.catalog.files import not_utf8
from vlm_bench.catalog.skills import skills
from vlm_bench.errors import ConfigError, DataFileError
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult
from vlm_bench.types.plan import ArmStep, Direction, UavStep, plan_to_json
from vlm_bench.types.rounds import round_request_id


def _answer_each(
    requests: Sequence[GenerationRequest],
    answer: Callable[[GenerationRequest], tuple[str, str | None]],
) -> list[GenerationResult]:
    """A result per request from ``answer`` (its text and error), timed per request."""
    out: list[GenerationResult] = []
    for req in requests:
        start = time.perf_counter()
        text, error = answer(req)
        out.append(
            GenerationResult(
                id=req.id,
                text=text,
                error=error,
                latency_s=time.perf_counter() - start,
                finish_reason=None if error else "stop",
            )
        )
    return out


class PlannerBackend(Backend):
    """A built-in that plans from what the runner puts in a request: :meth:`plan` gives the
    plan, or the reason it cannot (recorded as a backend error). It reads no images, so runs
    render no views for it."""

    sees_images = False

    def __init__(self, model: str = "", args: BackendArgs | None = None) -> None:
        self.args = args or BackendArgs()

    @abstractmethod
    def plan(self, request: GenerationRequest) -> Sequence[UavStep | ArmStep] | str:
        """The request's plan, or an error message."""

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        """One plan per request, in the paper's JSON format."""
        return _answer_each(requests, self._answer)

    def _answer(self, request: GenerationRequest) -> tuple[str, str | None]:
        plan = self.plan(request)
        if isinstance(plan, str):
            return "", plan
        return json.dumps(plan_to_json(list(plan))), None


class OracleBackend(PlannerBackend):
    """Answers each request with its episode's GT plan (the ceiling: every metric is 100).
    The GT is drawn for the first frame, so the oracle cannot replan: a closed loop's replan
    gets an empty plan, which ends the episode (the open-loop reference)."""

    name = "oracle"

    def plan(self, request: GenerationRequest) -> Sequence[UavStep | ArmStep] | str:
        """``meta.gt_plan`` (round 0), else no steps."""
        if request.meta is None or request.meta.gt_plan is None:
            return "oracle: request has no meta.gt_plan"
        return request.meta.gt_plan if request.meta.round == 0 else ()


class RandomArgs(BackendArgs):
    """``-M`` arguments of the random backend."""

    seed: int = Field(default=0, description="Seed; mixed with each request id.")
    min_steps: int = Field(default=1, ge=1, description="Shortest plan.")
    max_steps: int = Field(default=6, ge=1, description="Longest plan.")

    @model_validator(mode="after")
    def _ordered(self) -> RandomArgs:
        if self.min_steps > self.max_steps:
            raise ValueError("min_steps must not exceed max_steps")
        return self


class RandomBackend(PlannerBackend):
    """Seeded random *valid* plans over the scene's objects: the floor baseline."""

    name = "random"
    Args = RandomArgs

    def __init__(self, model: str = "", args: RandomArgs | None = None) -> None:
        self.args: RandomArgs = args or RandomArgs()

    def random_plan(self, request_id: str, object_ids: Sequence[str]) -> list[UavStep | ArmStep]:
        """The random plan of one request: same seed and id, same plan."""
        digest = hashlib.sha256(f"{self.args.seed}|{request_id}".encode()).digest()
        rng = random.Random(int.from_bytes(digest[:8], "big"))
        arm = [s for s in skills().values() if s.agent == "ARM"]
        steps: list[UavStep | ArmStep] = []
        for _ in range(rng.randint(self.args.min_steps, self.args.max_steps)):
            if rng.random() < 0.5:
                steps.append(UavStep(direction=rng.choice(list(Direction))))
                continue
            skill = rng.choice(arm)
            optional = [f.name for f in skill.fields if f.type == "object" and not f.required]
            target = rng.choice(object_ids) if "target" in optional and rng.random() < 0.5 else None
            steps.append(ArmStep(object=rng.choice(object_ids), skill=skill.name, target=target))
        return steps

    def plan(self, request: GenerationRequest) -> Sequence[UavStep | ArmStep] | str:
        """A random plan over ``meta.object_ids``."""
        if request.meta is None or not request.meta.object_ids:
            return "random: request has no meta.object_ids"
        return self.random_plan(request.id, request.meta.object_ids)


class MockArgs(BackendArgs):
    """``-M`` arguments of the mock backend: a JSONL file of scripted outputs, or one text."""

    file: Path | None = Field(
        default=None,
        description='JSONL, one {"id": ..., "text": ...}, {"id", "error"} or, one answer per '
        'closed-loop round, {"id", "rounds": [...]} a line.',
    )
    text: str | None = Field(default=None, description="Answer every request with this text.")

    @model_validator(mode="after")
    def _one_source(self) -> MockArgs:
        if (self.file is None) == (self.text is None):
            raise ValueError("give exactly one of file=... or text=...")
        return self


def _load_script(path: Path) -> dict[str, tuple[str, str | None]]:
    """Read scripted outputs: id → (text, error)."""
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except OSError as exc:
        raise DataFileError(str(path), f"cannot read: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise DataFileError(str(path), not_utf8(exc)) from None
    script: dict[str, tuple[str, str | None]] = {}
    for n, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        try:
            row = json.loads(line)
        except json.JSONDecodeError as exc:
            raise DataFileError(str(path), f"line {n}: invalid JSON: {exc.msg}") from None
        if not isinstance(row, dict) or not isinstance(row.get("id"), str):
            raise DataFileError(str(path), f"line {n}: expected an object with a string 'id'")
        rounds = row.get("rounds")
        if rounds is not None:
            if not isinstance(rounds, list) or not all(isinstance(t, str) for t in rounds):
                raise DataFileError(str(path), f"line {n}: 'rounds' must be a list of strings")
            for r, text in enumerate(rounds):
                script[round_request_id(row["id"], r)] = (text, None)
            continue
        text, error = row.get("text", ""), row.get("error")
        if not isinstance(text, str) or not (error is None or isinstance(error, str)):
            raise DataFileError(str(path), f"line {n}: 'text' and 'error' must be strings")
        script[row["id"]] = (text, error or None)
    return script


class MockBackend(Backend):
    """Scripted outputs for tests and demos; unknown ids give an error result. It stands in
    for a VLM, so its requests carry the views a VLM's would."""

    name = "mock"
    Args = MockArgs

    def __init__(self, model: str = "", args: MockArgs | None = None) -> None:
        if args is None:
            raise ConfigError("backend 'mock' needs -M file=outputs.jsonl or -M text=...")
        self.args = args
        self.script = _load_script(args.file) if args.file is not None else {}

    def generate(
        self, requests: Sequence[GenerationRequest], config: GenerationConfig
    ) -> list[GenerationResult]:
        """Look each request id up in the script (or answer the fixed text)."""
        return _answer_each(requests, self._answer)

    def _answer(self, request: GenerationRequest) -> tuple[str, str | None]:
        if self.args.text is not None:
            return self.args.text, None
        if request.id in self.script:
            text, error = self.script[request.id]
            return ("" if error else text), error
        return "", f"mock: no scripted output for id {request.id!r}"
