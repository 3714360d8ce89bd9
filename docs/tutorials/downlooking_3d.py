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
# # Seeds 000 and 003: self-interferometric down-looking SAL
#
# The Python API end to end: the optical design of section 5 derived from its requirements, raw
# balanced-detector current simulated from the fields of a point and of an extended "I" scene,
# the forward and backward scans focused, and the eq-19 fringes measured against eq 25.
# `SALKIT_TUTORIAL_CI=1` (the test suite) uses a smaller scene.

# %%
import os

import matplotlib.pyplot as plt
import numpy as np

import salkit
from salkit.geometry.downlooking import design
from salkit.interferometry import fringe_period, interferogram
from salkit.systems.downlooking import extended_run

CI = os.environ.get("SALKIT_TUTORIAL_CI") == "1"
extent = 0.6 if CI else 1.5
sc = salkit.load_scenario(salkit.example_path("downlooking_3d"), [
    "experiment.terrain=null", "scene.extended.pattern=uniform", f"scene.extended.extent=[{extent}, {extent}]"])

# %% [markdown]
# ## The design
# From range 1.8 km, a 7.5 m spot and 1.8 cm resolution the design fixes the magnification, the
# resolution of each axis and the fringe period of eq 25.

# %%
d = design(sc.experiment)
print(f"magnification {d.magnification:.0f}, resolution {d.resolution_x * 1e3:.1f} x {d.resolution_y * 1e3:.1f} mm, "
      f"fringe period (eq 25) {d.fringe_period_x * 1e3:.1f} mm, {d.samples} samples per scan at "
      f"{d.sample_rate / 1e3:.1f} kHz")

# %% [markdown]
# ## A point target: raw current to the eq-19 image
# `salkit.simulate` computes the balanced current of every scan from the optical fields of the
# scenario's point target; `salkit.focus` forms the forward and backward images and adds them
# (eq 19); `salkit.measure` compares the point's response with the design's resolution.

# %%
raw = salkit.simulate(sc)
image = salkit.focus(raw)
m = salkit.measure(image)
print(f"{raw.sizes['scan']} scans of {raw.sizes['fast_time']} samples; IRW across track {m['irw_range_m'] * 1e3:.2f} mm "
      f"(theory {m['irw_range_theory_m'] * 1e3:.2f} mm), along track {m['irw_azimuth_m'] * 1e3:.2f} mm")

# %% [markdown]
# ## An extended scene: the fringes
# A uniform square, imaged in both scan directions; the interferogram of the two images has
# straight fringes whose period is eq 25's.

# %%
_, imgs, _ = extended_run(sc, d, sc.experiment, np.random.default_rng(sc.seed))
ifg = interferogram(imgs.forward.astype(complex), imgs.backward.astype(complex))
per = fringe_period(ifg, imgs.x)
print(f"measured fringe period {per['period_m'] * 1e3:.1f} mm against eq 25's {d.fringe_period_x * 1e3:.1f} mm")
assert abs(per["period_m"] / d.fringe_period_x - 1) < 0.02

# %%
fig, axes = plt.subplots(1, 3, figsize=(12, 3.6), layout="constrained")
ext = [imgs.y[0], imgs.y[-1], imgs.x[0], imgs.x[-1]]
a = np.abs(imgs.forward)
panels = ((20 * np.log10(np.maximum(a / a.max(), 1e-3)), "forward scans (dB)", "gray", None),
          (imgs.combined.real, "eq 19: forward + backward (real part)", "RdBu_r", None),
          (np.angle(ifg), "interferogram phase (rad)", "twilight", (-np.pi, np.pi)))
for ax, (img, t, cmap, lim) in zip(axes, panels):
    im = ax.imshow(img.T, origin="lower", extent=ext, cmap=cmap, **({} if lim is None else dict(vmin=lim[0], vmax=lim[1])))
    ax.set_title(t)
    ax.set_xlabel("along track (m)")
    ax.set_ylabel("cross track (m)")
    fig.colorbar(im, ax=ax, shrink=0.8)
