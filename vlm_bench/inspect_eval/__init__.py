"""The benchmark as an inspect_ai task: ``inspect eval vlm_bench/aerial --model <model>``.

Registered through the ``inspect_ai`` entry point (:mod:`vlm_bench.inspect_eval._registry`);
needs the ``inspect`` extra (``pip install 'vlm-bench[inspect]'``). The task's samples are the
exported dataset's rows (built in-process, or read from ``-T dataset=PATH``), its scorer is
:func:`vlm_bench.score_answer`; ``-T loop=closed`` replans after failed executions in the
simulator. docs/protocols.md shows the commands.
"""
