# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Seed 004: spotlight SAL through turbulence, and phase gradient autofocus
#
# The Python API end to end: phase screens checked against Kolmogorov theory, a point target
# imaged through a turbulent path, measured against the diffraction limit, and restored by PGA.
# Open with `jupytext --to notebook docs/tutorials/turbulence_pga.py`, or run as a script.
# `SALKIT_TUTORIAL_CI=1` (the test suite) uses smaller ensembles.

# %%
import os

import matplotlib.pyplot as plt
import numpy as np

import salkit
from salkit.atmosphere import phase_screens, structure_function, structure_function_estimate
from salkit.autofocus import autofocus

CI = os.environ.get("SALKIT_TUTORIAL_CI") == "1"
EXAMPLE = salkit.example_path("turbulence_pga")

# %% [markdown]
# ## Phase screens
# An ensemble of FFT screens with subharmonics, r0 = 5 cm on a 1 cm grid. Its ensemble structure
# function should follow 6.88 (r / r0)^(5/3).

# %%
r0, dx, n = 0.05, 0.01, 64
screens = phase_screens(n, dx, r0, count=40 if CI else 400, seed=1)
r, d, err = structure_function_estimate(screens, dx)
theory = structure_function(r, r0)
print("largest deviation from theory, 2 samples to n/4:", f"{np.max(np.abs(d[1:] / theory[1:] - 1)):.1%}")
fig, ax = plt.subplots(figsize=(5, 3.5), layout="constrained")
ax.errorbar(r * 100, d, yerr=err, fmt="o", ms=3, label="ensemble")
ax.plot(r * 100, theory, "k-", label="6.88 (r/r0)^(5/3)")
ax.set_xlabel("separation (cm)")
ax.set_ylabel("D(r) (rad$^2$)")
ax.legend()

# %% [markdown]
# ## A point target with and without turbulence
# The shipped scenario (2 um, 10 km, 15 GHz, 0.5 m aperture, PFA) with its point target, imaged
# through the medium class Cn2 = 1e-14 m^(-2/3) over 50 frozen layers, then without turbulence.

# %%
def image(cn2):
    sets = ["experiment=null"] + ([f"atmosphere.cn2={cn2}"] if cn2 else ["atmosphere=null"])
    sc = salkit.load_scenario(EXAMPLE, sets)
    raw = salkit.simulate(sc)
    return salkit.focus(raw, sc.processing, scenario=sc)


clean, turbulent = image(0.0), image(1e-14)
m0, m1 = salkit.measure(clean), salkit.measure(turbulent)
print(f"azimuth IRW: clean {m0['irw_azimuth_m'] * 100:.3f} cm (theory {m0['irw_azimuth_theory_m'] * 100:.3f} cm), "
      f"turbulent {m1['irw_azimuth_m'] * 100:.3f} cm")
print(f"peak: turbulent / clean = {m1['peak_amplitude'] / m0['peak_amplitude']:.2f}")

# %% [markdown]
# ## Phase gradient autofocus
# PGA estimates the turbulence's phase error along the aperture from the image itself.

# %%
fixed, res = autofocus(turbulent, "pga", kernel="lumv", max_iter=20)
m2 = salkit.measure(fixed)
print(f"after PGA ({len(res.history) - 1} iterations): IRW {m2['irw_azimuth_m'] * 100:.3f} cm, "
      f"peak / clean = {m2['peak_amplitude'] / m0['peak_amplitude']:.2f}")
assert m2["peak_amplitude"] > m1["peak_amplitude"]

fig, axes = plt.subplots(1, 3, figsize=(11, 3.4), layout="constrained")
for ax, ds, t in zip(axes, (clean, turbulent, fixed), ("no turbulence", "Cn2 = 1e-14", "after PGA")):
    a = np.abs(ds["image"].values)
    im = ax.imshow(20 * np.log10(np.maximum(a / a.max(), 1e-3)).T, origin="lower", cmap="gray", vmin=-30,
                   extent=[ds["azimuth"][0], ds["azimuth"][-1], ds["range"][0], ds["range"][-1]])
    ax.set_title(t)
    ax.set_xlabel("azimuth (m)")
    ax.set_ylabel("range (m)")
fig.colorbar(im, ax=axes, label="dB")
