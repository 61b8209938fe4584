"""vlm-bench: evaluate vision-language models as planners for aerial manipulation."""

__version__ = "0.1.0"
