"""JSON-Schema constrained decoding for the ``hf`` backend with xgrammar (optional extra)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any

from vlm_bench.errors import MissingExtraError
from vlm_bench.types.generation import GenerationRequest


class SchemaConstraint:
    """Compiles request schemas against a tokenizer and builds per-batch logits processors.

    Compiled grammars are cached by schema text, so episodes sharing a schema compile once.
    """

    def __init__(self, tokenizer: Any, vocab_size: int, stop_token_ids: Sequence[int]) -> None:
        try:
            import xgrammar as xgr
        except ImportError:
            raise MissingExtraError("xgrammar", "constrained") from None
        self._xgr = xgr
        info = xgr.TokenizerInfo.from_huggingface(
            tokenizer, vocab_size=vocab_size, stop_token_ids=list(stop_token_ids) or None
        )
        self._compiler = xgr.GrammarCompiler(info)
        self._cache: dict[str, Any] = {}

    def _compiled(self, schema: dict[str, Any]) -> Any:
        key = json.dumps(schema, sort_keys=True)
        if key not in self._cache:
            # Compact JSON: no free whitespace for the model to waste tokens on.
            self._cache[key] = self._compiler.compile_json_schema(key, any_whitespace=False)
        return self._cache[key]

    def logits_processor(self, batch: Sequence[GenerationRequest]) -> Any:
        """A fresh ``transformers.LogitsProcessor`` for one ``generate`` call over ``batch``."""
        from xgrammar.contrib.hf import LogitsProcessor

        grammars = [self._compiled(req.json_schema or {}) for req in batch]
        return LogitsProcessor(grammars)
