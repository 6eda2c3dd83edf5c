"""Database.farthest_point_sampling: equal to a brute-force greedy over the
database's own fields, every component first, the seed first, vertices used
by no face never chosen, bad arguments, and threads (the GIL is released)."""
import threading

import numpy as np
import pytest

import geosep
from conftest import grid_arrays


def brute_force(db, n, k, seed, used):
    D = np.array([db.field(v) if used[v] else np.full(n, np.inf) for v in range(n)])
    out, chosen = [seed], ~used.copy()
    chosen[seed] = True
    for _ in range(1, k):
        d = D[out].min(axis=0)
        d[chosen] = -1  # never again (distances are >= 0)
        v = int(np.argmax(d))  # the first maximum: ties to the lowest id
        out.append(v)
        chosen[v] = True
    return np.array(out)


def test_equals_brute_force(plane, plane_db):
    n = plane.n_vertices
    used = np.ones(n, bool)
    for seed in (0, 117):
        want = brute_force(plane_db, n, n, seed, used)
        for k in (1, 5, 60, n):
            got = plane_db.farthest_point_sampling(k, seed=seed)
            assert got.dtype == np.int64 and got.shape == (k,)
            assert np.array_equal(got, want[:k])
    assert plane_db.farthest_point_sampling(0).shape == (0,)


def test_components_first(two, two_db):
    s = two_db.farthest_point_sampling(3)
    assert s[0] == 0 and np.isinf(two_db.distance(int(s[0]), int(s[1])))


def test_unreferenced_vertices_never_chosen():
    V, F = grid_arrays(8, 8)
    V = np.vstack([V, [[5.0, 5.0, 0.0], [6.0, 5.0, 0.0]]])  # 64, 65: used by no face
    m = geosep.Mesh(V, F)
    db = geosep.Database.build(m, vmax=20)
    used = np.r_[np.ones(64, bool), False, False]
    s = db.farthest_point_sampling(64, seed=3)
    assert np.array_equal(np.sort(s), np.arange(64))
    assert np.array_equal(s, brute_force(db, 66, 64, 3, used))
    with pytest.raises(ValueError, match="exceeds the 64 vertices"):
        db.farthest_point_sampling(65)
    with pytest.raises(ValueError, match="used by no face"):
        db.farthest_point_sampling(2, seed=64)


def test_bad_arguments(plane_db):
    with pytest.raises(ValueError):
        plane_db.farthest_point_sampling(232)  # the plane has 231 vertices
    with pytest.raises(ValueError):
        plane_db.farthest_point_sampling(-1)
    with pytest.raises(IndexError):
        plane_db.farthest_point_sampling(2, seed=231)
    with pytest.raises(TypeError):
        plane_db.farthest_point_sampling(2.5)


def test_threads(sphere_db):
    want = sphere_db.farthest_point_sampling(20, seed=5)
    results = []

    def work():
        results.append(sphere_db.farthest_point_sampling(20, seed=5))
    threads = [threading.Thread(target=work) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(results) == 4 and all(np.array_equal(r, want) for r in results)
