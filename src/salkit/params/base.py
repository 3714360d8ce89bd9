"""The base of every parameter object (frozen, no unknown fields, defaults validated, no inf or
NaN) and the parameter objects the SAL and down-looking scenarios share."""
from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field


class FieldProblem(ValueError):
    """A check across fields that names the field it refuses (relative to the object checked), its
    value and the constraint: what a model validator raises so that the error reported to the user
    names ``platform.trajectory`` rather than the object that holds it.

    Parameters
    ----------
    field : str
        Dotted path below the object being validated.
    value : object
    constraint : str
    """

    def __init__(self, field: str, value, constraint: str):
        super().__init__(f"{field} = {value!r}: {constraint}")
        self.field, self.value, self.constraint = field, value, constraint


class _Frozen(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid", validate_default=True, allow_inf_nan=False)


class PhaseError(_Frozen):
    """A known per-pulse phase error common to all scatterers (residual motion, vibration), for
    validating autofocus. ``amplitude`` is the peak (quadratic: at the aperture ends; sinusoidal)
    or the RMS (random, a low-pass Gaussian process), rad."""

    kind: Literal["quadratic", "sinusoidal", "random"] = "quadratic"
    amplitude: float = Field(gt=0, le=1e3, description="rad")
    cycles: float = Field(default=2.5, gt=0, description="sinusoidal: cycles across the aperture")
    bandwidth: float = Field(default=4.0, gt=0, description="random: cycles across the aperture")
    seed: int = Field(default=0, ge=0)

    def values(self, n: int):
        """The error (rad) on n pulses."""
        t = np.linspace(-1, 1, n)
        if self.kind == "quadratic":
            return self.amplitude * t ** 2
        if self.kind == "sinusoidal":
            return self.amplitude * np.sin(np.pi * self.cycles * t)
        rng = np.random.default_rng(self.seed)
        r = rng.standard_normal(4 * n)
        f = np.fft.fftfreq(4 * n)
        r = np.real(np.fft.ifft(np.fft.fft(r) * (np.abs(f) <= self.bandwidth / (2 * n))))[:n]
        return self.amplitude * (r - r.mean()) / r.std()
