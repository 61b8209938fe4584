"""The model's answers to a run's requests, through the run's response cache
(docs/design.md#runs).

:class:`ModelAnswers` answers round 0's requests and the replans alike: an answer cached under
the episode's key and the request's prompt hash is taken from the cache; the others are generated
in one ``Backend.generate`` call and cached before anything else is written, so an interrupt
loses no answer. The backend is loaded on the first request that misses the cache (a finished
resume never loads the model). A failed generation is an answer with an error (never raised); a
configuration error of the backend stops the run with its one-line message.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from vlm_bench.backends import Backend, resolve_backend
from vlm_bench.errors import ConfigError, VlmBenchError
from vlm_bench.storage import RunStore
from vlm_bench.types.generation import GenerationConfig, GenerationRequest, GenerationResult
from vlm_bench.types.records import CachedResponse, usage_of

MAX_ERROR_MESSAGES = 5
"""Backend error messages kept for the run's summary."""


@dataclass(frozen=True)
class Question:
    """A request to answer, under its cache key."""

    key: str
    """The episode's key."""
    prompt_hash: str
    """The cache key of the answer (a replan's chains the conversation before it)."""
    request: GenerationRequest


@dataclass(frozen=True)
class Answer:
    """The answer to a :class:`Question`: the model's text, or the backend's error."""

    question: Question
    response: CachedResponse | None
    """The answer as cached (None: the backend failed)."""
    cached: bool = False
    """Taken from the response cache."""
    error: str | None = None
    """The backend's error, where it failed."""
    latency_s: float = 0.0
    """The failed generation's time (s)."""


@dataclass
class AnswerStats:
    """Counts of a run's answers."""

    cached: int = 0
    errors: int = 0
    generate_calls: int = 0
    error_messages: list[str] = field(default_factory=list)
    """``request id: error`` of the first few backend errors."""


def load_backend(model: str, args: dict[str, str]) -> Backend:
    """Build the run's backend; a model that fails to load is a one-line error naming it.

    Raises:
        ConfigError: The backend's loader raised (e.g. a corrupt checkpoint, an unsupported
            architecture, a server refusing the model); the message keeps its first line.
    """
    try:
        return resolve_backend(model, args)
    except VlmBenchError:
        raise
    except Exception as exc:  # noqa: BLE001  (loaders raise anything: OSError, ValueError, ...)
        lines = str(exc).strip().splitlines()
        detail = lines[0][:300] if lines else ""
        raise ConfigError(f"cannot load model {model!r}: {type(exc).__name__}: {detail}") from None


class ModelAnswers:
    """A run's answers (module doc).

    Args:
        model: The model string (loaded on the first cache miss unless ``given``).
        backend_args: Its ``-M`` arguments.
        generation: Decoding settings.
        store: The run folder whose response cache is read and written.
        given: A backend instance to use (the caller closes it); None: load one (closed here).
    """

    def __init__(
        self,
        model: str,
        backend_args: dict[str, str],
        generation: GenerationConfig,
        store: RunStore,
        given: Backend | None = None,
    ) -> None:
        self.model = model
        self.backend_args = backend_args
        self.generation = generation
        self.store = store
        self.stats = AnswerStats()
        self._backend = given
        self._owned = given is None

    def answer(self, questions: Sequence[Question]) -> list[Answer]:
        """Answer every question, in order: cached answers first looked up, the others generated
        in one call and cached."""
        store = self.store
        misses = [q for q in questions if store.cached_response(q.key, q.prompt_hash) is None]
        results = self._generate([q.request for q in misses])
        out: list[Answer] = []
        for q in questions:
            cached = store.cached_response(q.key, q.prompt_hash)
            if cached is not None:
                self.stats.cached += 1
                out.append(Answer(q, cached, cached=True))
                continue
            result = results[q.request.id]
            if result.error is not None:
                self.stats.errors += 1
                if len(self.stats.error_messages) < MAX_ERROR_MESSAGES:
                    self.stats.error_messages.append(f"{q.request.id}: {result.error}")
                out.append(Answer(q, None, error=result.error, latency_s=result.latency_s))
                continue
            response = CachedResponse(
                key=q.key, prompt_hash=q.prompt_hash, text=result.text, **usage_of(result)
            )
            store.append_response(response)
            out.append(Answer(q, response))
        return out

    def close(self) -> None:
        """Free the backend this object loaded."""
        if self._owned and self._backend is not None:
            self._backend.close()

    def _generate(self, requests: list[GenerationRequest]) -> dict[str, GenerationResult]:
        if not requests:
            return {}
        if self._backend is None:
            self._backend = load_backend(self.model, self.backend_args)
        self.stats.generate_calls += 1
        try:
            results = self._backend.generate(requests, self.generation)
        except VlmBenchError:
            raise  # configuration errors stop the run with their one-line message
        except Exception as exc:  # noqa: BLE001  (a backend bug must not kill a long run)
            message = f"backend raised {type(exc).__name__}: {exc}"
            results = [GenerationResult(id=r.id, error=message) for r in requests]
        by_id = {r.id: r for r in results}
        return {
            req.id: by_id.get(req.id)
            or GenerationResult(id=req.id, error="backend returned no result for this request")
            for req in requests
        }
