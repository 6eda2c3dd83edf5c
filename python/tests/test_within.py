"""Database.within, nearest and radius_matrix: equal to the thresholded
fields (the same vertices and distances, by distance then id), a brute-force
selection of the nearest candidates, CSR rows equal to within by id,
threads, and bad arguments."""
import threading

import numpy as np
import pytest

import geosep


def thresholded(db, x, r):
    f = db.field(x)
    ids = np.flatnonzero((f <= r) & np.isfinite(f))
    order = np.lexsort((ids, f[ids]))  # by distance, then id
    return ids[order], f[ids][order]


@pytest.mark.parametrize("name", ["plane_db", "sphere_db", "two_db"])
def test_within_equals_thresholded_field(request, name):
    db = request.getfixturevalue(name)
    rng = np.random.default_rng(7)
    for x in rng.integers(0, db.n_vertices, 12):
        x = int(x)
        f = db.field(x)
        fin = np.sort(f[np.isfinite(f)])
        for r in (0.0, fin[len(fin) // 100], fin[len(fin) // 10], fin[len(fin) // 2], fin[-1], np.inf,
                  np.nextafter(fin[len(fin) // 5], 0)):
            ids, d = db.within(x, r)
            want_ids, want_d = thresholded(db, x, r)
            assert ids.dtype == np.int64 and d.dtype == np.float64
            assert np.array_equal(ids, want_ids) and np.array_equal(d, want_d)
            assert ids[0] == x and d[0] == 0.0


def test_within_two_components(two_db):
    ids, d = two_db.within(0, np.inf)
    f = two_db.field(0)
    assert np.isfinite(d).all() and len(ids) == np.isfinite(f).sum() < two_db.n_vertices


def test_nearest_equals_brute_force(sphere_db):
    rng = np.random.default_rng(3)
    n = sphere_db.n_vertices
    for _ in range(10):
        x = int(rng.integers(n))
        cand = rng.integers(0, n, 50)
        cand = np.r_[cand, cand[:5], x]  # repeats, x itself
        f = sphere_db.field(x)
        u = np.unique(cand)
        order = np.lexsort((u, f[u]))
        for k in (1, 4, len(u), len(u) + 3):
            ids, d = sphere_db.nearest(x, cand, k)
            assert np.array_equal(ids, u[order][:k]) and np.array_equal(d, f[u][order][:k])
    ids, d = sphere_db.nearest(0, [], 3)
    assert ids.shape == (0,) and d.shape == (0,)


def test_nearest_unreachable_last(two_db):
    f = two_db.field(0)
    far = int(np.flatnonzero(np.isinf(f))[0])
    ids, d = two_db.nearest(0, [far, 1, 0], 3)
    assert list(ids) == [0, 1, far] and d[2] == np.inf


def test_radius_matrix(plane_db):
    n = plane_db.n_vertices
    sources = np.array([0, 5, 117, 230, 5])
    r = 0.3
    indptr, indices, data = plane_db.radius_matrix(sources, r)
    assert indptr.dtype == np.int64 and indices.dtype == np.int64 and data.dtype == np.float64
    assert indptr.shape == (len(sources) + 1,) and indptr[0] == 0 and indptr[-1] == len(indices) == len(data)
    dense = np.zeros((len(sources), n))
    for i, s in enumerate(sources):
        row = slice(indptr[i], indptr[i + 1])
        assert np.all(np.diff(indices[row]) > 0)  # increasing ids
        ids, d = plane_db.within(int(s), r)
        o = np.argsort(ids)
        assert np.array_equal(indices[row], ids[o]) and np.array_equal(data[row], d[o])
        dense[i, indices[row]] = data[row]
    f = np.array([plane_db.field(int(s)) for s in sources])
    assert np.array_equal(dense, np.where(f <= r, f, 0.0))
    for t in (1, 2):
        again = plane_db.radius_matrix(sources, r, threads=t)
        assert all(np.array_equal(a, b) for a, b in zip(again, (indptr, indices, data)))
    e = plane_db.radius_matrix([], r)
    assert e[0].tolist() == [0] and e[1].shape == (0,) and e[2].shape == (0,)


def test_bad_arguments(plane_db):
    n = plane_db.n_vertices
    with pytest.raises(IndexError):
        plane_db.within(n, 1.0)
    with pytest.raises(IndexError):
        plane_db.within(-1, 1.0)
    for bad in (-0.1, np.nan):
        with pytest.raises(ValueError, match="radius"):
            plane_db.within(0, bad)
        with pytest.raises(ValueError, match="radius"):
            plane_db.radius_matrix([0], bad)
    with pytest.raises(TypeError):
        plane_db.within(0, "1")
    with pytest.raises(TypeError):
        plane_db.within(0.5, 1.0)
    with pytest.raises(IndexError, match="candidates"):
        plane_db.nearest(0, [1, n], 1)
    with pytest.raises(ValueError, match="k = -1"):
        plane_db.nearest(0, [1], -1)
    with pytest.raises(ValueError, match="1-D"):
        plane_db.nearest(0, [[1, 2]], 1)
    with pytest.raises(IndexError, match="sources"):
        plane_db.radius_matrix([0, n], 0.1)
    with pytest.raises(TypeError):
        plane_db.radius_matrix([0], 0.1, 2)  # threads is keyword-only
    for bad in (-1, 1025):  # -1 used to reach OpenMP as 2^32 - 1 threads: the process aborted
        with pytest.raises(ValueError, match="threads"):
            plane_db.radius_matrix([0], 0.1, threads=bad)


def test_threads(sphere_db):
    want = [sphere_db.within(x, 0.4) for x in range(20)]
    results = {}

    def work(t):
        results[t] = [sphere_db.within(x, 0.4) for x in range(20)]
    threads = [threading.Thread(target=work, args=(t,)) for t in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for t in range(4):
        assert all(np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1]) for a, b in zip(results[t], want))
