"""``--perturb``, parsed in one place for the CLI and the Python API."""

from __future__ import annotations

import math

from vlm_bench.errors import ConfigError
from vlm_bench.executor.perturbations.gust import Gust
from vlm_bench.executor.perturbations.registered import PERTURBATIONS
from vlm_bench.types.closed_loop import PerturbConfig


def parse_perturb(text: str) -> tuple[PerturbConfig | None, float]:
    """``slip=P,bump=P,gust=N,...`` as perturbations and the gust force std (``uav_noise``, N).

    Raises:
        ConfigError: An unknown kind, a missing ``=``, or a value out of range.
    """
    values: dict[str, float] = {}
    usage = ",".join(
        f"{n}={'N' if PERTURBATIONS.get(n).maximum is None else 'P'}" for n in PERTURBATIONS
    )
    for part in (p.strip() for p in text.split(",")):
        if not part:
            continue
        name, sep, value = part.partition("=")
        name = name.strip()
        if not sep or name not in PERTURBATIONS:
            raise ConfigError(f"--perturb takes {usage}; got {part!r}")
        try:
            number = float(value)
        except ValueError:
            raise ConfigError(f"--perturb {name} must be a number, got {value!r}") from None
        top = PERTURBATIONS.get(name).maximum
        if not math.isfinite(number) or number < 0 or (top is not None and number > top):
            limit = "a number >= 0" if top is None else f"a probability in [0, {top:g}]"
            raise ConfigError(f"--perturb {name} must be {limit}, got {value!r}")
        values[name] = number
    gust = values.pop(Gust.name, 0.0)
    config = PerturbConfig(**values)
    return (config if config.active else None), gust


def perturb_options(
    perturb: str | PerturbConfig | None, uav_noise: float
) -> tuple[PerturbConfig | None, float]:
    """``--perturb`` (text or parsed) as perturbations, and the gust std from its ``gust`` or
    ``uav_noise`` (the CLI's ``--uav-noise``, the API's ``uav_noise=``).

    Raises:
        ConfigError: A bad ``--perturb``, or a ``gust`` and a different ``uav_noise``.
    """
    if not isinstance(perturb, str):
        return perturb, uav_noise
    config, gust = parse_perturb(perturb)
    if gust and uav_noise and gust != uav_noise:
        raise ConfigError(f"--perturb gust={gust:g} and --uav-noise {uav_noise:g} disagree")
    return config, gust or uav_noise
