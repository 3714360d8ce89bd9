"""What the sensor sees of the scene's 3-D objects, look by look.

The objects' surfaces are sampled once (:class:`ObjectScene`: every sample's position, normal, area
and speckle at slow time 0, :mod:`salkit.simulate.targets` for the shapes, surfaces and sampling)
and seen many times: a look, the sensor's position at a slow time, gives each sample its complex
reflectivity from its material and its incidence, or zero where it faces away or another surface
hides it (a ray cast towards the sensor through Embree, trimesh's own ray casting the fallback).
The same samples and speckle serve every look, so the scene is one surface seen from turning
directions, not a new draw at each.

**Looks over an aperture** (:func:`look_segments`): one look holds while the direction to the
sensor, in the frame of each object, turns by at most :data:`LOOK_TURN_DEG`; an aperture or a
sub-aperture that turns further is cut into runs of pulses that do not, each seen from its middle
pulse (at 5 km SAL's aperture turns by milliradians: one look; a wide-angle or GEO stack, one a
sub-aperture or a few). Glints, whose lobes are far narrower, are evaluated once a look too.

**Spinning objects** (``attitude_rate_deg_s``, an angular velocity w about the object's centre c):
at slow time t a sample at x0 (t = 0) lies at c + R(t) (x0 - c), R(t) the turn by |w| t about w.
Ranges are invariant under turning both ends, so the object's echoes are those of the samples at x0
seen from antenna positions c + R(t)^T (a - c), velocity R^T (v - w x (a - c)) and boresight R^T b
(:func:`object_frame`): its look direction turns with the spin, and its occlusions with it.
"""
from __future__ import annotations

import dataclasses
import math

import lazy_loader as _lazy
import numpy as np

from ..registry import SURFACES
from .targets import _faces, _glint, _material, _retro, _stratified, object_parts

_trimesh = _lazy.load("trimesh", suppress_warning=True)

#: Largest turn of the look direction (deg, in each object's frame) one look holds for.
LOOK_TURN_DEG = 2.0


def spin(rate_deg_s, t: float) -> np.ndarray:
    """The turn of a spinning object after ``t`` seconds: |w| t about w (Rodrigues), (3, 3).

    Parameters
    ----------
    rate_deg_s : (3,) float
        Angular velocity about the scene's x, y, z axes, deg/s.
    t : float
        Slow time, s.

    Returns
    -------
    float64 (3, 3)

    Examples
    --------
    >>> np.round(spin((0.0, 0.0, 90.0), 1.0) @ [1.0, 0.0, 0.0], 12)
    array([0., 1., 0.])
    """
    w = np.radians(np.asarray(rate_deg_s, np.float64))
    ang = float(np.linalg.norm(w)) * float(t)
    if ang == 0.0:
        return np.eye(3)
    k = w / np.linalg.norm(w)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(ang) * K + (1.0 - math.cos(ang)) * (K @ K)


def object_frame(collection, obj):
    """The collection as a spinning object sees it: antenna positions, velocities and boresights
    turned back by the object's spin about its centre (ranges unchanged), the dechirp reference
    as it was.

    Parameters
    ----------
    collection : Collection
    obj : SceneObject

    Returns
    -------
    Collection
    """
    c = np.asarray(obj.position, np.float64)
    w = np.radians(np.asarray(obj.attitude_rate_deg_s, np.float64))
    pos = np.empty_like(collection.positions)
    vel = np.empty_like(collection.velocity)
    bore = np.empty_like(collection.boresight)
    for p, t in enumerate(collection.slow_time):
        Rt = spin(obj.attitude_rate_deg_s, float(t)).T
        rel = collection.positions[p] - c
        pos[p] = c + Rt @ rel
        vel[p] = Rt @ (collection.velocity[p] - np.cross(w, rel))
        bore[p] = Rt @ collection.boresight[p]
    return dataclasses.replace(collection, positions=pos, velocity=vel, boresight=bore)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def look_segments(positions: np.ndarray, slow_time: np.ndarray, objects, max_turn_deg: float = LOOK_TURN_DEG):
    """Runs of pulses over which the look direction to every object, in its own frame (its spin
    undone), turns by at most ``max_turn_deg``.

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions, m.
    slow_time : float64 (P,)
        s.
    objects : sequence of SceneObject
    max_turn_deg : float

    Returns
    -------
    list of (int, int)
        ``(a, b)``: pulses a to b - 1, covering 0 .. P - 1 in order.
    """
    P = positions.shape[0]
    if not objects or P == 0:
        return [(0, P)]
    looks = []
    still = [o for o in objects if not o.spinning]
    if still:
        c = np.mean([o.position for o in still], axis=0)
        looks.append(_unit(positions - c))
    for o in objects:
        if o.spinning:
            c = np.asarray(o.position, np.float64)
            looks.append(_unit(np.stack([spin(o.attitude_rate_deg_s, float(t)).T @ (positions[p] - c)
                                         for p, t in enumerate(slow_time)])))
    U = np.stack(looks)  # (G, P, 3)
    cos_max = math.cos(math.radians(max_turn_deg))
    out, a = [], 0
    while a < P:
        cos = np.einsum("gpk,gk->gp", U[:, a:], U[:, a]).min(axis=0)  # from pulse a on
        beyond = np.nonzero(cos < cos_max)[0]
        b = a + (int(beyond[0]) if beyond.size else P - a)
        out.append((a, max(b, a + 1)))
        a = max(b, a + 1)
    return out


def _hidden(scene, pos: np.ndarray, sensor: np.ndarray) -> np.ndarray:
    """Whether another surface of ``scene`` lies between each point and the sensor (a ray cast from
    just off the point; monostatic: hidden is shadowed)."""
    look = _unit(sensor - pos)
    eps = 1e-6 * float(np.linalg.norm(scene.extents)) + 1e-5
    return scene.ray.intersects_any(pos + eps * look, look)


def scene_mesh(objects, t: float = 0.0, parts=None):
    """Every object's surface at slow time ``t`` (the spinning ones turned), one trimesh.Trimesh in
    the scene frame.

    Parameters
    ----------
    objects : sequence of SceneObject
    t : float
        s.
    parts : list of dict, optional
        :func:`salkit.simulate.targets.object_parts` of each object, when at hand.

    Returns
    -------
    trimesh.Trimesh
    """
    parts = parts if parts is not None else [object_parts(o) for o in objects]
    meshes = []
    for obj, pp in zip(objects, parts):
        R = spin(obj.attitude_rate_deg_s, t) if obj.spinning else None
        for m in pp.values():
            if R is None:
                meshes.append(m)
                continue
            M = np.eye(4)
            M[:3, :3] = R
            M[:3, 3] = np.asarray(obj.position) - R @ np.asarray(obj.position)
            meshes.append(m.copy().apply_transform(M))
    return _trimesh.util.concatenate(meshes)


@dataclasses.dataclass
class _Item:
    owner: int  # the object's index
    mesh: object  # its part at slow time 0, scene frame
    material: object
    first: int  # its samples: first .. last - 1
    last: int
    faces: list | None = None  # a glint's planar faces, one sample each


class ObjectScene:
    """The scene's objects sampled once, seen from any look.

    Parameters
    ----------
    objects : sequence of SceneObject
    cell_area : float
        Resolution cell area, m^2 (the normalisation: a cell of reflectivity T images with power T^2).
    spacing : float
        Sample spacing on the surfaces, m (:data:`salkit.simulate.targets.SAMPLES_PER_CELL` a cell).
    wavelength : float
        m.
    rng : numpy.random.Generator
        The speckle and the rough surfaces' sample positions.
    smooth_phase : callable, optional
        ``smooth_phase(pos) -> rad`` for smooth surfaces that are not glints (they add in phase).

    Attributes
    ----------
    positions : float64 (N, 3)
        Every sample at slow time 0, m.
    owner : int (N,)
        Its object's index in ``objects``.
    """

    def __init__(self, objects, cell_area: float, spacing: float, wavelength: float, rng: np.random.Generator,
                 smooth_phase=None):
        self.objects, self.cell, self.wavelength = tuple(objects), float(cell_area), float(wavelength)
        self.items: list[_Item] = []
        self.parts = [object_parts(o) for o in self.objects]
        pos, nrm, dA, unit = [], [], [], []
        n = 0
        for k, (obj, parts) in enumerate(zip(self.objects, self.parts)):
            for part, mesh in parts.items():
                mat = _material(obj, part)
                if SURFACES.get(mat.kind).glint and not mat.speckle:  # a coherent glint a planar face
                    faces = _faces(mesh)
                    c = np.stack([(mesh.triangles_center[f] * mesh.area_faces[f, None]).sum(0) / mesh.area_faces[f].sum()
                                  for f in faces])
                    pos.append(c)
                    nrm.append(mesh.face_normals[[f[0] for f in faces]])
                    dA.append(np.array([mesh.area_faces[f].sum() for f in faces]))
                    unit.append(np.ones(len(faces), np.complex128))
                    self.items.append(_Item(k, mesh, mat, n, n + len(faces), faces))
                    n += len(faces)
                    continue
                idx, p, a = _stratified(mesh, spacing, rng if mat.speckle else None)
                if mat.speckle:  # circular Gaussian, one draw a sample whatever the looks
                    u = (rng.standard_normal(p.shape[0]) + 1j * rng.standard_normal(p.shape[0])) / math.sqrt(2.0)
                else:
                    u = np.exp(1j * smooth_phase(p)) if smooth_phase is not None else np.ones(p.shape[0], np.complex128)
                pos.append(p)
                nrm.append(mesh.face_normals[idx])
                dA.append(a)
                unit.append(u)
                self.items.append(_Item(k, mesh, mat, n, n + p.shape[0]))
                n += p.shape[0]
        self.positions = np.concatenate(pos) if pos else np.zeros((0, 3))
        self.normals = np.concatenate(nrm) if nrm else np.zeros((0, 3))
        self.area = np.concatenate(dA) if dA else np.zeros(0)
        self.unit = np.concatenate(unit) if unit else np.zeros(0, np.complex128)
        self.owner = np.concatenate([np.full(it.last - it.first, it.owner) for it in self.items]) if self.items \
            else np.zeros(0, int)
        self._still = None  # the objects' mesh at slow time 0 (its ray intersector kept)

    @property
    def n_samples(self) -> int:
        """Samples, facing away and hidden included."""
        return self.positions.shape[0]

    def _turns(self, t: float) -> list:
        return [spin(o.attitude_rate_deg_s, t) if o.spinning else None for o in self.objects]

    def mesh_at(self, t: float):
        """Every object's surface at slow time ``t`` (:func:`scene_mesh`; the still scene's kept
        with its ray intersector).

        Parameters
        ----------
        t : float
            s.

        Returns
        -------
        trimesh.Trimesh
        """
        if not any(o.spinning for o in self.objects):
            if self._still is None:
                self._still = scene_mesh(self.objects, 0.0, self.parts)
            return self._still
        return scene_mesh(self.objects, t, self.parts)

    def world(self, t: float) -> np.ndarray:
        """Every sample's position at slow time ``t``, m (N, 3).

        Parameters
        ----------
        t : float
            s.

        Returns
        -------
        float64 (N, 3)
        """
        out = self.positions.copy()
        for k, (obj, R) in enumerate(zip(self.objects, self._turns(t))):
            if R is not None:
                sel = self.owner == k
                c = np.asarray(obj.position, np.float64)
                out[sel] = c + (self.positions[sel] - c) @ R.T
        return out

    def amplitudes(self, sensor: np.ndarray, t: float = 0.0) -> np.ndarray:
        """Every sample's complex reflectivity seen from ``sensor`` at slow time ``t``: zero where it
        faces away or another surface hides it.

        Parameters
        ----------
        sensor : float64 (3,)
            The sensor's position, m, scene frame.
        t : float
            Slow time, s (the spinning objects' turn).

        Returns
        -------
        complex128 (N,)
        """
        sensor = np.asarray(sensor, np.float64)
        out = np.zeros(self.n_samples, np.complex128)
        turns = self._turns(t)
        for it in self.items:
            obj, R = self.objects[it.owner], turns[it.owner]
            c = np.asarray(obj.position, np.float64)
            s = sensor if R is None else c + R.T @ (sensor - c)  # the sensor in the object's frame at t = 0
            sl = slice(it.first, it.last)
            surf = SURFACES.get(it.material.kind)
            if it.faces is not None:
                for i, tris in enumerate(it.faces):
                    look = _unit(s - self.positions[it.first + i])
                    cos = float(self.normals[it.first + i] @ look)
                    if cos <= 0:
                        continue
                    _, sigma, sign = _glint(it.mesh, tris, look, self.wavelength)
                    if it.material.kind == "retroreflector":
                        sigma = float(_retro(np.array([cos]), it.material)[0] > 0) * 4.0 * math.pi * (
                            self.area[it.first + i] * cos) ** 2 / self.wavelength ** 2
                        sign = 1.0
                    else:
                        sigma *= it.material.reflectance
                    out[it.first + i] = sign * math.sqrt(sigma / self.cell)
                continue
            look = _unit(s - self.positions[sl])
            cos = np.einsum("ij,ij->i", self.normals[sl], look)
            sigma0 = np.where(cos > 0, surf.sigma0(cos, it.material), 0.0)
            if it.material.speckle:  # amplitude^2 = sigma0 dA / cell
                out[sl] = np.sqrt(sigma0 * self.area[sl] / self.cell) * self.unit[sl]
            else:  # amplitudes that add in phase: a cell of sigma0 images with power sigma0
                out[sl] = np.sqrt(sigma0) * self.area[sl] / self.cell * self.unit[sl]
        lit = np.nonzero(out)[0]
        if lit.size:
            hidden = _hidden(self.mesh_at(t), self.world(t)[lit], sensor)
            out[lit[hidden]] = 0.0
        return out


def object_scatterers(objects, sensor: np.ndarray, cell_area: float, spacing: float, wavelength: float,
                      rng: np.random.Generator, smooth_phase=None, t: float = 0.0):
    """Scatterers of the scene's objects seen from ``sensor`` at slow time ``t``: positions (N, 3)
    and complex reflectivities (N,), hidden and back-facing samples removed (one look of an
    :class:`ObjectScene`).

    Parameters
    ----------
    objects : sequence of SceneObject
    sensor : float64 (3,)
        Where the sensor is, m, scene frame.
    cell_area : float
        Resolution cell area, m^2.
    spacing : float
        Sample spacing on the surfaces, m.
    wavelength : float
        m.
    rng : numpy.random.Generator
    smooth_phase : callable, optional
    t : float
        Slow time, s: spinning objects are where their spin has turned them.

    Returns
    -------
    (float64 (N, 3), complex128 (N,))
    """
    scene = ObjectScene(objects, cell_area, spacing, wavelength, rng, smooth_phase)
    amp = scene.amplitudes(sensor, t)
    seen = amp != 0
    return scene.world(t)[seen], amp[seen]


def look_turn_deg(positions: np.ndarray, centre: np.ndarray) -> float:
    """How far the look direction to ``centre`` turns over the aperture (first to last pulse), deg.

    Parameters
    ----------
    positions : float64 (P, 3)
        Antenna positions, m.
    centre : float64 (3,)
        The scene point looked at, m.

    Returns
    -------
    float
    """
    u = _unit(positions - centre)
    return float(np.degrees(np.arccos(np.clip(u[0] @ u[-1], -1.0, 1.0))))


def model_view(objects, sensor: np.ndarray, spacing: float, t: float = 0.0) -> dict:
    """The objects as the sensor sees them at slow time ``t``, for a figure: every surface sample
    projected on the plane across the line of sight (horizontal and vertical axes, m), its
    Lambertian brightness cos theta, and whether it faces away, is hidden (shadowed: monostatic) or
    is seen.

    Parameters
    ----------
    objects : sequence of SceneObject
    sensor : float64 (3,)
        The aperture centre, m.
    spacing : float
        Sample spacing, m.
    t : float
        Slow time, s (spinning objects turned).

    Returns
    -------
    dict
        ``h``, ``v`` (m), the scene-frame ``x``, ``y``, ``z`` (m), ``brightness``, ``state`` (0
        seen, 1 hidden, 2 facing away), ``look`` (the unit line of sight, scene to sensor).
    """
    sensor = np.asarray(sensor, np.float64)
    scene = scene_mesh(objects, t)
    idx, p, _ = _stratified(scene, spacing, None)
    look = _unit(sensor - p)
    cos = np.einsum("ij,ij->i", scene.face_normals[idx], look)
    state = np.where(cos > 0, 0, 2)
    front = np.nonzero(cos > 0)[0]
    hidden = _hidden(scene, p[front], sensor)
    state[front[hidden]] = 1
    lc = sensor / np.linalg.norm(sensor)
    h = np.cross([0.0, 0.0, 1.0], lc)
    h /= np.linalg.norm(h)
    v = np.cross(lc, h)
    return {"h": p @ h, "v": p @ v, "x": p[:, 0], "y": p[:, 1], "z": p[:, 2], "brightness": np.clip(cos, 0, 1),
            "state": state, "look": lc}
