"""3-D objects against theory: a smooth plate's glint follows its physical-optics sinc^2 lobe (first
null at lambda / 2L) against the integral evaluated point by point; a Lambertian sphere returns
sigma = 8 pi rho r^2 / 3 (cos^2 theta per unit area, the hidden half removed); a rough plate's image
has speckle contrast 1 and exponential intensities; a box's shadow on a plate is 30 dB below the
lit plate; a point on the box top appears where its range puts it (layover)."""
import math

import numpy as np
import pytest
from scipy import stats

from salkit import focus, simulate
from salkit.errors import ScenarioError
from salkit.params import parse_scenario
from salkit.params.models import SceneObject
from salkit.registry import SHAPES, SURFACES
from salkit.simulate.targets import _glint, _plate, object_parts
from salkit.simulate.views import object_scatterers

from ..conftest import SPOT, merge

LAM = 1.55e-6


def test_the_glint_is_the_physical_optics_integral():
    a = 40 * LAM  # small enough to integrate at lambda / 12 a sample
    mesh = _plate([a, a])
    step = LAM / 12
    u = (np.arange(int(a / step)) + 0.5) * step - a / 2
    X, Y = np.meshgrid(u, u, indexing="ij")
    null = LAM / (2 * a)
    for s in np.array([0.0, 0.3, 0.6, 0.9, 1.0, 1.4]) * null:  # look tilted in x-z by asin(s)
        look = np.array([s, 0.0, math.sqrt(1 - s * s)])
        direct = abs(np.sum(np.exp(2j * 2 * np.pi / LAM * (look[0] * X + look[1] * Y)))) * step ** 2 * look[2]
        _, sigma, _ = _glint(mesh, np.array([0, 1]), look, LAM)
        po = math.sqrt(sigma * LAM ** 2 / (4 * math.pi))
        assert po == pytest.approx(direct, abs=0.05 * a * a)
    _, at_null, _ = _glint(mesh, np.array([0, 1]), np.array([null, 0.0, math.sqrt(1 - null ** 2)]), LAM)
    _, at_zero, _ = _glint(mesh, np.array([0, 1]), np.array([0.0, 0.0, 1.0]), LAM)
    assert at_null < 1e-6 * at_zero and at_zero == pytest.approx(4 * math.pi * a ** 4 / LAM ** 2, rel=1e-9)


def test_a_lambertian_sphere_returns_its_cosine_law_integral():
    r, rho, cell = 0.5, 0.4, 0.02 * 0.02
    obj = SceneObject(shape="sphere", size=(2 * r,), material={"kind": "lambertian", "reflectance": rho})
    sensor = np.array([0.0, -4000.0, 3000.0])
    pos, amp = object_scatterers([obj], sensor, cell, 0.01, LAM, np.random.default_rng(0))
    assert np.sum(np.abs(amp) ** 2) * cell == pytest.approx(8 * math.pi * rho * r * r / 3, rel=0.05)
    look = sensor / np.linalg.norm(sensor)
    assert np.all(pos @ look > -0.05)  # only the lit half (to a facet of the icosphere: 0.04 m)


BOX = [{"shape": "plate", "size": [1.0, 1.0], "material": {"kind": "lambertian", "reflectance": 0.5}},
       {"shape": "box", "size": [0.2, 0.2, 0.3], "position": [0.1, 0.1, 0.15],
        "material": {"kind": "lambertian", "reflectance": 0.5}}]


def _image(objs, window="taylor", sll=35.0, nbar=4):
    grid = {"nx": 256, "ny": 256, "dx": 0.005, "dy": 0.005, "plane": "ground"}
    sc = parse_scenario(merge(SPOT, scene={"objects": objs}, processing={**SPOT["processing"], "grid": grid,
                                                                         "window": window, "taylor_sll": sll,
                                                                         "taylor_nbar": nbar}))
    img = focus(simulate(sc), scenario=sc)
    az, rg = np.meshgrid(img["azimuth"].values, img["range"].values, indexing="ij")
    return sc, np.abs(img["image"].values) ** 2, az, rg


def test_a_rough_plates_speckle_is_fully_developed():
    objs = [{"shape": "plate", "size": [2.0, 2.0], "material": {"kind": "lambertian", "reflectance": 0.5}}]
    grid = {"nx": 400, "ny": 400, "dx": 0.005, "dy": 0.005, "plane": "ground"}
    sc = parse_scenario(merge(SPOT, scene={"objects": objs}, processing={**SPOT["processing"], "grid": grid},
                              simulation={"method": "nufft"}))
    I = np.abs(focus(simulate(sc), scenario=sc)["image"].values) ** 2
    smooth = [{**objs[0], "material": {**objs[0]["material"], "speckle": False}}]  # its mean: beam and cos^2
    sc0 = parse_scenario(merge(SPOT, scene={"objects": smooth}, processing={**SPOT["processing"], "grid": grid},
                               simulation={"method": "nufft"}))
    mean = np.abs(focus(simulate(sc0), scenario=sc0)["image"].values) ** 2
    sample = (I / mean)[40:-40:4, 40:-40:4].ravel()  # 2 cm apart (the resolution): nearly independent
    assert np.std(sample) / np.mean(sample) == pytest.approx(1.0, abs=0.05)
    assert stats.kstest(sample / np.mean(sample), "expon").pvalue > 0.01


def test_the_box_shadows_the_plate_30_db():
    """The shadow a 0.3 m box casts on a plate, 37 degrees above the horizon: 0.4 m long behind it,
    below the lit plate by more than 30 dB (measured -39 dB with a 50 dB Taylor window: the image's
    own sidelobes from the lit plate around it set that floor, -28 dB with a 35 dB window)."""
    objs = [{"shape": "plate", "size": [1.2, 1.2], "material": {"kind": "lambertian", "reflectance": 0.5}},
            {"shape": "box", "size": [0.3, 0.2, 0.3], "position": [0.0, -0.2, 0.15],
             "material": {"kind": "lambertian", "reflectance": 0.5}}]
    sc, I, az, rg = _image(objs, sll=50.0, nbar=6)
    elev = math.atan2(sc.platform.altitude, sc.platform.standoff)
    assert 0.3 / math.tan(elev) == pytest.approx(0.4)  # the shadow's length behind the box's far face at y = -0.1
    lit = (np.abs(az) > 0.3) & (np.abs(az) < 0.55) & (np.abs(rg) < 0.4)
    shadow = (np.abs(az) < 0.08) & (rg > 0.05) & (rg < 0.25)
    assert 10 * np.log10(I[shadow].mean() / I[lit].mean()) < -30


def test_a_point_on_the_box_top_lies_over_where_its_range_puts_it():
    retro = {"shape": "plate", "size": [0.01, 0.01], "position": [0.1, 0.1, 0.3001], "attitude_deg": [0, 0, 53.13],
             "material": {"kind": "retroreflector", "reflectance": 1.0, "speckle": False}}
    sc, I, az, rg = _image(BOX + [retro])
    S = np.array([0.0, -sc.platform.standoff, sc.platform.altitude])
    top = np.array([0.1, 0.1, 0.3001])
    R = np.linalg.norm(S - top)
    y = S[1] + math.sqrt(R ** 2 - S[2] ** 2 - (top[0] - S[0]) ** 2)  # the ground point of the same range
    i, j = np.unravel_index(np.argmax(I), I.shape)
    assert abs(az[i, j] - top[0]) <= 0.005 and abs(rg[i, j] - y) <= 0.005  # within a pixel
    assert y < top[1] - 0.2  # laid over towards the sensor by h / tan(elevation)


def test_shapes_meshes_and_refusals(tmp_path):
    assert set(SHAPES.names()) >= {"box", "plate", "sphere", "cylinder", "satellite", "vehicle"}
    assert set(SURFACES.names()) == {"lambertian", "specular", "retroreflector"}
    parts = object_parts(SceneObject(shape="satellite", size=(4.0, 2.0, 2.0), position=(1, 2, 3)))
    assert set(parts) == {"bus", "panels", "booms", "dish"}
    box = object_parts(SceneObject(shape="box", size=(1, 2, 3)))["body"]
    box.export(tmp_path / "box.stl")
    again = object_parts(SceneObject(mesh=str(tmp_path / "box.stl")))["body"]
    assert again.area == pytest.approx(box.area, rel=1e-9)
    with pytest.raises(ValueError, match="give exactly one of shape and mesh"):
        SceneObject()
    with pytest.raises(ValueError, match="is not a declared shape"):
        SceneObject(shape="torus")
    with pytest.raises(ValueError, match="mesh = .*: file does not exist"):
        SceneObject(mesh=str(tmp_path / "missing.stl"))
    (tmp_path / "bad.stl").write_text("not a mesh")
    with pytest.raises(ScenarioError, match="scene.objects.mesh"):
        object_parts(SceneObject(mesh=str(tmp_path / "bad.stl")))


def test_the_model_seen_from_the_sensor():
    from salkit.simulate.views import model_view
    sensor = np.array([0.0, -4000.0, 3000.0])
    box = model_view([SceneObject(shape="box", size=(1, 1, 1), position=(0, 0, 0.5))], sensor, 0.05)
    assert [np.mean(box["state"] == k) for k in (0, 1, 2)] == pytest.approx([1 / 3, 0.0, 2 / 3], abs=1e-9)
    scene = [SceneObject(shape="plate", size=(4, 4)), SceneObject(shape="box", size=(1, 1, 1), position=(0, 0, 0.5))]
    v = model_view(scene, sensor, 0.05)
    ground = (v["z"] < 1e-9) & (v["state"] == 1)  # under the box, and its shadow behind it: 1 / tan(37 deg) long
    assert v["y"][ground].min() == pytest.approx(-0.5, abs=0.05) and v["y"][ground].max() == pytest.approx(0.5 + 4 / 3, abs=0.05)
