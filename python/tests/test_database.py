"""geosep.Database: known answers, agreement with exact fields, numpy
broadcasting, pairwise, fields, surface points, files, options and every
error class."""
import sys
import numpy as np
import pytest

import geosep


def test_plane_distances_are_euclidean(plane, plane_db):
    V = plane.vertices
    rng = np.random.default_rng(1)
    x, y = rng.integers(0, plane.n_vertices, (2, 2000))
    d = db_d = plane_db.distance(x, y)
    e = np.linalg.norm(V[x] - V[y], axis=1)
    ok = e > 0
    assert np.mean(np.abs(d[ok] - e[ok]) / e[ok]) < 1e-3
    assert np.max(np.abs(db_d[ok] - e[ok]) / e[ok]) < 0.02
    assert np.all(d[~ok] == 0)


def test_database_agrees_with_exact_field(sphere, sphere_db):
    for s in (0, 100, 641):
        exact = geosep.distance_field(sphere, s)
        approx = sphere_db.field(s)
        assert approx.shape == (sphere.n_vertices,) and approx.dtype == np.float64
        ok = exact > 0
        rel = np.abs(approx[ok] - exact[ok]) / exact[ok]
        assert np.mean(rel) < 0.005 and np.max(rel) < 0.1
        assert approx[s] == 0


def test_scalars(sphere_db):
    d = sphere_db.distance(3, 400)
    assert isinstance(d, float) and d > 0
    assert sphere_db.distance(np.int32(3), np.uint64(400)) == d
    assert sphere_db.distance(400, 3) == pytest.approx(d, rel=1e-12)
    assert sphere_db.distance(7, 7) == 0
    assert sphere_db.field(3)[400] == d
    # 0-d arrays answer like numpy's ufuncs: a float
    assert sphere_db.distance(np.array(3), np.array(400)) == d


@pytest.mark.parametrize(
    "xs, ys",
    [((5,), (5,)), ((3, 1), (4,)), ((2, 3, 4), (3, 1)), ((), (6,)), ((4,), ()), ((0,), (3, 0)), ((2, 1, 3), (1, 5, 1))],
)
def test_broadcasting(sphere_db, xs, ys):
    rng = np.random.default_rng(7)
    n = sphere_db.n_vertices
    x = rng.integers(0, n, xs)
    y = rng.integers(0, n, ys)
    d = sphere_db.distance(x, y)
    shape = np.broadcast_shapes(xs, ys)
    assert isinstance(d, np.ndarray) and d.shape == shape and d.dtype == np.float64
    bx, by = np.broadcast_arrays(x, y)
    expected = [sphere_db.distance(int(a), int(b)) for a, b in zip(bx.ravel(), by.ravel())]
    np.testing.assert_array_equal(d.ravel(), expected)


def test_broadcasting_errors(sphere_db):
    with pytest.raises(ValueError, match="broadcast"):
        sphere_db.distance(np.zeros(3, int), np.zeros(4, int))
    with pytest.raises(ValueError, match="integers"):
        sphere_db.distance([0.5, 1], [1, 2])
    with pytest.raises(ValueError, match="integers"):
        sphere_db.distance(1.0, 2)
    assert sphere_db.distance([], []).shape == (0,)


def test_ids_out_of_range(sphere_db):
    n = sphere_db.n_vertices
    with pytest.raises(IndexError, match=rf"{n}.*\[0, {n}\)"):
        sphere_db.distance(0, n)
    with pytest.raises(IndexError, match="-1"):
        sphere_db.distance(-1, 0)
    with pytest.raises(IndexError, match=rf"{n + 2}"):
        sphere_db.distance([0, 1], [2, n + 2])
    with pytest.raises(IndexError, match="-3"):
        sphere_db.pairwise([0, -3])
    with pytest.raises(IndexError):
        sphere_db.pairwise([0], [n])
    with pytest.raises(IndexError):
        sphere_db.field(n)
    with pytest.raises(IndexError):
        sphere_db.field(-1)


def test_pairwise(sphere_db):
    src = [0, 5, 77, 300]
    dst = np.array([1, 2, 641], np.int32)
    P = sphere_db.pairwise(src, dst)
    assert P.shape == (4, 3) and P.dtype == np.float64
    np.testing.assert_array_equal(P, sphere_db.distance(np.array(src)[:, None], dst[None, :]))
    S = sphere_db.pairwise(src)
    assert S.shape == (4, 4)
    np.testing.assert_allclose(S, S.T, rtol=1e-12)
    assert np.all(np.diag(S) == 0)
    assert sphere_db.pairwise([], dst).shape == (0, 3)
    with pytest.raises(ValueError, match="1-D"):
        sphere_db.pairwise([[0, 1]])


def test_field_threads_same_answers(sphere_db):
    n = sphere_db.n_vertices
    for x in (0, n // 3, n - 1):
        one = sphere_db.field(x)
        assert np.array_equal(sphere_db.field(x, threads=2), one)
        assert np.array_equal(sphere_db.field(x, threads=0), one)
        assert one[n // 2] == sphere_db.distance(x, n // 2)
    with pytest.raises(TypeError):
        sphere_db.field(0, 2)  # threads is keyword-only
    with pytest.raises(TypeError):
        sphere_db.field(0, threads="two")
    for bad in (-1, 1025, 2**32):  # -1 used to wrap to 2^32 - 1 threads
        with pytest.raises(ValueError, match="threads"):
            sphere_db.field(0, threads=bad)


def test_unreachable_is_inf(two, two_db):
    n = two.n_vertices
    assert two_db.distance(0, n - 1) == np.inf
    assert np.isposinf(two_db.pairwise([0], [n - 1])[0, 0])
    f = two_db.field(0)
    assert np.all(np.isposinf(f[n // 2 :])) and np.all(np.isfinite(f[: n // 2]))


def vertex_points(mesh, vertices):
    """For each vertex, a face of it and the weights (1 at the vertex)."""
    F = mesh.faces
    faces, bary = [], []
    for v in vertices:
        f = int(np.nonzero((F == v).any(axis=1))[0][0])
        faces.append(f)
        bary.append((F[f] == v).astype(float))
    return np.array(faces), np.array(bary)


def test_point_distance_on_vertices_equals_distance(sphere, sphere_db):
    rng = np.random.default_rng(3)
    a = rng.integers(0, sphere.n_vertices, 50)
    b = rng.integers(0, sphere.n_vertices, 50)
    fa, ba = vertex_points(sphere, a)
    fb, bb = vertex_points(sphere, b)
    d = sphere_db.point_distance(fa, ba, fb, bb, mesh=sphere)
    assert d.shape == (50,)
    np.testing.assert_array_equal(d, sphere_db.distance(a, b))
    # one point (scalar face, 3 weights): a float
    one = sphere_db.point_distance(int(fa[0]), ba[0], int(fb[0]), bb[0])
    assert isinstance(one, float) and one == d[0]
    # one point against many
    np.testing.assert_array_equal(sphere_db.point_distance(fa[0], ba[0], fb, bb), sphere_db.distance(a[0], b))


def test_point_distance_on_the_plane(plane, plane_db):
    rng = np.random.default_rng(5)
    k = 200
    fa, fb = rng.integers(0, plane.n_faces, (2, k))
    ba, bb = rng.dirichlet([1, 1, 1], k), rng.dirichlet([1, 1, 1], k)
    d = plane_db.point_distance(fa, ba, fb, bb, mesh=plane)
    V, F = plane.vertices, plane.faces.astype(np.int64)
    pa = np.einsum("ki,kij->kj", ba, V[F[fa]])
    pb = np.einsum("ki,kij->kj", bb, V[F[fb]])
    e = np.linalg.norm(pa - pb, axis=1)
    assert np.all(d >= e - 1e-12)  # never below the straight distance
    ok = e > 1e-3
    assert np.mean(np.abs(d[ok] - e[ok]) / e[ok]) < 0.01
    # loops and vectors agree
    assert plane_db.point_distance(int(fa[3]), ba[3], int(fb[3]), bb[3]) == d[3]


def test_point_distance_errors(sphere, sphere_db, plane):
    with pytest.raises(ValueError, match="weight"):
        sphere_db.point_distance(0, [0.5, 0.5, 0.5], 1, [1, 0, 0])
    with pytest.raises(ValueError, match="weight"):
        sphere_db.point_distance([0, 1], [[1, 0, 0], [-0.5, 1.5, 0]], [2, 3], [[1, 0, 0], [1, 0, 0]])
    with pytest.raises(IndexError, match=rf"{sphere.n_faces}"):
        sphere_db.point_distance(sphere.n_faces, [1, 0, 0], 0, [1, 0, 0])
    with pytest.raises(IndexError):
        sphere_db.point_distance(-1, [1, 0, 0], 0, [1, 0, 0])
    with pytest.raises(ValueError, match=r"\(k, 3\)"):
        sphere_db.point_distance([0, 1], [1, 0, 0], 0, [1, 0, 0])
    with pytest.raises(ValueError, match=r"\(k, 3\)"):
        sphere_db.point_distance(0, [1, 0], 0, [1, 0, 0])
    with pytest.raises(ValueError, match="as many"):
        sphere_db.point_distance([0, 1], np.eye(3)[:2], [0, 1, 2], np.eye(3))
    with pytest.raises(ValueError, match="not the database's"):
        sphere_db.point_distance(0, [1, 0, 0], 0, [1, 0, 0], mesh=plane)
    with pytest.raises(TypeError):
        sphere_db.point_distance(0, [1, 0, 0], 0, [1, 0, 0], mesh="sphere.obj")


def test_save_open_roundtrip(tmp_path, sphere, sphere_db):
    path = tmp_path / "sphere.gsdb"
    sphere_db.save(path)
    db = geosep.Database.open(str(path))
    assert db.n_vertices == sphere_db.n_vertices == sphere.n_vertices
    a, b = sphere_db.info(), db.info()
    assert a == b
    assert a["method"] == "exact" and a["n_vertices"] == sphere.n_vertices and a["file_bytes"] == path.stat().st_size
    P = np.arange(sphere.n_vertices)
    np.testing.assert_array_equal(db.pairwise(P[::7]), sphere_db.pairwise(P[::7]))
    np.testing.assert_array_equal(db.vertices, sphere.vertices)
    assert db.mesh is None and db.build_stats is None
    assert sphere_db.mesh is sphere and sphere_db.build_stats["n_fields"] > 0
    # an opened database needs the mesh for surface points
    with pytest.raises(TypeError, match="mesh="):
        db.point_distance(0, [1, 0, 0], 1, [1, 0, 0])
    assert db.point_distance(0, [1, 0, 0], 1, [0, 1, 0], mesh=sphere) == sphere_db.point_distance(
        0, [1, 0, 0], 1, [0, 1, 0])


def test_corrupt_database(tmp_path, sphere_db):
    path = tmp_path / "db.gsdb"
    sphere_db.save(path)
    data = bytearray(path.read_bytes())
    for where in (len(data) // 3, len(data) // 2, len(data) - 10):
        bad = bytearray(data)
        bad[where] ^= 0xFF
        p = tmp_path / f"flip{where}.gsdb"
        p.write_bytes(bytes(bad))
        with pytest.raises(geosep.DatabaseError):
            geosep.Database.open(p, verify=True)
    # the header is checked at every open, verified or not
    bad = bytearray(data)
    bad[9] ^= 0xFF
    p = tmp_path / "version.gsdb"
    p.write_bytes(bytes(bad))
    with pytest.raises(geosep.DatabaseError):
        geosep.Database.open(p)
    assert geosep.Database.open(path, verify=True).n_vertices == sphere_db.n_vertices
    p = tmp_path / "truncated.gsdb"
    p.write_bytes(bytes(data[: len(data) // 2]))
    with pytest.raises(geosep.DatabaseError, match="truncated.gsdb"):
        geosep.Database.open(p)
    p = tmp_path / "mesh.obj"
    p.write_text("v 0 0 0\n")
    with pytest.raises(geosep.DatabaseError):
        geosep.Database.open(p)
    with pytest.raises(FileNotFoundError):
        geosep.Database.open(tmp_path / "missing.gsdb")
    with pytest.raises(OSError):
        sphere_db.save(tmp_path / "no" / "such" / "folder.gsdb")
    # errors without an errno keep their message (not "[Errno None] None: ...")
    for call in (lambda: sphere_db.save(tmp_path), lambda: geosep.Database.open(tmp_path)):
        with pytest.raises(OSError) as e:
            call()
        assert str(tmp_path) in str(e.value) and "regular file" in str(e.value) and "None" not in str(e.value)


def test_build_options(plane):
    db = geosep.Database.build(plane, method="fmm", threads=1, vmax=12, mmax=8, tol=0.01, spacing=1.0,
                               vertex_sources=True, sampled=False, leaf_exact=True, seed=4, max_samples=32,
                               field_memory=64, fmm_start=2.0)
    i = db.info()
    assert (i["method"], i["vmax"], i["mmax"], i["tol"], i["spacing"], i["seed"], i["max_samples"]) == (
        "fmm", 12, 8, 0.01, 1.0, 4, 32)
    assert i["vertex_sources"] and i["leaf_exact"] and not i["sampled"] and i["fmm_start"] == 2.0
    assert i["near_radius"] > 0 and i["n_near_pairs"] >= 0  # near pairs by default
    assert db.build_stats["n_near_pairs"] == i["n_near_pairs"]
    n0 = geosep.Database.build(plane, vmax=12, near_radius=0).info()
    assert n0["near_radius"] == 0 and n0["n_near_pairs"] == 0
    with pytest.raises(ValueError, match="near_radius"):
        geosep.Database.build(plane, near_radius=-1)
    h = geosep.Database.build(plane, method="heat", heat_time=2.0, heat_refine=1, sampled=True).info()
    assert (h["method"], h["heat_time"], h["heat_refine"], h["sampled"]) == ("heat", 2.0, 1, True)
    with pytest.raises(TypeError, match="vmaxx"):
        geosep.Database.build(plane, vmaxx=10)
    with pytest.raises(ValueError, match="vmax"):
        geosep.Database.build(plane, vmax=1)
    with pytest.raises(ValueError, match="tol"):
        geosep.Database.build(plane, tol=2.0)
    with pytest.raises(ValueError, match="unknown method"):
        geosep.Database.build(plane, method="magic")
    with pytest.raises(TypeError):
        geosep.Database.build(plane, vmax="many")
    with pytest.raises(TypeError):
        geosep.Database()


def test_progress(plane, capsys):
    geosep.Database.build(plane, progress=True)
    err = capsys.readouterr().err
    lines = err.strip("\n").split("\n")
    stages = [ln.split("\r")[-1].split()[0] for ln in lines]
    # one line per stage, in order; the build reports "fields" only from its
    # own thread, which may get no node of a small mesh
    assert stages[0] == "tree" and stages[-1] == "write" and stages == sorted(
        stages, key=["tree", "fields", "leaves", "near", "write"].index)
    assert all(ln.startswith("\r") and ln.rstrip().endswith("s") and "100%" in ln.split("\r")[-1] for ln in lines)
    calls = []
    geosep.Database.build(plane, progress=lambda stage, f: calls.append((stage, f)))
    assert capsys.readouterr().err == ""
    assert calls[0] == ("tree", 0.0) and calls[-1] == ("write", 1.0)
    assert {s for s, _ in calls} <= {"tree", "fields", "leaves", "near", "write"}

    def fail(stage, f):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        geosep.Database.build(plane, progress=fail)


def test_progress_bar_stderr(plane, monkeypatch):
    """The bar draws through sys.stderr: a broken stderr does not stop the
    build; a KeyboardInterrupt raised while it draws (a Ctrl-C whose handler
    ran inside write) is not swallowed: the build raises it."""

    class Broken:
        def write(self, text):
            raise OSError("stderr is gone")

        def flush(self):
            pass

    monkeypatch.setattr(sys, "stderr", Broken())
    assert geosep.Database.build(plane, progress=True).n_vertices == plane.n_vertices

    class CtrlC:
        writes = 0

        def write(self, text):
            CtrlC.writes += 1
            if CtrlC.writes == 2:
                raise KeyboardInterrupt

        def flush(self):
            pass

    monkeypatch.setattr(sys, "stderr", CtrlC())
    with pytest.raises(KeyboardInterrupt):
        geosep.Database.build(plane, progress=True)
    assert CtrlC.writes == 2  # nothing drawn after it


def test_bytes_and_pickle(sphere, sphere_db, tmp_path):
    import pickle

    data = sphere_db.to_bytes()
    p = tmp_path / "s.gsdb"
    sphere_db.save(p)
    assert data == p.read_bytes()
    n = sphere_db.n_vertices
    pairs = np.arange(0, n, 7)
    want = sphere_db.distance(pairs, pairs[::-1])
    for db in (geosep.Database.from_bytes(data), geosep.Database.from_bytes(bytearray(data)),
               geosep.Database.from_bytes(memoryview(data)), pickle.loads(pickle.dumps(sphere_db))):
        assert isinstance(db, geosep.Database) and db.n_vertices == n and db.mesh is None
        assert np.array_equal(db.distance(pairs, pairs[::-1]), want)
        assert np.array_equal(db.field(3), sphere_db.field(3))
    bad = bytearray(data)
    bad[len(bad) // 2] ^= 0x40  # a flipped bit: the image is checked in full
    with pytest.raises(geosep.DatabaseError):
        geosep.Database.from_bytes(bad)
    with pytest.raises(geosep.DatabaseError):
        geosep.Database.from_bytes(data[: len(data) // 3])
    with pytest.raises(TypeError):
        geosep.Database.from_bytes("not bytes")
    m = pickle.loads(pickle.dumps(sphere))
    assert np.array_equal(m.vertices, sphere.vertices) and np.array_equal(m.faces, sphere.faces)
    assert np.array_equal(sphere_db.path(0, n - 1, mesh=m), sphere_db.path(0, n - 1, mesh=sphere))
    V = np.array(sphere.vertices)
    F = np.array(sphere.faces).astype(np.int64)
    F2 = np.vstack([F, F[:1]])  # a duplicated face: repaired, and then not picklable
    rep = geosep.Mesh(V, F2, repair=True)
    with pytest.raises(TypeError, match="repaired"):
        pickle.dumps(rep)
