"""The result of a run, the same for every engine: trajectory, summary, parameters and solver info."""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class Result:
    """trajectory: dict of arrays (one entry per accepted step and t = 0); summary: dict of
    scalars; params: the scene parameters; info: solver settings and counters."""

    trajectory: dict
    summary: dict
    params: object
    info: dict = field(default_factory=dict)
