"""lmms-eval hooks of ``vlm_bench_aerial`` and ``vlm_bench_aerial_text`` (named in their YAML).

A document is a row of the dataset ``vlm-bench export dataset`` writes. Chat models get
:func:`vlm_bench_doc_to_messages`: the system text and the user turn with each image where a run
puts it, as ``vlm-bench run`` sends them. Simple models get the images in prompt order
(:func:`vlm_bench_doc_to_visual`) and the system and user text (:func:`vlm_bench_doc_to_text`).
Answers are scored by :func:`vlm_bench.score_answer`, which refuses a row of another benchmark
version; every metric is the mean over episodes, overall and per suite.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from vlm_bench.export.row_model import image_column, user_parts
from vlm_bench.scoring.answer import score_answer

METRICS = ("s_plan", "s_loc", "s_obj", "s_skill", "s_total", "succ")
"""The paper's metrics as the YAML's ``metric_list`` names them (per suite ``<metric>_<suite>``)."""


def vlm_bench_doc_to_visual(doc: Mapping[str, Any]) -> list[Any]:
    """The row's images (PIL) in the order the user turn shows them."""
    return [doc[image_column(view)].convert("RGB") for view in doc["views"]]


def vlm_bench_doc_to_text(
    doc: Mapping[str, Any], lmms_eval_specific_kwargs: Mapping[str, Any] | None = None
) -> str:
    """System text, a blank line, then the user text (``<image:view>`` where each image goes)."""
    return f"{doc['system'].rstrip()}\n\n{doc['user']}"


def vlm_bench_doc_to_messages(
    doc: Mapping[str, Any], lmms_eval_specific_kwargs: Mapping[str, Any] | None = None
) -> list[dict[str, Any]]:
    """The chat a run sends: a system message, then the user turn's text parts and images in
    order (lmms-eval's message protocol)."""
    content: list[dict[str, Any]] = []
    for kind, value in user_parts(doc["user"]):
        if kind == "image":
            content.append({"type": "image", "url": doc[image_column(value)].convert("RGB")})
        else:
            content.append({"type": "text", "text": value})
    return [
        {"role": "system", "content": [{"type": "text", "text": doc["system"]}]},
        {"role": "user", "content": content},
    ]


def vlm_bench_process_results(doc: Mapping[str, Any], results: list[str]) -> dict[str, float]:
    """The paper's metrics of the model's answer (``results[0]``), under their overall and
    their suite's names; ``succ`` is 100 or 0, so that its mean is a percentage."""
    scores = score_answer(doc, results[0] if results else "").scores
    values = {
        "s_plan": scores.s_plan,
        "s_loc": scores.s_loc,
        "s_obj": scores.s_obj,
        "s_skill": scores.s_skill,
        "s_total": scores.s_total,
        "succ": 100.0 if scores.succ else 0.0,
    }
    suite = doc["suite"]
    return {**values, **{f"{name}_{suite}": value for name, value in values.items()}}
