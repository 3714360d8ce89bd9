"""Mesh files: a scene's parts with their transforms, a single mesh as "body", the bounds over
every part, and clear refusals of files that are not meshes or hold no triangles."""
import numpy as np
import pytest
import trimesh

from salkit.errors import ScenarioError
from salkit.io.meshes import mesh_bounds, read_mesh_parts


def test_single_mesh_is_body_and_bounds(tmp_path):
    path = tmp_path / "box.stl"
    trimesh.creation.box(extents=[2.0, 4.0, 6.0]).export(path)
    parts = read_mesh_parts(str(path))
    assert list(parts) == ["body"] and len(parts["body"].faces) == 12
    lo, hi = mesh_bounds(str(path))
    assert np.allclose(lo, [-1, -2, -3]) and np.allclose(hi, [1, 2, 3])


def test_scene_parts_keep_their_transforms(tmp_path):
    scene = trimesh.Scene()
    scene.add_geometry(trimesh.creation.box(extents=[1.0, 1.0, 1.0]), geom_name="a")
    moved = np.eye(4)
    moved[:3, 3] = [10.0, 0.0, 0.0]
    scene.add_geometry(trimesh.creation.box(extents=[1.0, 1.0, 1.0]), geom_name="b", transform=moved)
    path = tmp_path / "two.glb"
    scene.export(path)
    parts = read_mesh_parts(str(path))
    assert sorted(parts) == ["a", "b"]
    assert np.allclose(parts["b"].bounds.mean(axis=0), [10.0, 0.0, 0.0])
    lo, hi = mesh_bounds(str(path))
    assert np.allclose(lo, [-0.5, -0.5, -0.5]) and np.allclose(hi, [10.5, 0.5, 0.5])


def test_bad_and_empty_files_are_refused_naming_the_field(tmp_path):
    bad = tmp_path / "not_a_mesh.obj"
    bad.write_bytes(b"\x00\x01 definitely not a mesh")
    with pytest.raises(ScenarioError, match=r"scene\.objects\.mesh.*(cannot be read as a mesh|holds no triangles)"):
        read_mesh_parts(str(bad))
    with pytest.raises(ScenarioError, match="cannot be read as a mesh"):
        mesh_bounds(str(tmp_path / "missing.stl"), field="x.mesh")
    empty = tmp_path / "points.ply"
    trimesh.PointCloud(np.random.default_rng(0).random((10, 3))).export(empty)
    with pytest.raises(ScenarioError, match="holds no triangles"):
        read_mesh_parts(str(empty))
