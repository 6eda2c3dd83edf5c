"""Mesh(V, F, repair=True) and Mesh.load(path, repair=True) on generated
flawed meshes (doc/repair.md): a pinched vertex, an unwelded seam, a flipped
face, a duplicate face. Each repaired mesh validates again from its own
arrays, keeps the input's vertex ids and positions, reports the right
counts, and gives the intact surface's distances; without repair the same
arrays raise MeshError naming the vertex or edge (or, for the seam, which is
a valid mesh of two pieces, answer inf across it)."""
import numpy as np
import pytest

import geosep
from conftest import grid_arrays

KINDS = ("repeated_corner", "duplicate_face", "zero_area_collapsed", "zero_area_split", "zero_area_needle",
         "zero_area_boundary", "zero_area_dropped", "seam_edge", "seam_ambiguous", "welded_vertex",
         "nonmanifold_edge", "flipped_face", "orientation_cut", "sheet_cut", "split_vertex")


def check_repaired(m, V, expect):
    """m validates again from its arrays, keeps V's ids and positions bit
    for bit, and its report counts exactly `expect` (others 0)."""
    geosep.Mesh(np.array(m.vertices), np.array(m.faces, dtype=np.int64))  # the library's own validation again
    n = len(V)
    assert np.array_equal(m.vertices[:n], V)
    r = m.repair_report
    assert set(r["counts"]) == set(KINDS)
    assert {k: c for k, c in r["counts"].items() if c} == expect
    assert set(r["examples"]) == set(expect)
    assert r["n_input_vertices"] == n and r["n_vertices"] == m.n_vertices and r["n_faces"] == m.n_faces
    lines = r["text"].splitlines()  # first line, a line per kind made (or "nothing to repair"), the legend
    assert lines[0].startswith("repair mesh: ") and len(lines) == max(len(expect), 1) + 2
    vm = m.vertex_map
    assert vm.shape == (n,) and not vm.flags.writeable
    for v in range(n):
        al = m.input_aliases(v)
        assert al[0] == vm[v] and not al.flags.writeable
        assert np.array_equal(m.vertices[al], np.repeat(V[v][None], len(al), axis=0))  # same position
    with pytest.raises(ValueError):
        vm[0] = 1
    return r


def test_not_repaired_has_no_report(plane):
    assert plane.repair_report is None and plane.vertex_map is None
    assert plane.input_aliases(7).tolist() == [7]
    with pytest.raises(IndexError):
        plane.input_aliases(plane.n_vertices)


def test_valid_mesh_comes_out_unchanged():
    V, F = grid_arrays(5, 4)
    m = geosep.Mesh(V, F, repair=True)
    check_repaired(m, V, {})
    assert np.array_equal(m.faces, F) and np.array_equal(m.vertex_map, np.arange(len(V)))


def test_pinched_vertex():
    # two triangles touching at vertex 0 only
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]], float)
    F = np.array([[0, 1, 2], [0, 3, 4]])
    with pytest.raises(geosep.MeshError, match="non-manifold vertex 0"):
        geosep.Mesh(V, F)
    m = geosep.Mesh(V, F, repair=True)
    r = check_repaired(m, V, {"split_vertex": 1})
    assert m.n_vertices == 6 and m.input_aliases(0).tolist() == [0, 5]
    assert r["examples"]["split_vertex"][0]["vertices"][:2] == (0, 5)
    assert m.faces.tolist() == [[0, 1, 2], [5, 3, 4]]
    d = geosep.distance_field(m, 1)
    assert d[2] == pytest.approx(np.sqrt(2), rel=1e-12) and np.isinf(d[3])


def seam_arrays():
    """The plane of the `plane` fixture (21 x 11 on [0,2]x[0,1]) cut along
    x = 1: the right half's faces use copies of the 11 seam vertices,
    appended as 231..241. Returns (V, F, the intact F)."""
    V, F = grid_arrays(21, 11, 2.0, 1.0)
    seam = np.arange(10, 231, 21)  # column x = 1
    copy = {int(s): 231 + i for i, s in enumerate(seam)}
    right = V[F].mean(axis=1)[:, 0] > 1
    Fc = F.copy()
    for f in np.nonzero(right)[0]:
        Fc[f] = [copy.get(int(v), int(v)) for v in F[f]]
    return np.vstack([V, V[seam]]), Fc, F


def test_unwelded_seam_distances_equal_the_intact_plane():
    V, F, F_intact = seam_arrays()
    cut = geosep.Mesh(V, F)  # valid: two pieces, nothing connects them
    assert np.isinf(geosep.distance_field(cut, 0)[20])
    m = geosep.Mesh(V, F, repair=True)
    check_repaired(m, V, {"seam_edge": 10, "welded_vertex": 11})
    intact = geosep.Mesh(V[:231], F_intact)
    d_intact = geosep.distance_field(intact, 0)
    d = geosep.distance_field(m, 0)
    vm = m.vertex_map
    # every input vertex, by its input id, has the intact plane's distance
    n_in = np.concatenate([np.arange(231), np.arange(10, 231, 21)])  # the intact vertex of each input vertex
    np.testing.assert_allclose(d[vm], d_intact[n_in], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(d_intact[20], 2.0, rtol=1e-12)  # across the seam: straight
    # the database of the repaired mesh answers across the seam too
    db = geosep.Database.build(m, vmax=20)
    assert db.distance(int(vm[0]), int(vm[20])) == pytest.approx(2.0, rel=5e-3)


def test_flipped_face():
    V, F = grid_arrays(6, 5)
    Fb = F.copy()
    Fb[7] = Fb[7][::-1]
    with pytest.raises(geosep.MeshError, match="edge|orient"):
        geosep.Mesh(V, Fb)
    m = geosep.Mesh(V, Fb, repair=True)
    check_repaired(m, V, {"flipped_face": 1})
    assert np.array_equal(m.vertex_map, np.arange(len(V)))

    def canon(faces):  # each face from its smallest corner, orientation kept
        return sorted(tuple(np.roll(f, -int(np.argmin(f)))) for f in np.asarray(faces).tolist())
    assert canon(m.faces) == canon(F)
    np.testing.assert_allclose(geosep.distance_field(m, 0), np.linalg.norm(V - V[0], axis=1), atol=1e-12)


def test_duplicate_face():
    V, F = grid_arrays(6, 5)
    Fd = np.vstack([F, F[3][[1, 2, 0]]])  # the same face again, rotated
    with pytest.raises(geosep.MeshError, match="edge|face"):
        geosep.Mesh(V, Fd)
    m = geosep.Mesh(V, Fd, repair=True)
    r = check_repaired(m, V, {"duplicate_face": 1})
    assert r["examples"]["duplicate_face"][0]["face"] == len(F)
    assert np.array_equal(m.faces, F)
    np.testing.assert_allclose(geosep.distance_field(m, 0), np.linalg.norm(V - V[0], axis=1), atol=1e-12)


def test_load_repair(tmp_path):
    p = tmp_path / "pinched.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3\nf 1 4 5\n")
    with pytest.raises(geosep.MeshError, match="non-manifold vertex 0"):
        geosep.Mesh.load(p)
    m = geosep.Mesh.load(p, repair=True)
    r = m.repair_report
    assert r["counts"]["split_vertex"] == 1 and m.input_aliases(0).tolist() == [0, 5]
    assert r["examples"]["split_vertex"][0]["line"] == 7  # the file's line of face 1
    assert r["text"].startswith(f"repair {p}: 5 vertices, 2 faces -> 6 vertices (1 new), 2 faces")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nf 1 2 9\n")
    with pytest.raises(geosep.MeshError, match="bad.obj"):
        geosep.Mesh.load(bad, repair=True)  # out-of-range ids stay errors
    with pytest.raises(OSError):
        geosep.Mesh.load(tmp_path / "missing.obj", repair=True)


def test_repair_arrays_still_refuses_bad_data():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, np.nan, 0]], float)
    with pytest.raises(geosep.MeshError):
        geosep.Mesh(V, [[0, 1, 2]], repair=True)
    with pytest.raises(geosep.MeshError):
        geosep.Mesh(V[:2], [[0, 1, 2]], repair=True)


def brute_input_distance(db, m, x, y):
    """min over the aliases of x and y of db.distance (the documented rule)."""
    if x == y:
        return 0.0
    return min(db.distance(int(a), int(b)) for a in m.input_aliases(x) for b in m.input_aliases(y))


def test_database_by_input_ids(tmp_path):
    """A database built from a repaired Mesh stores the input ids: the seam
    (welded vertices) and a pinched vertex (split), answered by input id as
    the least over the aliases; saved and opened, the same; an unrepaired
    database answers input ids as vertex ids."""
    V, F, _ = seam_arrays()
    m = geosep.Mesh(V, F, repair=True)
    db = geosep.Database.build(m, vmax=20)
    n_in = len(V)
    assert db.n_input_vertices == n_in and db.info()["n_input_vertices"] == n_in and db.n_vertices == m.n_vertices
    for v in (0, 10, 231, 241):
        assert db.input_aliases(v).tolist() == m.input_aliases(v).tolist()
    rng = np.random.default_rng(3)
    xs, ys = rng.integers(0, n_in, 300), rng.integers(0, n_in, 300)
    xs[:11], ys[:11] = np.arange(231, 242), np.arange(10, 231, 21)  # each welded copy and its representative
    want = np.array([brute_input_distance(db, m, int(x), int(y)) for x, y in zip(xs, ys)])
    assert np.array_equal(db.input_distance(xs, ys), want)
    assert np.all(want[:11] == 0.0)
    assert db.input_distance(int(xs[20]), int(ys[20])) == want[20]
    f = db.input_field(231)
    assert f.shape == (n_in,) and f[10] == 0.0
    assert np.array_equal(f, [brute_input_distance(db, m, 231, v) for v in range(n_in)])
    with pytest.raises(IndexError, match="input vertex id"):
        db.input_distance(0, n_in)
    with pytest.raises(IndexError):
        db.input_field(n_in)
    path = tmp_path / "seam.gsdb"
    db.save(str(path))
    re = geosep.Database.open(str(path), verify=True)
    assert re.n_input_vertices == n_in and np.array_equal(re.input_field(231), f)

    # a pinched vertex split in two: from the second triangle through the copy
    Vp = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]], float)
    mp = geosep.Mesh(Vp, np.array([[0, 1, 2], [0, 3, 4]]), repair=True)
    dbp = geosep.Database.build(mp)
    assert dbp.n_input_vertices == 5 and dbp.n_vertices == 6 and len(dbp.input_aliases(0)) == 2
    assert dbp.input_distance(0, 3) == 1.0 and dbp.input_distance(0, 1) == 1.0
    assert np.isinf(dbp.distance(0, 3))  # vertex 0 itself is in the first triangle
    assert np.isinf(dbp.input_distance(1, 3))  # the two triangles only touched at 0: now apart

    # not repaired: input ids are vertex ids
    V2, F2 = grid_arrays(6, 5)
    plain = geosep.Database.build(geosep.Mesh(V2, F2))
    assert plain.n_input_vertices == plain.n_vertices
    assert np.array_equal(plain.input_field(3), plain.field(3))
    assert plain.input_aliases(4).tolist() == [4]


def test_database_info_dgg_eps():
    V, F = grid_arrays(8, 6)
    m = geosep.Mesh(V, F)
    assert geosep.Database.build(m, method="dgg", dgg_eps=0.01).info()["dgg_eps"] == 0.01
    assert geosep.Database.build(m).info()["dgg_eps"] == 0.0
