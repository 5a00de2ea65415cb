"""Uploaded meshes: good files become the right body; each bad file is refused with a clear reason."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from app.uploads import limits
from app.uploads.limits import MAX_BYTES
from app.uploads.reading import NotWatertightError, body_from_upload, read_mesh
from physics.inertia import box

EXTENTS = (0.3, 0.2, 0.1)


def export(mesh: trimesh.Trimesh, ext: str) -> bytes:
    data = mesh.export(file_type=ext)
    return data.encode() if isinstance(data, str) else data  # OBJ exports as text


def box_mesh() -> trimesh.Trimesh:
    mesh = trimesh.creation.box(extents=EXTENTS)
    mesh.apply_translation([0.05, -0.02, 0.4])
    return mesh


def open_box_stl() -> bytes:
    mesh = box_mesh()
    holed = trimesh.Trimesh(mesh.vertices, mesh.faces[1:], process=False)  # one triangle missing
    return holed.export(file_type="stl")


@pytest.mark.parametrize("ext", ["stl", "obj", "ply", "glb"])
def test_a_box_in_every_format_gives_the_box_tensor(ext):
    data = export(box_mesh(), ext)
    body = body_from_upload(f"brick.{ext.upper()}", data, mass=2.0)
    exact = box(2.0, EXTENTS)
    # The mesh integral of a box is exact; STL/GLB store float32 vertices (relative 6e-8), so 1e-6.
    np.testing.assert_allclose(body.mass_properties.tensor, exact.tensor, rtol=0, atol=1e-6 * exact.tensor.max())
    np.testing.assert_allclose(body.mass_properties.center_of_mass, [0.05, -0.02, 0.4], atol=1e-7)
    assert body.mass_properties.mass == pytest.approx(2.0, rel=1e-12)
    assert body.mesh.is_watertight and len(body.mesh.faces) == 12
    assert "brick" in body.note and "12 triangles" in body.note


def test_file_over_the_size_limit_is_refused_before_parsing():
    with pytest.raises(ValueError, match=r"big\.stl is 20\.0 MB; the limit is 20\.0 MB"):
        read_mesh("big.stl", b"\0" * (MAX_BYTES + 1))


def test_file_that_is_not_a_mesh_type_is_refused():
    with pytest.raises(ValueError, match=r"notes\.txt is not a mesh file .* STL, OBJ, PLY or GLB .*\.txt"):
        read_mesh("notes.txt", b"hello")
    with pytest.raises(ValueError, match="no extension"):
        read_mesh("README", b"hello")


def test_empty_stl_is_refused():
    with pytest.raises(ValueError, match=r"empty\.stl is empty \(0 bytes\)"):
        read_mesh("empty.stl", b"")


@pytest.mark.parametrize("content", [
    b"this is not an STL file at all, just some text\n",
    b"solid nothing\nendsolid nothing\n",
    b"\0" * 84,  # a binary STL header that declares zero triangles
    bytes(range(256)) * 8,
], ids=["text", "ascii-empty-solid", "binary-zero-triangles", "random-bytes"])  # fmt: skip
def test_garbage_stl_that_trimesh_loads_as_empty_is_refused(content):
    # trimesh returns an empty Scene for these without raising: the check must catch it.
    with pytest.raises(ValueError, match=r"junk\.stl contains no triangles"):
        read_mesh("junk.stl", content)


@pytest.mark.parametrize(("name", "content"), [("junk.ply", b"garbage"), ("junk.glb", b"garbage bytes")])
def test_unreadable_file_is_refused(name, content):
    with pytest.raises(ValueError, match=rf"{name.replace('.', '[.]')} could not be read as a"):
        read_mesh(name, content)


def test_too_many_triangles_is_refused(monkeypatch):
    # The real limit is 500,000; a smaller one keeps the test fast and exercises the same branch.
    monkeypatch.setattr(limits, "MAX_FACES", 100)
    sphere = trimesh.creation.icosphere(subdivisions=2)  # 320 faces
    with pytest.raises(ValueError, match=r"ball\.stl has 320 triangles; the limit is 100"):
        read_mesh("ball.stl", sphere.export(file_type="stl"))


def test_non_finite_vertices_are_refused():
    obj = b"v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n"
    # Either refused as non-finite, or trimesh drops the NaN vertex with its faces and what is left
    # is not closed: both are refusals with a reason, never a body with NaN moments.
    with pytest.raises(ValueError, match="not finite|not watertight"):
        body_from_upload("nan.obj", obj)


def test_open_mesh_is_refused_with_its_convex_hull_offered():
    with pytest.raises(NotWatertightError, match=r"open\.stl is not watertight: 3 edges belong to only one") as info:
        body_from_upload("open.stl", open_box_stl())
    assert "convex hull" in str(info.value)
    hull = info.value.hull
    assert hull is not None and hull.is_watertight
    # Accepting the offer gives the full box: the hull of a box missing a triangle is the box.
    body = body_from_upload("open.stl", open_box_stl(), use_convex_hull=True, mass=2.0)
    exact = box(2.0, EXTENTS)
    np.testing.assert_allclose(body.mass_properties.tensor, exact.tensor, rtol=0, atol=1e-6 * exact.tensor.max())
    assert "convex hull" in body.note


def test_flat_open_mesh_has_no_hull_to_offer():
    plane = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]])
    with pytest.raises(NotWatertightError) as info:
        body_from_upload("sheet.obj", export(plane, "obj"))
    assert info.value.hull is None and "convex hull" not in str(info.value)
    with pytest.raises(ValueError, match="all lie on a plane"):
        body_from_upload("sheet.obj", export(plane, "obj"), use_convex_hull=True)


def test_millimetre_mesh_is_scaled_to_metres():
    mesh = box_mesh()
    mesh.apply_scale(1000.0)  # a CAD export in mm: 300 x 200 x 100
    body = body_from_upload("cad.stl", mesh.export(file_type="stl"), mass=2.0)
    exact = box(2.0, EXTENTS)
    np.testing.assert_allclose(body.mass_properties.tensor, exact.tensor, rtol=0, atol=1e-6 * exact.tensor.max())
    assert "millimetres" in body.note


def test_a_box_smaller_than_trimeshs_merge_tolerance_keeps_its_corners():
    """Audit: a 1e-8 m box was "not watertight: 0 edges ..." because trimesh welded its
    corners (merge tolerance 1e-8 m); the merge now happens at unit size."""
    mesh = trimesh.creation.box(extents=EXTENTS)
    tiny = trimesh.Trimesh(mesh.vertices * 1e-7, mesh.faces, process=False)
    body = body_from_upload("tiny.stl", export(tiny, "stl"), mass=2.0)
    exact = box(2.0, np.array(EXTENTS) * 1e-7)
    assert len(body.mesh.faces) == 12 and body.mesh.is_watertight
    np.testing.assert_allclose(body.mass_properties.tensor, exact.tensor, rtol=0, atol=1e-6 * exact.tensor.max())


def test_a_box_below_the_files_number_range_is_refused_as_too_small():
    """A 1e-100 m box is 0 in an STL's 32-bit numbers: the message says it is too small, not "not watertight"."""
    mesh = trimesh.creation.box(extents=EXTENTS)
    with np.errstate(under="ignore"):
        data = export(trimesh.Trimesh(mesh.vertices * 1e-100, mesh.faces, process=False), "stl")
    with pytest.raises(ValueError, match=r"dot\.stl is too small: all its vertices are one point .*1e-38 m"):
        body_from_upload("dot.stl", data)
