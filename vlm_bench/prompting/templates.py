"""The Jinja2 environment over ``prompts/``: strict, deterministic, no HTML escaping."""

from __future__ import annotations

import hashlib
import json
from functools import cache
from typing import Any

import jinja2

from vlm_bench.catalog.files import not_utf8
from vlm_bench.errors import DataFileError
from vlm_bench.resources import prompts_dir

TEMPLATES = ("system.j2", "few_shot.j2", "user.j2")
"""Templates that make up a prompt (hashed into every prompt)."""


def plan_json(plan: list[dict[str, Any]]) -> str:
    """Render a plan in the paper's JSON format, one step per line."""
    if not plan:
        return "[]"
    rows = ",\n".join("  " + json.dumps(step) for step in plan)
    return f"[\n{rows}\n]"


@cache
def environment() -> jinja2.Environment:
    """The template environment (cached): undefined variables are errors, not blanks."""
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(prompts_dir())),
        undefined=jinja2.StrictUndefined,
        autoescape=False,  # prompts are plain text, never HTML
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=False,
    )
    env.filters["plan_json"] = plan_json
    env.filters["tojson_compact"] = lambda value: json.dumps(value)
    return env


def render(name: str, **context: Any) -> str:
    """Render one template; a missing template or variable names the file."""
    path = prompts_dir() / name
    try:
        return environment().get_template(name).render(**context).strip() + "\n"
    except jinja2.TemplateNotFound:
        raise DataFileError(str(path), "template not found") from None
    except jinja2.UndefinedError as exc:
        raise DataFileError(str(path), f"undefined variable: {exc.message}") from None
    except jinja2.TemplateSyntaxError as exc:
        raise DataFileError(str(path), f"line {exc.lineno}: {exc.message}") from None
    except UnicodeDecodeError as exc:
        raise DataFileError(str(path), not_utf8(exc)) from None


@cache
def templates_digest() -> str:
    """sha256 over the template sources and the few-shot example file."""
    digest = hashlib.sha256()
    for name in (*TEMPLATES, "few_shot_examples.json"):
        path = prompts_dir() / name
        digest.update(name.encode())
        digest.update(path.read_bytes() if path.is_file() else b"<missing>")
    return digest.hexdigest()
