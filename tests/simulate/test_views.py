"""Objects seen look by look: a spinning object's echoes are those of its samples turned to where the
spin has them at each pulse; a tumbling Lambertian plate returns 4 rho A cos^2 theta at each look and
nothing once it faces away; a wide aperture is cut into looks that each turn at most LOOK_TURN_DEG;
the samples stay on the turned surface and the occlusions turn with it."""
import math

import numpy as np
import pytest

from salkit.params import parse_scenario
from salkit.params.models import SceneObject
from salkit.simulate.echoes import echo_signal
from salkit.simulate.sal import _Echoes
from salkit.simulate.views import (LOOK_TURN_DEG, ObjectScene, look_segments, object_frame, scene_mesh, spin)

from ..conftest import SPOT, merge

LAM = 1.55e-6


def test_spin_is_a_rotation_about_its_axis():
    w = (30.0, -50.0, 80.0)
    R = spin(w, 0.7)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
    assert np.linalg.det(R) == pytest.approx(1.0)
    axis = np.asarray(w) / np.linalg.norm(w)
    np.testing.assert_allclose(R @ axis, axis, atol=1e-14)  # the axis stays
    turn = math.degrees(math.acos((np.trace(R) - 1) / 2))
    assert turn == pytest.approx(np.linalg.norm(w) * 0.7, rel=1e-12)
    np.testing.assert_allclose(spin(w, 0.3) @ spin(w, 0.4), R, atol=1e-14)  # a constant rate composes


def test_a_spinning_objects_echoes_are_its_turned_scatterers():
    """Three corner cubes on a spinning plate, 25 deg/s about a tilted axis (the aperture lasts
    0.01 s: 0.25 deg): the simulator's echoes, formed in the object's frame, against each pulse's
    echoes of the corner cubes placed where the spin has them (the scene frame)."""
    retro = {"kind": "retroreflector", "reflectance": 1.0, "speckle": False}
    objs = [{"shape": "plate", "size": [0.01, 0.01], "position": list(p), "attitude_deg": [0, 0, 53.13],
             "attitude_rate_deg_s": [5.0, -8.0, 25.0], "material": retro}
            for p in ([0.2, 0.1, 0.0], [-0.15, 0.05, 0.1], [0.0, -0.2, 0.05])]
    sc = parse_scenario(merge(SPOT, scene={"objects": objs}))
    job = _Echoes(sc, np.random.default_rng(0))
    got = job.block(0, job.col.n_pulses, noise=False)
    assert len(job.looks) == 1 and len(job.groups[0]) == 4  # the still group (empty) and one a spinning object
    want = np.zeros_like(got)
    col = job.col
    for obj, pos, amp in job.groups[0][1:]:
        c = np.asarray(obj.position)
        for p in range(col.n_pulses):
            R = spin(obj.attitude_rate_deg_s, float(col.slow_time[p]))
            one = job._pulses(p, p + 1)
            want[p] += echo_signal(one, c + (pos - c) @ R.T, amp, sc, job.t)[0]
    assert np.abs(want).max() > 0
    assert np.max(np.abs(got - want)) < 1e-5 * np.abs(want).max()
    # and the frame is the turn undone: ranges and the beam's angles unchanged
    obj = job.groups[0][1][0]
    seen = object_frame(col, obj)
    p = col.n_pulses - 1
    R = spin(obj.attitude_rate_deg_s, float(col.slow_time[p]))
    x0 = np.array([0.3, -0.1, 0.2])
    x = np.asarray(obj.position) + R @ (x0 - np.asarray(obj.position))
    assert np.linalg.norm(seen.positions[p] - x0) == pytest.approx(np.linalg.norm(col.positions[p] - x), rel=1e-14)
    assert seen.boresight[p] @ (x0 - seen.positions[p]) == pytest.approx(col.boresight[p] @ (x - col.positions[p]),
                                                                         rel=1e-12)


def test_a_tumbling_plate_follows_its_cosine_law_look_by_look():
    """A Lambertian plate tumbling about x at 2000 deg/s: its normal sweeps 20 deg over the 0.01 s
    aperture, cut into looks of at most LOOK_TURN_DEG; at each look the samples' power sums to
    4 rho A cos^2 theta / cell (within 3 %), and to nothing once the plate faces away."""
    rho, A, cell = 0.5, 0.25, 0.015 ** 2
    obj = SceneObject(shape="plate", size=(0.5, 0.5), attitude_deg=(0.0, 0.0, 0.0), attitude_rate_deg_s=(2000.0, 0, 0),
                      material={"kind": "lambertian", "reflectance": rho})
    sc = parse_scenario(merge(SPOT, scene={"objects": [obj.model_dump()]}))
    job = _Echoes(sc, np.random.default_rng(0))
    col = job.col
    looks = look_segments(col.positions, col.slow_time, [obj])
    turn = 2000.0 * (col.slow_time[-1] - col.slow_time[0])
    assert len(looks) == pytest.approx(turn / LOOK_TURN_DEG, abs=1.5)
    scene = ObjectScene([obj], cell, 0.0075, LAM, np.random.default_rng(1))
    for a, b in looks:
        u = col.positions[a:b] - np.asarray(obj.position)
        for p in (a, b - 1):  # every pulse of a look within LOOK_TURN_DEG of its first, in the plate's frame
            R = spin(obj.attitude_rate_deg_s, float(col.slow_time[p]))
            v0 = spin(obj.attitude_rate_deg_s, float(col.slow_time[a])).T @ u[0]
            v = R.T @ u[p - a]
            assert math.degrees(math.acos(min(1.0, v0 @ v / np.linalg.norm(v0) / np.linalg.norm(v)))) <= LOOK_TURN_DEG + 1e-9
        m = (a + b - 1) // 2
        t = float(col.slow_time[m])
        n = spin(obj.attitude_rate_deg_s, t) @ [0.0, 0.0, 1.0]
        look = col.positions[m] / np.linalg.norm(col.positions[m])
        cos = float(n @ look)
        power = np.sum(np.abs(scene.amplitudes(col.positions[m], t)) ** 2)
        theory = 4 * rho * A * max(cos, 0.0) ** 2 / cell
        assert power == pytest.approx(theory, rel=0.03, abs=1e-9)
    # facing away: turned 180 deg the plate returns nothing
    back = scene.amplitudes(col.positions[0], 180.0 / 2000.0)
    assert not np.any(back)


def test_a_wide_aperture_is_seen_look_by_look():
    arc = np.radians(np.linspace(-3.5, 3.5, 701))  # a 7 degree arc at 45 deg elevation
    pos = 5000.0 * np.stack([np.sin(arc), -np.cos(arc), np.ones_like(arc)], axis=1)
    box = SceneObject(shape="box", size=(1, 1, 1), position=(0, 0, 0.5))
    looks = look_segments(pos, np.linspace(-1, 1, 701), [box])
    u = (pos - [0, 0, 0.5]) / np.linalg.norm(pos - [0, 0, 0.5], axis=1)[:, None]
    turn = math.degrees(math.acos(u[0] @ u[-1]))  # 4.95 deg: the arc seen from 45 deg elevation
    assert len(looks) == math.ceil(turn / LOOK_TURN_DEG) == 3 and looks[0][0] == 0 and looks[-1][1] == 701
    assert all(b0 == a1 for (_, b0), (a1, _) in zip(looks[:-1], looks[1:]))
    assert look_segments(pos, np.linspace(-1, 1, 701), []) == [(0, 701)]


def test_samples_stay_on_the_turned_surface_and_the_shadows_turn():
    """A box spinning about z over a still plate: the samples at t lie on the mesh at t, and the
    plate's hidden samples (under and behind the box) follow the box's turn."""
    box = SceneObject(shape="box", size=(0.6, 0.2, 0.4), position=(0, 0, 0.2), attitude_rate_deg_s=(0, 0, 90.0),
                      material={"kind": "lambertian", "reflectance": 0.5})
    plate = SceneObject(shape="plate", size=(2.0, 2.0), material={"kind": "lambertian", "reflectance": 0.5})
    scene = ObjectScene([box, plate], 1e-4, 0.02, LAM, np.random.default_rng(0))
    sensor = np.array([0.0, -4000.0, 3000.0])
    for t in (0.0, 0.5, 1.0):
        mesh = scene_mesh([box, plate], t)
        x = scene.world(t)[::97]
        inside = (mesh.triangles[:, 0][None] - x[:, None]) @ np.eye(3)  # each sample against each face's plane
        dist = np.abs(np.einsum("stk,tk->st", inside, mesh.face_normals)).min(axis=1)
        assert dist.max() < 1e-9 and np.all(np.abs(x) <= 1.0 + 1e-9)
    on_plate = scene.owner == 1
    hidden = [on_plate & (scene.amplitudes(sensor, t) == 0) for t in (0.0, 1.0)]
    x = scene.positions[:, 0]
    width = [np.ptp(x[h]) for h in hidden]  # the shadow's extent across the line of sight
    assert width[0] == pytest.approx(0.6, abs=0.05) and width[1] == pytest.approx(0.2, abs=0.05)
