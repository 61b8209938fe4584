"""A model's documented answer format: a reasoning block, then the answer in its own tag.

Reasoning models document the form of their output (GLM-4.1V-Thinking:
``<think>reasoning</think><answer>answer</answer>``). Output in exactly that form followed the
model's format, so nothing was repaired: the answer is parsed as if it were the whole output and
the reasoning is kept beside the plan. Anything else (a missing tag, text around the blocks, a
second answer) is left to the general repair path, which strips reasoning blocks as a repair.
The opening reasoning tag may be absent: chat templates often put it in the prompt.
"""

from __future__ import annotations

from dataclasses import dataclass

from vlm_bench.types.parse import AnswerFormat


@dataclass(frozen=True)
class TaggedAnswer:
    """Output split into its reasoning and its answer."""

    reasoning: str
    answer: str


def split_answer(text: str, fmt: AnswerFormat) -> TaggedAnswer | None:
    """``text`` as ``[<r>]reasoning</r> <a>answer</a>`` (whitespace around the blocks allowed),
    or None when it is not exactly in that form. Linear in the text's length."""
    open_r, close_r = f"<{fmt.reasoning}>", f"</{fmt.reasoning}>"
    open_a, close_a = f"<{fmt.answer}>", f"</{fmt.answer}>"
    body = text.strip()
    body = body.removeprefix(open_r)
    end = body.find(close_r)
    if end < 0:
        return None
    reasoning, rest = body[:end], body[end + len(close_r) :].strip()
    if open_r in reasoning or not (rest.startswith(open_a) and rest.endswith(close_a)):
        return None
    answer = rest[len(open_a) : len(rest) - len(close_a)]
    if open_a in answer or close_a in answer or close_r in answer:
        return None
    return TaggedAnswer(reasoning.strip(), answer.strip())
