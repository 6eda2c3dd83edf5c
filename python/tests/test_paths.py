"""Exact geodesic paths: Solver.path and geosep.geodesic_path on known
geodesics (a plane, a cube), their invariants (length = the exact field's
value, points in their faces), the shared ground truth, and every bad
argument."""
import numpy as np
import pytest

import geosep

from conftest import read_gt


def length(p):
    return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())


def face_points(mesh, faces, bary):
    V, F = mesh.vertices, mesh.faces
    return np.einsum("kj,kjc->kc", bary, V[F[faces]])


def test_plane_path_is_the_straight_segment(plane):
    V = plane.vertices
    a, b = 0, plane.n_vertices - 1
    p = geosep.geodesic_path(plane, a, b)
    assert p.dtype == np.float64 and p.ndim == 2 and p.shape[1] == 3 and p.shape[0] >= 2
    np.testing.assert_allclose(p[0], V[a], atol=1e-15)
    np.testing.assert_allclose(p[-1], V[b], atol=1e-15)
    assert length(p) == pytest.approx(np.linalg.norm(V[b] - V[a]), rel=1e-12)
    # every point on the segment
    d = (V[b] - V[a]) / np.linalg.norm(V[b] - V[a])
    off = (p - V[a]) - np.outer((p - V[a]) @ d, d)
    assert np.abs(off).max() < 1e-12


def test_faces_and_weights(plane):
    x, y = (5, (0.2, 0.3, 0.5)), (170, (0.6, 0.1, 0.3))
    p, faces, bary = geosep.Solver(plane).path(x, y, return_faces=True)
    k = len(p)
    assert faces.shape == (k,) and faces.dtype == np.int64 and bary.shape == (k, 3)
    assert faces[0] == 5 and faces[-1] == 170
    np.testing.assert_allclose(bary.sum(axis=1), 1, atol=1e-12)
    assert bary.min() >= -1e-12
    np.testing.assert_allclose(face_points(plane, faces, bary), p, atol=1e-12)
    # consecutive points share a face: point i+1 lies in face i
    np.testing.assert_allclose(p[-1], face_points(plane, [170], np.array([[0.6, 0.1, 0.3]]))[0], atol=1e-15)
    assert length(p) == pytest.approx(np.linalg.norm(p[-1] - p[0]), rel=1e-12)


def test_cube_opposite_corners():
    cube = geosep.Mesh.generate("cube:3")
    V = cube.vertices
    a = int(np.argmin(np.linalg.norm(V - [0, 0, 0], axis=1)))
    b = int(np.argmin(np.linalg.norm(V - [1, 1, 1], axis=1)))
    p = geosep.geodesic_path(cube, a, b)
    assert length(p) == pytest.approx(np.sqrt(5), rel=1e-12)
    # on the surface: some coordinate is 0 or 1 at every point
    assert np.all(np.min(np.minimum(np.abs(p), np.abs(p - 1)), axis=1) < 1e-12)


def test_length_is_the_exact_distance_and_reverse(sphere):
    solver = geosep.Solver(sphere)
    d = solver.field(7)
    for t in (0, 50, 300, sphere.n_vertices - 1):
        p = solver.path(7, t)
        assert length(p) == pytest.approx(d[t], rel=1e-9)
        assert length(solver.path(t, 7)) == pytest.approx(d[t], rel=1e-9)


def test_same_point_and_unreachable(two):
    p = geosep.geodesic_path(two, 3, 3)
    assert p.shape == (1, 3)
    q = geosep.geodesic_path(two, 0, two.n_vertices - 1)
    assert q.shape == (0, 3)
    q, f, b = geosep.geodesic_path(two, 0, two.n_vertices - 1, return_faces=True)
    assert q.shape == (0, 3) and f.shape == (0,) and b.shape == (0, 3)


def test_bad_arguments(plane):
    with pytest.raises(IndexError):
        geosep.geodesic_path(plane, 0, plane.n_vertices)
    with pytest.raises(IndexError):
        geosep.geodesic_path(plane, (plane.n_faces, (1, 0, 0)), 0)
    with pytest.raises(ValueError, match="sum"):
        geosep.geodesic_path(plane, 0, (3, (0.5, 0.6, 0)))
    with pytest.raises(ValueError):
        geosep.geodesic_path(plane, 0, (3, (0.5, 0.5)))
    with pytest.raises(TypeError):
        geosep.geodesic_path(plane, 0, "x")
    with pytest.raises(ValueError, match="exact"):
        geosep.Solver(plane, method="graph").path(0, 1)


def test_shared_ground_truth(shared):
    mesh = geosep.Mesh.load(shared / "meshes" / "bunny-5k.obj")
    sources, truth = read_gt(shared / "groundtruth" / "bunny-5k.gt")
    solver = geosep.Solver(mesh)
    rng = np.random.default_rng(1)
    for t in rng.integers(0, mesh.n_vertices, 20):
        assert length(solver.path(int(sources[0]), int(t))) == pytest.approx(truth[0, t], rel=1e-9)
