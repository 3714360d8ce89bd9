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
# # Seed 001: space-borne SAL of a GEO target, photon-limited sub-images and stacking
#
# The Python API end to end: the pass geometry from the two orbits, squinted sub-apertures of the
# same target, one photon-limited sub-image against eq 15, and the incoherent stack whose SNR grows
# as sqrt(P). `SALKIT_TUTORIAL_CI=1` (the test suite) stacks fewer sub-images.

# %%
import os

import matplotlib.pyplot as plt
import numpy as np
from scipy.ndimage import binary_erosion

import salkit
from salkit.geometry.collection import grid_axes
from salkit.metrics.snr import split_snr, stack_snr
from salkit.stack import geo_base, nearest_squints, subimage
from salkit.systems.spaceborne import collection_metrics, truth_image

CI = os.environ.get("SALKIT_TUTORIAL_CI") == "1"
scenario = salkit.load_scenario(salkit.example_path("spaceborne_geo"))

# %% [markdown]
# ## The pass
# `geo_base` turns the experiment (two circular orbits) into one sub-aperture's scenario: the
# relative speed V, the closest distance L0 and the sub-aperture length for the 5 cm resolution.

# %%
metrics, squints = collection_metrics(scenario)
base = geo_base(scenario)
print(f"V = {metrics['relative_speed_m_s']:.3f} m/s, L0 = {metrics['closest_distance_m'] / 1e3:.0f} km, "
      f"sub-aperture {metrics['subaperture_length_m']:.2f} m, {metrics['subimages_in_collection']} sub-images")

# %% [markdown]
# ## One sub-image, with and without photon noise
# Eq 15 of the seed gives the single-look SNR at N_s = 0.5 signal photons per sample: 1/3 for a
# uniform area. The satellite's edges lower the measured value a little (docs/spaceborne.md).

# %%
az, rg = grid_axes(base.processing.grid)
truth = truth_image(base, az, rg)
mask = binary_erosion(truth > 0.5 * truth.max(), iterations=2)
noisy, clean = subimage(base, 0.0, 0, noise=True), subimage(base, 0.0, 0, noise=False)
snr1 = stack_snr(np.abs(noisy) ** 2, np.abs(clean) ** 2, mask)
print(f"single sub-image SNR {snr1:.3f} (eq 15: {base.receiver.noise.snr_theory:.3f})")

# %% [markdown]
# ## The stack
# Sub-images at the squints nearest closest approach, each with its own photon noise, averaged in
# intensity on the common grid. The SNR is measured from two independent half-stacks.

# %%
count = 8 if CI else 64
qs = nearest_squints(count, metrics["subaperture_length_m"], metrics["closest_distance_m"])
intens = np.stack([np.abs(subimage(base, q, i, noise=True)) ** 2 for i, q in enumerate(qs)])
noise_power = np.mean(np.abs(noisy - clean)[mask] ** 2)
snr_p = split_snr(intens, mask, noise_power)
print(f"stack of {count}: SNR {snr_p:.2f}, gain {snr_p / snr1:.2f} against sqrt(P) = {np.sqrt(count):.2f}")

fig, axes = plt.subplots(1, 3, figsize=(11, 3.2), layout="constrained")
ext = [az[0], az[-1], rg[0], rg[-1]]
for ax, img, t in zip(axes, (truth, np.abs(noisy) ** 2, intens.mean(axis=0)),
                      ("truth", "one sub-image", f"stack of {count}")):
    ax.imshow(img.T / np.percentile(img, 99.5), origin="lower", extent=ext, cmap="gray", vmin=0, vmax=1)
    ax.set_title(t)
    ax.set_xlabel("along track (m)")
    ax.set_ylabel("range (m)")
