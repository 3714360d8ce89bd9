"""3-D objects of a scene (``scene.objects``): built-in shapes or mesh files (trimesh), placed,
turned and scaled, their surfaces sampled into scatterers (:mod:`salkit.simulate.views` sees them
from each look).

**Shapes** (:data:`salkit.registry.SHAPES`, declared here): ``box``, ``plate``, ``sphere``,
``cylinder`` and two procedural models, ``satellite`` (a bus, two solar panels on booms, a dish) and
``vehicle`` (a body, a cabin, four wheels); named parts take materials of their own.

**Surfaces** (:data:`salkit.registry.SURFACES`): the monostatic backscatter of a surface element
of area dA at incidence theta (cos theta = n . l, l towards the sensor), per unit area,

- ``lambertian``: sigma0 = 4 rho cos^2 theta (Lambert's radiance: irradiance cos theta, projected
  area cos theta);
- ``specular``: rough, Kirchhoff's geometric-optics lobe about the mirror direction for an rms slope
  s, sigma0 = R exp(-tan^2 theta / s^2) / (s^2 cos^4 theta); smooth (``speckle: false``), the
  coherent glint of each planar face, its physical-optics return (4 pi / lambda^2)
  |cos theta int e^{j 2 k l.r} dA|^2 R, a rectangle a x b giving (a b)^2 sinc^2(2 a u_a / lambda)
  sinc^2(2 b u_b / lambda) (first null at lambda / 2a);
- ``retroreflector``: a corner cube of aperture A returns 4 pi (A cos theta)^2 R / lambda^2 towards
  the sensor from any incidence within 45 degrees.

**Scatterers**: each face is sampled at :data:`SAMPLES_PER_CELL` samples a resolution cell (the
spacing half the finer resolution, in three dimensions: on any face, whatever its tilt), each
sample's amplitude^2 = sigma0 dA / cell (the extended scenes' normalisation: a cell of reflectivity
T has image power T^2), circular Gaussian for rough surfaces, phase-aligned for smooth non-glint
ones (amplitude sqrt(sigma0) dA / cell: a cell of them images with power sigma0). Samples facing away (cos theta <= 0) and samples another surface hides from the sensor (a ray
cast from each towards the sensor with Embree through embreex, trimesh's own ray casting as the
fallback) are removed: in a monostatic system what is hidden is what is shadowed, and layover
falls where the 3-D positions put it. One look holds while the look direction turns by at most
:data:`salkit.simulate.views.LOOK_TURN_DEG`; apertures that turn further, and spinning objects,
are seen look by look (:mod:`salkit.simulate.views`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import lazy_loader as _lazy
import numpy as np

from ..geometry.collection import rotation
from ..io.meshes import read_mesh_parts
from ..registry import SHAPES, SURFACES

_trimesh = _lazy.load("trimesh", suppress_warning=True)

#: Samples a resolution cell on every face (its spacing half the finer resolution).
SAMPLES_PER_CELL = 4


@dataclass(frozen=True)
class Shape:
    """A built-in 3-D shape.

    Attributes
    ----------
    name, summary : str
    parts : tuple of str
        Its named parts (``scene.objects[].parts`` keys).
    build : callable
        ``build(size) -> {part: trimesh.Trimesh}``, centred on the origin, m.
    """

    name: str
    summary: str
    parts: tuple
    build: Callable


@dataclass(frozen=True)
class Surface:
    """A surface kind: how an element scatters back to the sensor.

    Attributes
    ----------
    name, summary : str
    sigma0 : callable
        ``sigma0(cos_theta, material) -> float ndarray``: rough backscatter per unit area.
    glint : bool
        Smooth (``speckle: false``) surfaces of this kind return a coherent glint a planar face.
    """

    name: str
    summary: str
    sigma0: Callable
    glint: bool


def declare_shape(name: str, **declaration) -> Shape:
    """Declare a built-in shape.

    Parameters
    ----------
    name : str
    **declaration
        The other fields of :class:`Shape` (all required).

    Returns
    -------
    Shape
    """
    return SHAPES.declare(Shape, name, **declaration)


def declare_surface(name: str, **declaration) -> Surface:
    """Declare a surface kind.

    Parameters
    ----------
    name : str
    **declaration
        The other fields of :class:`Surface` (all required).

    Returns
    -------
    Surface
    """
    return SURFACES.declare(Surface, name, **declaration)


# ---------------------------------------------------------------- surfaces
def _lambertian(cos, mat):
    return 4.0 * mat.reflectance * cos ** 2


def _specular(cos, mat):
    s = max(mat.roughness, 1e-3)
    c = np.clip(cos, 1e-6, 1.0)
    tan2 = (1.0 - c * c) / (c * c)
    return mat.reflectance * np.exp(-tan2 / (s * s)) / (s * s * c ** 4)


def _retro(cos, mat):
    return np.where(cos > math.cos(math.radians(45.0)), mat.reflectance, 0.0)  # its return is the part's glint


declare_surface("lambertian", summary="diffuse: sigma0 = 4 rho cos^2 theta", sigma0=_lambertian, glint=False)
declare_surface("specular", summary="a lobe about the mirror direction (rms slope), a glint when smooth",
                sigma0=_specular, glint=True)
declare_surface("retroreflector", summary="a corner cube: 4 pi (A cos theta)^2 R / lambda^2 within 45 deg",
                sigma0=_retro, glint=True)


# ---------------------------------------------------------------- shapes
def _plate(size):
    x, y = float(size[0]), float(size[1] if len(size) > 1 else size[0])
    v = np.array([[-x / 2, -y / 2, 0.0], [x / 2, -y / 2, 0.0], [x / 2, y / 2, 0.0], [-x / 2, y / 2, 0.0]])
    return _trimesh.Trimesh(vertices=v, faces=[[0, 1, 2], [0, 2, 3]], process=False)  # one-sided, normal +z


def _box(size):
    s = list(size) + [size[-1]] * (3 - len(size))
    return _trimesh.creation.box(extents=s[:3])


def _sphere(size):
    return _trimesh.creation.icosphere(subdivisions=3, radius=float(size[0]) / 2)


def _cylinder(size):
    d, h = float(size[0]), float(size[1] if len(size) > 1 else size[0])
    return _trimesh.creation.cylinder(radius=d / 2, height=h, sections=32)


def _satellite(size):
    """A bus (0.3 of the span), two solar panels on booms along x, a dish on +y; size [x, y, z]."""
    X, Y, Z = (list(size) + [size[-1]] * 3)[:3]
    bus = _trimesh.creation.box(extents=[0.2 * X, 0.5 * Y, 0.6 * Z])
    panels = []
    for sgn in (-1, 1):
        p = _plate([0.3 * X, 0.45 * Y])
        p.apply_translation([sgn * 0.33 * X, 0.0, 0.3 * Z])  # facing +z, level with the bus top
        panels.append(p)
    booms = []
    for sgn in (-1, 1):
        b = _trimesh.creation.cylinder(radius=0.01 * Y, height=0.08 * X, sections=8)
        b.apply_transform(_trimesh.transformations.rotation_matrix(math.pi / 2, [0, 1, 0]))
        b.apply_translation([sgn * 0.14 * X, 0.0, 0.3 * Z - 0.02 * Y])
        booms.append(b)
    dish = _trimesh.creation.cylinder(radius=0.18 * Y, height=0.02 * Z, sections=32)
    dish.apply_translation([0.0, 0.35 * Y, 0.3 * Z + 0.01 * Z])
    return {"bus": bus, "panels": _trimesh.util.concatenate(panels), "booms": _trimesh.util.concatenate(booms),
            "dish": dish}


def _vehicle(size):
    """A car-sized body, a cabin on it, four wheels; size [length, width, height]."""
    L, W, H = (list(size) + [size[-1]] * 3)[:3]
    body = _trimesh.creation.box(extents=[L, W, 0.45 * H])
    body.apply_translation([0.0, 0.0, -0.05 * H])
    cabin = _trimesh.creation.box(extents=[0.5 * L, 0.9 * W, 0.4 * H])
    cabin.apply_translation([-0.05 * L, 0.0, 0.375 * H])
    wheels = []
    for sx in (-0.32, 0.32):
        for sy in (-0.5, 0.5):
            w = _trimesh.creation.cylinder(radius=0.18 * H, height=0.12 * W, sections=16)
            w.apply_transform(_trimesh.transformations.rotation_matrix(math.pi / 2, [1, 0, 0]))
            w.apply_translation([sx * L, sy * W, -0.32 * H])
            wheels.append(w)
    return {"body": body, "cabin": cabin, "wheels": _trimesh.util.concatenate(wheels)}


declare_shape("box", summary="a box of extents [x, y, z]", parts=("body",), build=lambda s: {"body": _box(s)})
declare_shape("plate", summary="a one-sided rectangle [x, y] facing +z", parts=("body",),
              build=lambda s: {"body": _plate(s)})
declare_shape("sphere", summary="a sphere of diameter [d]", parts=("body",), build=lambda s: {"body": _sphere(s)})
declare_shape("cylinder", summary="a cylinder [diameter, height] along z", parts=("body",),
              build=lambda s: {"body": _cylinder(s)})
declare_shape("satellite", summary="a bus, two solar panels on booms, a dish; size [x, y, z]",
              parts=("bus", "panels", "booms", "dish"), build=_satellite)
declare_shape("vehicle", summary="a body, a cabin and four wheels; size [length, width, height]",
              parts=("body", "cabin", "wheels"), build=_vehicle)


# ---------------------------------------------------------------- placing
def object_parts(obj) -> dict:
    """The parts of a scene object in the scene frame: ``{part: trimesh.Trimesh}``.

    Parameters
    ----------
    obj : SceneObject

    Returns
    -------
    dict

    Raises
    ------
    ScenarioError
        For a mesh file that cannot be read.
    """
    if obj.shape is not None:
        parts = SHAPES.get(obj.shape).build(tuple(obj.size))
        parts = parts if isinstance(parts, dict) else {"body": parts}
    else:
        parts = read_mesh_parts(obj.mesh)
    M = np.eye(4)
    M[:3, :3] = rotation(obj.attitude_deg) * obj.scale
    M[:3, 3] = obj.position
    return {k: m.copy().apply_transform(M) for k, m in parts.items()}


def _material(obj, part):
    return obj.parts.get(part, obj.material)


def _faces(mesh):
    """Planar faces of a mesh: groups of coplanar adjacent triangles (trimesh's facets, and each
    other triangle alone), as lists of triangle indices."""
    grouped = set()
    out = []
    for f in mesh.facets:
        out.append(np.asarray(f))
        grouped.update(int(i) for i in f)
    out += [np.array([i]) for i in range(len(mesh.faces)) if i not in grouped]
    return out


def _glint(mesh, tris, look, wavelength):
    """A planar face's physical-optics glint towards ``look``: (centroid, amplitude^2 x cell, sign)."""
    n = mesh.face_normals[tris[0]]
    area = float(mesh.area_faces[tris].sum())
    cos = float(n @ look)
    v = mesh.vertices[np.unique(mesh.faces[tris])]
    centre = (mesh.triangles_center[tris] * mesh.area_faces[tris, None]).sum(0) / area
    ea = np.cross(n, [0.0, 0.0, 1.0]) if abs(n[2]) < 0.9 else np.cross(n, [1.0, 0.0, 0.0])
    ea /= np.linalg.norm(ea)
    eb = np.cross(n, ea)
    a = float(np.ptp((v - centre) @ ea))
    b = float(np.ptp((v - centre) @ eb))
    # a rectangle's lobe (exact for rectangular faces; a triangle's approximated by its bounding box's)
    pattern = np.sinc(2.0 * a * float(look @ ea) / wavelength) * np.sinc(2.0 * b * float(look @ eb) / wavelength)
    sigma = 4.0 * math.pi / wavelength ** 2 * (cos * area * pattern) ** 2
    return centre, sigma, np.sign(pattern) if pattern != 0 else 1.0


def _stratified(mesh, spacing: float, rng):
    """Samples of every triangle: each cut into m^2 equal triangles (m = its side over ``spacing``),
    one sample in each, at its centroid (a regular lattice: a smooth surface images flat) or, given
    ``rng``, uniformly within it (a rough one). Returns (triangle index, position (N, 3) m, area m^2)."""
    area = mesh.area_faces
    m_of = np.maximum(1, np.ceil(np.sqrt(2.0 * area) / spacing).astype(int))
    idx, r1, r2, dA = [], [], [], []
    for m in np.unique(m_of):
        tris = np.nonzero(m_of == m)[0]
        i, j = np.meshgrid(np.arange(m), np.arange(m), indexing="ij")
        up = (i + j) <= m - 1
        down = (i + j) <= m - 2
        bi = np.concatenate([i[up], i[down]]).astype(float)
        bj = np.concatenate([j[up], j[down]]).astype(float)
        flip = np.concatenate([np.zeros(up.sum(), bool), np.ones(down.sum(), bool)])
        k = bi.size  # = m^2
        T = np.repeat(tris, k)
        if rng is None:
            u = np.full(T.size, 1.0 / 3.0)
            v = np.full(T.size, 1.0 / 3.0)
        else:
            u, v = rng.random(T.size), rng.random(T.size)
            fold = u + v > 1
            u[fold], v[fold] = 1 - u[fold], 1 - v[fold]
        fl = np.tile(flip, tris.size)
        a = np.tile(bi, tris.size)
        b = np.tile(bj, tris.size)
        r1.append(np.where(fl, a + 1 - u, a + u) / m)
        r2.append(np.where(fl, b + 1 - v, b + v) / m)
        idx.append(T)
        dA.append(np.repeat(area[tris] / k, k))
    idx, r1, r2 = np.concatenate(idx), np.concatenate(r1), np.concatenate(r2)
    tri = mesh.triangles
    pos = tri[idx, 0] + r1[:, None] * (tri[idx, 1] - tri[idx, 0]) + r2[:, None] * (tri[idx, 2] - tri[idx, 0])
    return idx, pos, np.concatenate(dA)


def sample_count(objects, spacing: float) -> int:
    """How many surface samples the objects make at ``spacing`` (m), facing away and hidden ones
    included: the size of their scatterer arrays, known before any sampling.

    Parameters
    ----------
    objects : sequence of SceneObject
    spacing : float
        m.

    Returns
    -------
    int
    """
    n = 0
    for obj in objects:
        for mesh in object_parts(obj).values():
            m = np.maximum(1, np.ceil(np.sqrt(2.0 * mesh.area_faces) / spacing))
            n += int(np.sum(m * m))
    return n
