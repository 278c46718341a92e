"""Seeded periodic fractal noise by spectral synthesis: the one random-field generator of the world and camera.

Used for the terrain heightmap and for the camera's ground textures. White noise is shaped by ``1/f^exponent`` in
the Fourier domain; larger exponents give smoother fields. The result tiles seamlessly.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def fractal_noise(size_px: int, spectral_exponent: float, rng: np.random.Generator) -> NDArray[np.float64]:
    """(size, size) periodic fractal noise with zero mean and unit standard deviation."""
    white = rng.standard_normal((size_px, size_px))
    spectrum = np.fft.rfft2(white)
    fy = np.fft.fftfreq(size_px)[:, None]
    fx = np.fft.rfftfreq(size_px)[None, :]
    f = np.hypot(fx, fy)
    f[0, 0] = 1.0
    spectrum *= f ** (-spectral_exponent)
    spectrum[0, 0] = 0.0
    field = np.fft.irfft2(spectrum, s=(size_px, size_px))
    return (field - field.mean()) / max(float(field.std()), 1e-12)
