"""Model output → plan: JSON extraction, deterministic repair, normalisation, error codes.

Parsing never raises on model output; see :func:`parse_plan` and
:class:`vlm_bench.types.parse.ParseCode` for the closed set of error codes.
"""

from vlm_bench.parsing.parser import error_result, parse_plan
from vlm_bench.parsing.schema import is_valid, plan_json_schema, schema_violations, step_json_schema

__all__ = [
    "error_result",
    "is_valid",
    "parse_plan",
    "plan_json_schema",
    "schema_violations",
    "step_json_schema",
]
