"""Typed data models for everything that crosses a module boundary or is serialised.

No face: each model is imported from the module that defines it (``vlm_bench.types.plan``,
``vlm_bench.types.episode``, ...), as every module of the package does.
"""
