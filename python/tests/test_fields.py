"""Distance fields: geosep.distance_field and geosep.Solver against known
answers (flat: the Euclidean distance), between methods, and every bad
argument."""
import threading

import numpy as np
import pytest

import geosep


def euclid(mesh, sources):
    V = mesh.vertices
    return np.min(np.linalg.norm(V[None, :, :] - V[np.atleast_1d(sources)][:, None, :], axis=2), axis=0)


def test_plane_is_euclidean(plane):
    for s in (0, 17, plane.n_vertices - 1):
        np.testing.assert_allclose(geosep.distance_field(plane, s), euclid(plane, s), rtol=1e-12, atol=1e-12)


def test_several_sources_give_the_minimum(plane):
    src = [3, 100, 200]
    d = geosep.distance_field(plane, src)
    assert d.shape == (plane.n_vertices,) and d.dtype == np.float64
    np.testing.assert_allclose(d, euclid(plane, src), atol=1e-12)
    np.testing.assert_allclose(d, np.min([geosep.distance_field(plane, s) for s in src], axis=0), atol=1e-12)
    np.testing.assert_array_equal(geosep.distance_field(plane, np.array(src, np.int32)), d)


def test_solver_reuse(sphere):
    solver = geosep.Solver(sphere)
    assert solver.method == "exact" and solver.mesh is sphere
    a = solver.field(5)
    b = solver.field([7, 9])
    np.testing.assert_array_equal(solver.field(5), a)  # nothing leaks from one solve to the next
    np.testing.assert_array_equal(b, geosep.distance_field(sphere, [7, 9]))
    assert a[5] == 0 and np.all(a >= 0)
    # on the unit icosphere, geodesic distances are close to great-circle ones
    V = sphere.vertices
    great = np.arccos(np.clip(V @ V[5] / np.linalg.norm(V, axis=1) / np.linalg.norm(V[5]), -1, 1))
    assert np.max(np.abs(a - great)) < 0.05


@pytest.mark.parametrize("method, tol", [("fmm", 0.03), ("heat", 0.06), ("graph", 0.15), ("dgg", 0.001)])
def test_methods_agree_with_exact(sphere, method, tol):
    exact = geosep.distance_field(sphere, 0)
    approx = geosep.Solver(sphere, method).field(0)
    ok = exact > 0
    assert np.mean(np.abs(approx[ok] - exact[ok]) / exact[ok]) < tol
    if method in ("graph", "dgg"):  # paths along edges / graph edges are never shorter
        assert np.all(approx >= exact - 1e-12)


def test_solver_options(sphere):
    a = geosep.Solver(sphere, "heat", heat_time=1.0, heat_refine=0).field(0)
    b = geosep.Solver(sphere, "heat", heat_time=10.0, heat_refine=0).field(0)
    assert not np.array_equal(a, b)
    c = geosep.distance_field(sphere, 0, "heat", heat_time=10.0, heat_refine=0)
    np.testing.assert_allclose(b, c)
    geosep.Solver(sphere, "heat", heat_refine="auto")
    geosep.Solver(sphere, "fmm", fmm_start=0)
    with pytest.raises(ValueError, match="heat_time"):
        geosep.Solver(sphere, "heat", heat_time=0.0)
    with pytest.raises(ValueError, match="heat_refine"):
        geosep.Solver(sphere, "heat", heat_refine=9)
    with pytest.raises(ValueError, match="heat_refine"):
        geosep.Solver(sphere, "heat", heat_refine="most")
    with pytest.raises(ValueError, match="fmm_exact_start|fmm_start"):
        geosep.Solver(sphere, "fmm", fmm_start=-1)
    with pytest.raises(TypeError):
        geosep.Solver(sphere, "heat", heat_tim=1.0)
    with pytest.raises(ValueError, match="dgg_eps"):
        geosep.Solver(sphere, "dgg", dgg_eps=0.0)
    d = geosep.distance_field(sphere, 0, "dgg", dgg_eps=0.01)
    e = geosep.Solver(sphere, "dgg", dgg_eps=0.01).field(0)
    np.testing.assert_array_equal(d, e)


def test_dgg_plane_and_database(plane):
    d = geosep.Solver(plane, "dgg").field(0)
    e = euclid(plane, 0)
    assert np.all(d >= e * (1 - 1e-12)) and np.max(d[e > 0] / e[e > 0] - 1) < 0.01
    db = geosep.Database.build(plane, method="dgg", dgg_eps=0.003, threads=1)
    assert db.info()["method"] == "dgg"
    with pytest.raises(ValueError, match="dgg_eps"):
        geosep.Database.build(plane, method="dgg", dgg_eps=1.0)


def test_max_distance(plane):
    full = geosep.distance_field(plane, 0)
    part = geosep.Solver(plane).field(0, max_distance=0.5)
    near = full <= 0.5
    np.testing.assert_allclose(part[near], full[near], atol=1e-12)
    assert np.all(part[~near] > 0.5)
    np.testing.assert_array_equal(geosep.distance_field(plane, 0, max_distance=np.inf), full)
    for bad in (0, -1.0, np.nan):
        with pytest.raises(ValueError, match="max_distance"):
            geosep.distance_field(plane, 0, max_distance=bad)


def test_unreachable_is_inf(two):
    d = geosep.distance_field(two, 0)
    n = two.n_vertices
    assert np.all(np.isfinite(d[: n // 2])) and np.all(np.isposinf(d[n // 2 :]))


def test_bad_arguments(plane):
    n = plane.n_vertices
    with pytest.raises(IndexError, match=rf"{n}.*\[0, {n}\)"):
        geosep.distance_field(plane, n)
    with pytest.raises(IndexError, match="-1"):
        geosep.distance_field(plane, -1)
    with pytest.raises(IndexError, match=rf"{n + 5}"):
        geosep.Solver(plane).field([0, n + 5])
    with pytest.raises(ValueError, match="empty"):
        geosep.distance_field(plane, [])
    with pytest.raises(ValueError, match="integers"):
        geosep.distance_field(plane, [0.5])
    with pytest.raises(ValueError, match="1-D"):
        geosep.distance_field(plane, [[0, 1]])
    with pytest.raises(ValueError, match="unknown method"):
        geosep.Solver(plane, "dijkstra")
    with pytest.raises(TypeError):
        geosep.distance_field("mesh.obj", 0)


def test_solver_from_threads(sphere):
    """One Solver shared by threads: calls run one at a time (a lock), so
    every result is right."""
    solver = geosep.Solver(sphere)
    expected = {s: geosep.distance_field(sphere, s) for s in range(8)}
    errors = []

    def work(s):
        for _ in range(3):
            if not np.array_equal(solver.field(s), expected[s]):
                errors.append(s)

    threads = [threading.Thread(target=work, args=(s,)) for s in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
