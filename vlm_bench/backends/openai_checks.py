"""Checks of an OpenAI-compatible server before episodes are sent to it.

- :func:`preflight`: the server answers at all (a ``GET /models`` within a few seconds), and
  takes the API key. A down server is a one-line error at load, not minutes of retries.
- :func:`check_structured_outputs`: the server enforces ``response_format`` json_schema. Some
  servers accept the field and ignore it (``transformers serve`` logs "Ignoring unsupported
  fields"), which would make a run that says it is constrained silently unconstrained. The probe
  asks for a reply no model writes unprompted: a fixed token in a JSON object.
"""

from __future__ import annotations

import json
from typing import Any

from vlm_bench.backends.request_backend import ServerUnreachableError
from vlm_bench.errors import ConfigError

PROBE_TOKEN = "vlm-bench-probe-7f3a"
PROBE_SCHEMA: dict[str, Any] = {
    "type": "object",
    "properties": {"probe": {"type": "string", "enum": [PROBE_TOKEN]}},
    "required": ["probe"],
    "additionalProperties": False,
}
"""An object root with every property required and no others: accepted by strict servers."""


def server_url(client: Any) -> str:
    """The client's base URL, for messages."""
    return str(client.base_url).rstrip("/")


def preflight(client: Any, openai: Any, timeout_s: float) -> None:
    """Ask the server for its models once, without retries.

    Raises:
        ServerUnreachableError: No connection, or no answer within ``timeout_s``.
        ConfigError: The server refuses the API key (401/403).
    """
    url = server_url(client)
    try:
        client.with_options(timeout=timeout_s, max_retries=0).models.list()
    except openai.APIConnectionError as exc:  # includes timeouts
        cause = exc.__cause__ or exc
        raise ServerUnreachableError(
            f"cannot reach the OpenAI-compatible server at {url} ({type(cause).__name__}: "
            f"{cause}); start it, or pass -M base_url=..."
        ) from None
    except (openai.AuthenticationError, openai.PermissionDeniedError) as exc:
        raise ConfigError(
            f"the server at {url} refused the API key ({exc.status_code}); pass -M api_key=... "
            "or set OPENAI_API_KEY"
        ) from None
    except openai.APIStatusError:
        pass  # it answered: a server without GET /models is still a server


def check_structured_outputs(client: Any, openai: Any, model: str, max_tokens_param: str) -> None:
    """Ask for :data:`PROBE_SCHEMA` and check that the reply follows it.

    Raises:
        ConfigError: The server rejects or ignores ``response_format`` json_schema.
        ServerUnreachableError: The server does not answer.
    """
    url = server_url(client)
    try:
        response = client.with_options(max_retries=0).chat.completions.create(
            model=model,
            messages=[{"role": "user", "content": "Reply with one word: hello."}],
            temperature=0.0,
            response_format={
                "type": "json_schema",
                "json_schema": {"name": "probe", "schema": PROBE_SCHEMA},
            },
            **{max_tokens_param: 64},
        )
    except openai.APIConnectionError as exc:
        raise ServerUnreachableError(f"cannot reach the server at {url}: {exc}") from None
    except openai.APIStatusError as exc:
        raise ConfigError(
            f"--constrained: the server at {url} rejects response_format json_schema "
            f"({exc.status_code}: {str(exc)[:200]}); run without --constrained"
        ) from None
    text = (response.choices[0].message.content or "") if response.choices else ""
    try:
        reply = json.loads(text)
    except json.JSONDecodeError:
        reply = None
    if reply != {"probe": PROBE_TOKEN}:
        raise ConfigError(
            f"--constrained: the server at {url} does not enforce response_format json_schema "
            f'(a probe asking for {{"probe": "{PROBE_TOKEN}"}} got {text[:80]!r}), so the '
            "run would not be constrained; use a server with structured outputs (vLLM, SGLang) "
            "or run without --constrained"
        )
