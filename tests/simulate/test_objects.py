"""Scene objects declared once: the built-in kinds, patterns and materials, their checks in the
scenario, and a kind and a material declared here alone simulated through a scenario (the recipe
of docs/architecture.md)."""
import numpy as np
import pytest

from salkit import focus, simulate
from salkit.errors import ScenarioError
from salkit.params import parse_scenario
from salkit.params.models import ExtendedScene
from salkit.registry import MATERIALS, OBJECT_KINDS, PATTERNS
from salkit.simulate.objects import declare_material, declare_object_kind, load_image
from salkit.simulate.scene import extended_scatterers, material_of

from ..conftest import SPOT, merge


def test_the_built_in_declarations():
    assert set(OBJECT_KINDS.names()) >= {"pattern", "image"}
    assert set(PATTERNS.names()) >= {"letter_I", "bars", "checker", "disk", "uniform", "satellite"}
    assert {n: MATERIALS[n].speckle for n in ("diffuse", "smooth")} == {"diffuse": True, "smooth": False}
    u, v = np.meshgrid(np.linspace(-0.5, 0.5, 64), np.linspace(-0.5, 0.5, 64), indexing="ij")
    for name, p in PATTERNS.items():
        m = p.mask(u, v)
        assert m.shape == u.shape and 0 <= m.min() and m.max() <= 1, name


def test_the_scenario_checks_against_the_declarations():
    with pytest.raises(ValueError, match="is not a declared pattern .did you mean 'letter_I'"):
        ExtendedScene(extent=(1, 1), spacing=0.1, pattern="letter_i")
    with pytest.raises(ValueError, match="is not a declared scene object kind"):
        ExtendedScene(extent=(1, 1), spacing=0.1, kind="mesh")
    with pytest.raises(ValueError, match="kind=image needs a file"):
        ExtendedScene(extent=(1, 1), spacing=0.1, kind="image")
    with pytest.raises(ValueError, match="give one of the two"):
        ExtendedScene(extent=(1, 1), spacing=0.1, material="smooth", speckle=True)
    e = ExtendedScene(extent=(1, 1), spacing=0.1, material="smooth")
    assert e.speckle is False and material_of(e) == "smooth"
    assert material_of(ExtendedScene(extent=(1, 1), spacing=0.1)) == "diffuse"
    with pytest.raises(ScenarioError, match="scene.extended.file"):
        load_image("/nonexistent.png")


def test_a_material_keeps_the_cell_power():
    """Diffuse: mean power T^2 per resolution cell over many cells; smooth: amplitude T per cell."""
    cell = 0.02 * 0.02
    rough = ExtendedScene(pattern="uniform", extent=(1.0, 1.0), spacing=0.005, material="diffuse")
    _, amp = extended_scatterers(rough, cell, np.random.default_rng(0))
    assert np.sum(np.abs(amp) ** 2) * cell == pytest.approx(1.0, rel=0.05)
    flat = ExtendedScene(pattern="uniform", extent=(1.0, 1.0), spacing=0.005, material="smooth")
    _, amp = extended_scatterers(flat, cell, np.random.default_rng(0))
    assert np.sum(np.abs(amp)) * cell == pytest.approx(1.0, rel=0.02)  # amplitude 1 in each of the 1/cell cells


@pytest.fixture
def ring_and_glass():
    declare_object_kind("ring", summary="a thin ring (a test's kind)", needs=(),
                        reflectivity=lambda ext, u, v: ((np.hypot(u, v) > 0.3) & (np.hypot(u, v) < 0.4)).astype(float))

    def glass(pos, t, spacing, cell_area, rng, smooth_phase):  # half the smooth amplitude, no speckle
        return pos, (0.5 * t * spacing ** 2 / cell_area).astype(np.complex128) * np.exp(1j * smooth_phase(pos))
    declare_material("glass", summary="half as bright as smooth (a test's material)", speckle=False, scatter=glass)
    yield
    OBJECT_KINDS.remove("ring")
    MATERIALS.remove("glass")


def test_the_recipe_a_kind_and_a_material_declared_are_simulated(ring_and_glass):
    images = {}
    for material in ("glass", "smooth"):
        ext = {"kind": "ring", "material": material, "extent": [0.5, 0.5], "spacing": 0.004}
        sc = parse_scenario(merge(SPOT, scene={"extended": ext}))
        images[material] = focus(simulate(sc), scenario=sc)
    img = np.abs(images["glass"]["image"].values)
    az, rg = np.meshgrid(images["glass"]["azimuth"].values, images["glass"]["range"].values, indexing="ij")
    r = np.hypot(az / 0.5, rg / 0.5)
    on, off = img[(r > 0.32) & (r < 0.38)].mean(), img[r < 0.2].mean()
    assert off < 0.1 * on  # the ring is bright where the kind puts it, dark inside
    ratio = np.abs(images["glass"]["image"].values).max() / np.abs(images["smooth"]["image"].values).max()
    assert ratio == pytest.approx(0.5, rel=1e-4)  # the material's amplitude, everything else the same
