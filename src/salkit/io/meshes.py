"""Mesh files of scene objects (OBJ, STL, PLY, glTF/GLB, read with trimesh): the parts a file
holds, in the file's own frame, or a clear error naming the file.

Both the simulator (:func:`salkit.simulate.targets.object_parts`, which places the parts in the
scene) and the sampling checks (:mod:`salkit.geometry.sampling`, which bound the scene before any
work) read meshes through :func:`read_mesh_parts`, so a file is accepted or refused alike by both.
"""
from __future__ import annotations

import lazy_loader as _lazy
import numpy as np

from ..errors import ScenarioError

_trimesh = _lazy.load("trimesh", suppress_warning=True)


def read_mesh_parts(path: str, field: str = "scene.objects.mesh") -> dict:
    """The parts of a mesh file, ``{name: trimesh.Trimesh}``, each with its node's transform
    applied (a scene's graph flattened; a single mesh is the part "body").

    Parameters
    ----------
    path : str
        Mesh file.
    field : str
        The scenario field named in an error.

    Returns
    -------
    dict

    Raises
    ------
    ScenarioError
        For a file that cannot be read as a mesh, or that holds no triangles.

    Examples
    --------
    >>> read_mesh_parts("/no/such/file.obj")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    salkit.errors.ScenarioError: scene.objects.mesh = '/no/such/file.obj': cannot be read as a mesh (...)
    """
    try:
        loaded = _trimesh.load(path)
    except Exception as err:  # noqa: BLE001 - any reader failure is a bad file
        raise ScenarioError(field, path, f"cannot be read as a mesh ({err})") from None
    if isinstance(loaded, _trimesh.Scene):
        parts = {}
        for node in loaded.graph.nodes_geometry:
            T, gname = loaded.graph[node]
            parts[str(gname)] = loaded.geometry[gname].copy().apply_transform(T)
    else:
        parts = {"body": loaded}
    if not parts or not all(len(getattr(m, "faces", ())) for m in parts.values()):
        raise ScenarioError(field, path, "holds no triangles")
    return parts


def mesh_bounds(path: str, field: str = "scene.objects.mesh") -> tuple[np.ndarray, np.ndarray]:
    """The axis-aligned bounds of every part of a mesh file, in its own frame, m.

    Parameters
    ----------
    path : str
    field : str
        The scenario field named in an error.

    Returns
    -------
    (float64 (3,), float64 (3,))
        Lower and upper corners.

    Raises
    ------
    ScenarioError
        As :func:`read_mesh_parts`.
    """
    b = np.array([np.asarray(m.bounds, np.float64) for m in read_mesh_parts(path, field).values()])
    return b[:, 0].min(axis=0), b[:, 1].max(axis=0)
