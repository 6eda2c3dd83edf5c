"""geosep.Mesh: construction from arrays, files and specs; validation and
the exceptions it raises; read-only views; the report."""
import errno

import numpy as np
import pytest

import geosep
from conftest import grid_arrays


def test_version():
    assert isinstance(geosep.__version__, str)
    assert len(geosep.__version__.split(".")) == 3


def test_exception_hierarchy():
    assert issubclass(geosep.MeshError, geosep.Error)
    assert issubclass(geosep.MeshError, ValueError)
    assert issubclass(geosep.DatabaseError, geosep.Error)
    assert issubclass(geosep.DatabaseError, ValueError)
    assert not issubclass(geosep.Error, ValueError)


def test_from_arrays_is_copied_and_read_only():
    V, F = grid_arrays(4, 3)
    m = geosep.Mesh(V, F)
    assert (m.n_vertices, m.n_faces) == (12, 12)
    np.testing.assert_array_equal(m.vertices, V)
    np.testing.assert_array_equal(m.faces, F)
    assert m.vertices.dtype == np.float64 and m.vertices.shape == (12, 3)
    assert m.faces.shape == (12, 3)
    V[0, 0] = 99.0  # the mesh holds its own copy
    F[0, 0] = 5
    assert m.vertices[0, 0] == 0.0 and m.faces[0, 0] == 0
    with pytest.raises(ValueError):
        m.vertices[0, 0] = 1.0
    with pytest.raises(ValueError):
        m.faces[0, 0] = 1


@pytest.mark.parametrize("fdtype", [np.int32, np.int64, np.uint32])
@pytest.mark.parametrize("vdtype", [np.float32, np.float64])
def test_dtypes_accepted(vdtype, fdtype):
    V, F = grid_arrays(3, 3)
    m = geosep.Mesh(V.astype(vdtype), F.astype(fdtype))
    assert m.n_faces == 8
    # lists work too
    assert geosep.Mesh(V.tolist(), F.tolist()).n_vertices == 9


def test_same_as_generated():
    V, F = grid_arrays(5, 4, 2.0, 3.0)
    ours = geosep.Mesh(V, F)
    gen = geosep.Mesh.generate("grid:5,4,2,3")
    np.testing.assert_allclose(np.sort(gen.vertices, axis=0), np.sort(ours.vertices, axis=0), atol=1e-15)
    assert gen.report()["n_faces"] == ours.report()["n_faces"]


@pytest.mark.parametrize(
    "V, F, what",
    [
        (np.zeros((4, 2)), [[0, 1, 2]], "V must be an (n, 3) array of floats"),
        (np.zeros(12), [[0, 1, 2]], "V must be an (n, 3) array of floats"),
        (np.zeros((4, 3), complex), [[0, 1, 2]], "V must be an (n, 3) array of floats"),
        (np.zeros((4, 3)), np.array([[0.0, 1.0, 2.0]]), "F must be an (m, 3) array of int32 or int64"),
        (np.zeros((4, 3)), [0, 1, 2], "F must be an (m, 3) array of int32 or int64"),
        (np.zeros((4, 3)), [[0, 1, 2, 3]], "F must be an (m, 3) array of int32 or int64"),
    ],
)
def test_bad_shape_or_dtype(V, F, what):
    with pytest.raises(ValueError) as e:
        geosep.Mesh(V, F)
    assert what in str(e.value)
    assert "got an array of shape" in str(e.value)
    assert not isinstance(e.value, geosep.MeshError)


def test_non_manifold_vertex():
    # two triangles touching at vertex 2 only (a bow tie)
    V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [2, 1, 0], [2, 2, 0]]
    F = [[0, 1, 2], [2, 3, 4]]
    with pytest.raises(geosep.MeshError, match=r"non-manifold vertex 2\b"):
        geosep.Mesh(V, F)


@pytest.mark.parametrize(
    "F, pattern",
    [
        ([[0, 1, 5]], r"5"),  # out of range
        ([[0, 1, -1]], r"-1"),  # negative
        ([[0, 1, 1]], r"1"),  # repeated in a face
        ([[0, 1, 2**40]], r"1099511627776"),  # beyond uint32
        (np.zeros((0, 3), int), r""),  # no faces: no surface
    ],
)
def test_invalid_faces(F, pattern):
    V = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    with pytest.raises(geosep.MeshError, match=pattern):
        geosep.Mesh(V, F)


def test_non_finite_and_degenerate():
    with pytest.raises(geosep.MeshError):
        geosep.Mesh([[0, 0, 0], [1, 0, 0], [np.nan, 1, 0]], [[0, 1, 2]])
    with pytest.raises(geosep.MeshError):
        geosep.Mesh([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 2]])  # zero area


def test_report():
    r = geosep.Mesh.generate("torus:12,8").report()
    expected = {"n_vertices", "n_faces", "n_edges", "unreferenced", "components", "boundary_edges",
                "boundary_loops", "euler", "genus", "min_angle_deg", "max_angle_deg", "min_edge",
                "max_edge", "mean_edge", "bbox_min", "bbox_max"}
    assert set(r) == expected
    assert (r["n_vertices"], r["genus"], r["components"], r["boundary_loops"], r["euler"]) == (96, 1, 1, 0, 0)
    r = geosep.Mesh.generate("two:4").report()
    assert r["components"] == 2 and r["boundary_loops"] == 2
    V, F = grid_arrays(3, 3)
    r = geosep.Mesh(np.vstack([V, [[5, 5, 5]]]), F).report()  # one unreferenced vertex
    assert r["unreferenced"] == 1 and r["n_vertices"] == 10
    assert r["bbox_min"] == (0.0, 0.0, 0.0) and r["bbox_max"] == (5.0, 5.0, 5.0)


def test_save_load_roundtrip(tmp_path):
    m = geosep.Mesh.generate("sphere:2")
    path = tmp_path / "sphere.obj"
    m.save(path)
    back = geosep.Mesh.load(str(path))
    np.testing.assert_array_equal(back.vertices, m.vertices)
    np.testing.assert_array_equal(back.faces, m.faces)
    assert geosep.Mesh.load(path, format="obj").n_faces == m.n_faces


def test_load_errors(tmp_path):
    missing = tmp_path / "missing.obj"
    with pytest.raises(OSError) as e:
        geosep.Mesh.load(missing)
    assert e.value.errno == errno.ENOENT and isinstance(e.value, FileNotFoundError)
    assert e.value.filename == str(missing)
    assert "missing.obj" in str(e.value)
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n")
    with pytest.raises(geosep.MeshError, match=r"bad\.obj.*4"):  # names the file and the line
        geosep.Mesh.load(bad)
    with pytest.raises(ValueError, match="format"):
        geosep.Mesh.load(bad, format="xyz")
    with pytest.raises(OSError) as e:
        geosep.Mesh.load(tmp_path)  # a directory
    assert str(tmp_path) in str(e.value) and "None" not in str(e.value)


def test_generate_and_subdivide():
    m = geosep.Mesh.generate("grid:3,3")
    s = m.subdivide()
    assert s.n_faces == 4 * m.n_faces
    np.testing.assert_array_equal(s.vertices[: m.n_vertices], m.vertices)
    with pytest.raises(ValueError, match="grid"):
        geosep.Mesh.generate("grid:1")
    with pytest.raises(ValueError):
        geosep.Mesh.generate("nonsense:3")


def test_random_vertices():
    m = geosep.Mesh.generate("sphere:2")
    a = m.random_vertices(10, seed=3)
    assert a.shape == (10,) and len(set(a.tolist())) == 10 and a.max() < m.n_vertices
    np.testing.assert_array_equal(a, m.random_vertices(10, seed=3))
    with pytest.raises(ValueError):
        m.random_vertices(m.n_vertices + 1)
    with pytest.raises(ValueError, match="k must be"):  # not 2^32 - 1 (a 16 GB array first)
        m.random_vertices(-1)
    with pytest.raises(TypeError):
        m.random_vertices(2.5)
    assert m.random_vertices(0).shape == (0,)
