"""``vlm_bench/aerial``: the inspect_ai task (``inspect eval vlm_bench/aerial -T ...``)."""

from __future__ import annotations

from vlm_bench.inspect_eval.extra import require_inspect

require_inspect()  # one line naming the extra, not an ImportError traceback

from inspect_ai import Task, task  # noqa: E402
from inspect_ai.dataset import MemoryDataset  # noqa: E402
from inspect_ai.model import GenerateConfig  # noqa: E402
from inspect_ai.solver import generate  # noqa: E402

from vlm_bench.inspect_eval.options import TaskArg, task_options  # noqa: E402
from vlm_bench.inspect_eval.samples import task_samples  # noqa: E402
from vlm_bench.inspect_eval.scoring import plan_scorer  # noqa: E402
from vlm_bench.resources import results_dir  # noqa: E402
from vlm_bench.storage import default_snapshot_cache  # noqa: E402


@task
def aerial(
    task: TaskArg | None = None,
    suite: str | None = None,
    seeds: TaskArg = "0-9",
    instruction: str = "both",
    views: TaskArg | None = None,
    resolution: int | None = None,
    k_shot: int | None = None,
    loop: str = "open",
    max_rounds: int = 3,
    perturb: TaskArg | None = None,
    dataset: str | None = None,
) -> Task:
    """The benchmark's episodes as an inspect task, scored with the AIR-VLA paper's metrics.

    Args:
        task: Task id(s), comma-separated (default: all 60).
        suite: Only this suite (``lh``, ``long_horizon``, ...).
        seeds: Episode seeds, ``0-9`` (the protocol's, default) or ``0,3``.
        instruction: ``explicit``, ``implicit`` or ``both``.
        views: Views shown, comma-separated (default: all four).
        resolution: Snapshot side in pixels (default 448).
        k_shot: Few-shot examples in the system prompt (default 2).
        loop: ``open`` (one answer per episode) or ``closed`` (replan after a failed
            execution in the simulator, scored with Succ@k).
        max_rounds: Closed loop: replans after round 0 (K).
        perturb: Closed loop: ``slip=P,bump=P,gust=N`` (the closed protocol: slip=0.3,bump=0.3).
        dataset: An exported dataset folder to read the episodes from (``vlm-bench export
            dataset``); default: build them here (renders with MuJoCo).
    """
    options = task_options(
        task, suite, seeds, instruction, views, resolution, k_shot, loop, max_rounds, perturb,
        dataset,
    )  # fmt: skip
    cache = default_snapshot_cache(results_dir() / "inspect")
    samples = task_samples(options, cache / "inspect_png", cache)
    if options.loop == "closed":
        from vlm_bench.inspect_eval.closed_loop import closed_loop_solver

        solver = closed_loop_solver(options)
        scorer = plan_scorer(options.max_rounds)
    else:
        solver = generate()
        scorer = plan_scorer()
    return Task(
        dataset=MemoryDataset(samples, name="vlm_bench_aerial"),
        solver=solver,
        scorer=scorer,
        config=GenerateConfig(temperature=0.0),
        metadata={"loop": options.loop, "benchmark": "vlm-bench"},
    )
