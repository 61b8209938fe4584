"""Where an hf or vllm model comes from, checked in about a second: a local folder, the Hugging
Face cache, or one short hub query. A typo then fails at once with one line, instead of after the
model loader's minutes of retries against an unreachable hub."""

from __future__ import annotations

import os
import re
from pathlib import Path

from vlm_bench.errors import ConfigError

HUB_TIMEOUT_S = 10.0
"""Longest wait for the hub's answer about a model id."""

_TRUE = ("1", "true", "yes", "on")
_HUB_ID = re.compile(r"[A-Za-z0-9][\w.-]{0,95}(/[A-Za-z0-9][\w.-]{0,95})?")
"""A Hugging Face repo id: ``name`` or ``org/name`` (letters, digits, ``_ . -``)."""


def hub_offline() -> bool:
    """True when ``HF_HUB_OFFLINE`` (or ``TRANSFORMERS_OFFLINE``) forbids hub access."""
    from huggingface_hub import constants

    env = any(
        os.environ.get(name, "").strip().lower() in _TRUE
        for name in ("HF_HUB_OFFLINE", "TRANSFORMERS_OFFLINE")
    )
    return env or bool(constants.HF_HUB_OFFLINE)


def _looks_like_path(model: str) -> bool:
    return model.startswith(("/", "./", "../", "~")) or model.count("/") > 1 or "\\" in model


def _check_folder(model: str, path: Path, needs_config: bool) -> None:
    if not path.is_dir():
        if needs_config:
            raise ConfigError(f"model path {model} is a file; give the model's folder")
        return
    if needs_config and not (path / "config.json").is_file():
        raise ConfigError(f"model folder {model} has no config.json (not a saved model)")


def _cached(model: str, revision: str | None) -> bool:
    from huggingface_hub import try_to_load_from_cache

    found = try_to_load_from_cache(model, "config.json", revision=revision)
    return isinstance(found, str)


def _ask_hub(model: str, revision: str | None, hint: str) -> None:
    from huggingface_hub import HfApi
    from huggingface_hub.errors import RepositoryNotFoundError, RevisionNotFoundError

    try:
        HfApi().model_info(model, revision=revision, timeout=HUB_TIMEOUT_S)
    except RevisionNotFoundError:
        raise ConfigError(f"model {model!r} has no revision {revision!r} on the hub") from None
    except RepositoryNotFoundError:
        raise ConfigError(
            f"model {model!r} is not a local folder and not on the Hugging Face hub (a private "
            f"model needs HF_TOKEN){hint}"
        ) from None
    except Exception as exc:  # noqa: BLE001  (no network takes many forms: DNS, proxy, TLS)
        raise ConfigError(
            f"model {model!r} is not a local folder or in the Hugging Face cache, and the hub "
            f"could not be asked ({type(exc).__name__}){hint}"
        ) from None


def check_model_source(
    model: str, revision: str | None = None, *, hint: str = "", needs_config: bool = True
) -> None:
    """Check that ``model`` names a local model folder or a Hugging Face model.

    Args:
        model: A local path or a hub id (``org/name``).
        revision: The hub revision asked for (``-M revision=...``).
        hint: Appended to a not-found message (e.g. ``"; did you mean 'openai/x'?"``).
        needs_config: A local folder must hold ``config.json`` (transformers); a file is refused.

    Raises:
        ConfigError: A missing path, an invalid id, an id the hub does not know, or one that is
            not cached while the hub is off or unreachable (one line naming the model).
    """
    path = Path(model).expanduser()
    if path.exists():
        _check_folder(model, path, needs_config)
        return
    if _looks_like_path(model):
        raise ConfigError(f"model path {model} does not exist{hint}")
    if not _HUB_ID.fullmatch(model) or ".." in model or "--" in model:
        raise ConfigError(
            f"model {model!r} is neither an existing local path nor a Hugging Face id "
            f"(org/name){hint}"
        )
    if _cached(model, revision):
        return
    if hub_offline():
        raise ConfigError(
            f"model {model!r} is not a local folder and not in the Hugging Face cache, and "
            f"HF_HUB_OFFLINE is set{hint}"
        )
    _ask_hub(model, revision, hint)
