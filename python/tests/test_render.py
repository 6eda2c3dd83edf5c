"""geosep.render: arrays and PNG files, what the options change, bad
arguments."""
import numpy as np
import pytest

import geosep


def test_array(sphere):
    img = geosep.render(sphere, size=(120, 90))
    assert img.shape == (90, 120, 3) and img.dtype == np.uint8
    assert np.all(img[0, 0] == 255) and np.all(img[-1, -1] == 255)  # white background
    assert not np.all(img[45, 60] == 255)  # the sphere in the middle
    np.testing.assert_array_equal(img, geosep.render(sphere, size=(120, 90)))  # deterministic


def test_field_isolines_separators_points(sphere, sphere_db):
    f = geosep.distance_field(sphere, 0)
    plain = geosep.render(sphere, size=(160, 120))
    coloured = geosep.render(sphere, f, isolines=0, size=(160, 120))
    lines = geosep.render(sphere, f, isolines=10, size=(160, 120))
    seps = geosep.render(sphere, f, isolines=0, separators=sphere_db, size=(160, 120))
    dots = geosep.render(sphere, points=sphere.vertices[:5], size=(160, 120))
    for other in (coloured, lines, seps, dots):
        assert not np.array_equal(other, plain)
    assert not np.array_equal(lines, coloured) and not np.array_equal(seps, coloured)
    # viridis: blue dominates near the source, not on the plain surface
    blue = lambda img: np.mean(img[..., 2].astype(int) - img[..., 0].astype(int))
    assert blue(coloured[30:90, 40:120]) > blue(plain[30:90, 40:120]) + 20
    # the view turns the picture
    assert not np.array_equal(geosep.render(sphere, f, size=(160, 120), view=(120, -30)), lines)


def test_png(tmp_path, sphere):
    path = tmp_path / "sphere.png"
    assert geosep.render(sphere, geosep.distance_field(sphere, 3), size=(200, 100), path=path) is None
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert int.from_bytes(data[16:20], "big") == 200 and int.from_bytes(data[20:24], "big") == 100
    with pytest.raises(OSError):
        geosep.render(sphere, path=tmp_path / "no" / "folder" / "x.png")


def test_bad_arguments(sphere, plane_db):
    n = sphere.n_vertices
    with pytest.raises(ValueError, match=rf"\({n},\)"):
        geosep.render(sphere, np.zeros(n - 1))
    with pytest.raises(ValueError, match="size"):
        geosep.render(sphere, size=(8, 100))
    with pytest.raises(ValueError, match="size"):
        geosep.render(sphere, size=(100.5, 100))
    with pytest.raises(TypeError, match="size"):
        geosep.render(sphere, size=100)
    with pytest.raises(TypeError, match="view"):
        geosep.render(sphere, view=("up", 3))
    with pytest.raises(ValueError):
        geosep.render(sphere, view=(np.nan, 0))
    with pytest.raises(ValueError):
        geosep.render(sphere, separators=plane_db)  # another mesh's database
    with pytest.raises(TypeError, match="separators"):
        geosep.render(sphere, separators="db.gsdb")
    with pytest.raises(ValueError, match="points"):
        geosep.render(sphere, points=[1, 2, 3])
    with pytest.raises(ValueError):
        geosep.render(sphere, np.zeros(n), isolines=10**6)
