"""The ``inspect_ai`` entry point: importing it registers ``vlm_bench/aerial`` (inspect loads
the ``[project.entry-points.inspect_ai]`` module named ``vlm_bench`` when a task name starts
with ``vlm_bench/``)."""

from vlm_bench.inspect_eval.task import aerial

__all__ = ["aerial"]
