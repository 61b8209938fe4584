"""A run's plan: everything a run needs from its configuration, resolved once, before the run
folder is written (docs/design.md#runs).

:func:`plan_run` checks the configuration (benchmark version, resolution, task ids, backend) and
resolves what the rest of the run reads: the episodes in order, the backend's name and whether
it reads images, the protocol mark, the manifest, the views shown, each instruction variant's
prompt options, the executor's settings and the closed loop's. The pipeline, the pool driver and
the snapshot source receive the plan's parts, never the configuration.
"""

from __future__ import annotations

import platform
from collections.abc import Mapping
from dataclasses import dataclass

from vlm_bench.backends import Backend, operational_args
from vlm_bench.backends.preflight import BackendCheck, check_backend
from vlm_bench.backends.rules_planner import NO_SCENE
from vlm_bench.catalog.tasks import tasks_in
from vlm_bench.errors import ConfigError
from vlm_bench.rounds.state import StateView
from vlm_bench.runner.cached_snapshots import check_resolution
from vlm_bench.runner.selection import EpisodeRef, select_episodes
from vlm_bench.storage import data_hashes, git_revision, package_versions
from vlm_bench.storage.provenance import machine
from vlm_bench.types.benchmark_version import require_current_version
from vlm_bench.types.closed_loop import HistoryMode, LoopConfig
from vlm_bench.types.execution import ExecutorConfig
from vlm_bench.types.generation import GenerationConfig
from vlm_bench.types.prompt import PromptConfig
from vlm_bench.types.protocol import ProtocolMark
from vlm_bench.types.protocol_match import protocol_mark
from vlm_bench.types.records import utc_now
from vlm_bench.types.run import RunConfig, RunManifest
from vlm_bench.types.task import InstructionVariant


@dataclass(frozen=True)
class RunPlan:
    """What a run does, resolved from its configuration (module doc)."""

    config: RunConfig
    """The configuration it was resolved from (the manifest's, the run folder's identity)."""
    episodes: tuple[EpisodeRef, ...]
    """The run's episodes in benchmark order."""
    backend: BackendCheck
    """The backend that serves the model, and whether it reads images."""
    protocol: ProtocolMark
    """The run's stated protocol and its share of it."""
    operational: frozenset[str]
    """The backend's operational ``-M`` arguments (left out of the config hash)."""
    shown: StateView
    """The views every prompt shows (none where the backend reads no images), their size and
    labels: round 0's snapshots and each replan's."""
    prompts: Mapping[InstructionVariant, PromptConfig]
    """Each instruction variant's prompt options."""
    generation: GenerationConfig
    """Decoding settings (batch size, constrained decoding)."""
    executor: ExecutorConfig | None
    """The executor's settings (gusts, perturbations); None: the run executes no plans."""
    loop: LoopConfig | None
    """The closed loop's settings; None: an open loop."""
    history: HistoryMode
    """How a replan's conversation shows earlier rounds."""

    def manifest(self, run_id: str) -> RunManifest:
        """The manifest of a new run folder (provenance gathered now)."""
        config = self.config
        return RunManifest(
            run_id=run_id,
            config=config.redacted(),
            config_hash=config.config_hash(self.operational),
            operational_args=tuple(sorted(self.operational)),
            backend=self.backend.name,
            data=data_hashes(),
            packages=package_versions(),
            git_revision=git_revision(),
            python=platform.python_version(),
            platform=machine(),
            created=utc_now(),
            protocol=self.protocol,
        )


def plan_run(config: RunConfig, given: Backend | None = None) -> RunPlan:
    """Check ``config`` and resolve its plan; nothing is loaded, rendered or written.

    Args:
        config: The run configuration.
        given: A backend instance the run uses instead of resolving ``config.model`` (trusted:
            not checked).

    Raises:
        BenchmarkVersionError: The config asks for another benchmark version.
        ConfigError: A resolution above the offscreen buffer, an unknown model, a bad backend
            argument, the ``rules`` planner without the scene as text.
        MissingExtraError: The backend's optional dependency is not installed.
        UnknownNameError: Unknown task ids.
    """
    require_current_version(config.benchmark_version, "the run's config")
    check_resolution(config.resolution)
    episodes = tuple(select_episodes(config))
    if given is not None:
        backend = BackendCheck(given.name, config.model, given.sees_images)
    else:
        backend = check_backend(
            config.model, config.backend_args, constrained=config.generation.constrained
        )
    if backend.name == "rules" and not config.scene_as_text:
        raise ConfigError(NO_SCENE)
    views = config.views if config.images and backend.sees_images else ()
    return RunPlan(
        config=config,
        episodes=episodes,
        backend=backend,
        protocol=protocol_mark(config, len(episodes), len(tasks_in(None))),
        operational=operational_args(config.model),
        shown=StateView(tuple(views), config.resolution, config.labels),
        prompts={v: config.prompt_config(v) for v in config.instructions},
        generation=config.generation,
        executor=config.executor_config() if config.execute else None,
        loop=config.loop_config() if config.loop == "closed" else None,
        history=config.history,
    )
