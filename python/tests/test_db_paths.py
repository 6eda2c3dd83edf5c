"""Database.path: geodesic paths from a database and its mesh. On a plane the
straight segment; on generated curved meshes and the shared meshes within 1%
of the exact distance and never below it; points on the surface; the faces
form; bad arguments; geosep.render(polylines=...)."""
import numpy as np
import pytest

import geosep

from conftest import read_gt


def length(p):
    return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())


def face_points(mesh, faces, bary):
    V, F = mesh.vertices, mesh.faces
    return np.einsum("kj,kjc->kc", bary, V[F[faces]])


def check_on_surface(mesh, p, faces, bary):
    k = len(p)
    assert faces.shape == (k,) and faces.dtype == np.int64 and bary.shape == (k, 3)
    assert bary.min() >= 0
    np.testing.assert_allclose(bary.sum(axis=1), 1, atol=1e-12)
    np.testing.assert_allclose(face_points(mesh, faces, bary), p, atol=1e-12)


def test_plane_straight(plane, plane_db):
    V = plane.vertices
    for a, b in [(0, plane.n_vertices - 1), (3, 200), (17, 150)]:
        p = plane_db.path(a, b)
        assert p.dtype == np.float64 and p.ndim == 2 and p.shape[1] == 3
        np.testing.assert_allclose(p[0], V[a], atol=1e-15)
        np.testing.assert_allclose(p[-1], V[b], atol=1e-15)
        assert length(p) == pytest.approx(np.linalg.norm(V[b] - V[a]), rel=1e-12)


def test_faces_form_and_points(plane, plane_db):
    x, y = (5, (0.2, 0.3, 0.5)), (170, (0.6, 0.1, 0.3))
    p, faces, bary = plane_db.path(x, y, mesh=plane, return_faces=True)
    check_on_surface(plane, p, faces, bary)
    assert faces[0] == 5 and faces[-1] == 170
    np.testing.assert_allclose(bary[0], [0.2, 0.3, 0.5], atol=1e-15)
    assert length(p) == pytest.approx(np.linalg.norm(p[-1] - p[0]), rel=1e-12)


@pytest.mark.parametrize("spec", ["cylinder:24,10,1,2", "cone:24,10,1,1", "cube:6", "torus:24,12"])
def test_generated_within_one_percent(spec):
    m = geosep.Mesh.generate(spec)
    db = geosep.Database.build(m)
    solver = geosep.Solver(m)
    rng = np.random.default_rng(3)
    ids = rng.choice(m.n_vertices, size=16, replace=False)
    for a, b in zip(ids[::2], ids[1::2]):
        p, faces, bary = db.path(int(a), int(b), return_faces=True)
        check_on_surface(m, p, faces, bary)
        exact = solver.field(int(a))[b]
        assert exact * (1 - 1e-9) <= length(p) <= exact * 1.01


def test_one_point_and_unreachable(two, two_db):
    p = two_db.path(3, 3)
    assert p.shape == (1, 3)
    q = two_db.path(0, two.n_vertices - 1)
    assert q.shape == (0, 3)


def test_bad_arguments(plane, plane_db, sphere):
    with pytest.raises(IndexError):
        plane_db.path(0, plane.n_vertices)
    with pytest.raises(IndexError):
        plane_db.path((plane.n_faces, (1, 0, 0)), 3)
    with pytest.raises(ValueError, match="sum"):
        plane_db.path((3, (0.5, 0.6, 0)), 7)
    with pytest.raises(TypeError):
        plane_db.path("a", 3)
    with pytest.raises(ValueError, match="not the database's"):
        plane_db.path(0, 3, mesh=sphere)
    with pytest.raises(TypeError, match="Mesh"):
        plane_db.path(0, 3, mesh=np.zeros(3))
    opened = geosep.Database.open(plane_db_path(plane_db))
    with pytest.raises(TypeError, match="mesh="):
        opened.path(0, 3)
    assert length(opened.path(0, 3, mesh=plane)) == pytest.approx(length(plane_db.path(0, 3)))


def plane_db_path(db, _cache={}):
    import tempfile, os
    if "p" not in _cache:
        d = tempfile.mkdtemp()
        _cache["p"] = os.path.join(d, "plane.gsdb")
        db.save(_cache["p"])
    return _cache["p"]


def test_shared_bunny(shared):
    mesh = geosep.Mesh.load(shared / "meshes" / "bunny-5k.obj")
    db = geosep.Database.build(mesh)
    sources, dist = read_gt(shared / "groundtruth" / "bunny-5k.gt")
    rng = np.random.default_rng(5)
    for s in range(2):
        for t in rng.choice(mesh.n_vertices, size=20, replace=False):
            if t == sources[s]:
                continue
            p = db.path(int(sources[s]), int(t))
            assert dist[s, t] * (1 - 1e-9) <= length(p) <= dist[s, t] * 1.01


def test_render_polylines(plane, plane_db):
    p = plane_db.path(0, plane.n_vertices - 1)
    plain = geosep.render(plane, size=(120, 80), view=(0, 0))
    one = geosep.render(plane, polylines=p, size=(120, 80), view=(0, 0))
    two = geosep.render(plane, polylines=[p, plane_db.path(10, 220)], size=(120, 80), view=(0, 0))
    assert not np.array_equal(one, plain) and not np.array_equal(two, one)
    assert (one == 255).all(axis=2).sum() > (plain == 255).all(axis=2).sum()  # the white core
    with pytest.raises(ValueError, match="polylines"):
        geosep.render(plane, polylines=[np.zeros((3, 2))])
    with pytest.raises(TypeError, match="polylines"):
        geosep.render(plane, polylines=5)
    with pytest.raises(ValueError, match="path point"):
        geosep.render(plane, polylines=np.array([[0, 0, 0], [np.nan, 0, 0]]))
