"""Shared fixtures of the geosep Python tests: meshes made by our own array
generator and by geosep.Mesh.generate, their databases (built once per
session), and the location of the shared test data (skipped when absent)."""
import os
import pathlib

import numpy as np
import pytest

import geosep

REPO = pathlib.Path(__file__).resolve().parents[2]


def grid_arrays(nx, ny, width=1.0, height=1.0):
    """A flat nx x ny vertex grid on [0,width]x[0,height] (z = 0), each
    quad split into two counter-clockwise triangles: (V, F) as numpy arrays."""
    x, y = np.meshgrid(np.linspace(0, width, nx), np.linspace(0, height, ny))
    V = np.column_stack([x.ravel(), y.ravel(), np.zeros(nx * ny)])
    i, j = np.meshgrid(np.arange(nx - 1), np.arange(ny - 1))
    a = (j * nx + i).ravel()
    b, c, d = a + 1, a + nx + 1, a + nx
    F = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])]).astype(np.int64)
    return V, F


def shared_dir():
    """GEOSEP_SHARED, else ../shared next to the repository."""
    env = os.environ.get("GEOSEP_SHARED")
    return pathlib.Path(env) if env else REPO.parent / "shared"


def read_gt(path):
    """A GEOGT1 ground-truth file: (sources (k,), distances (k, n))."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"GEOGT1\0\0"
    n, k = np.frombuffer(data, "<u4", 2, 8)
    rec = np.frombuffer(data, np.uint8, offset=16).reshape(k, 4 + 8 * n)
    sources = rec[:, :4].copy().view("<u4").ravel()
    dist = rec[:, 4:].copy().view("<f8")
    return sources, dist


@pytest.fixture(scope="session")
def shared():
    d = shared_dir()
    if not (d / "meshes").is_dir() or not (d / "groundtruth").is_dir():
        pytest.skip(f"shared test data not found at {d} (set GEOSEP_SHARED to its folder)")
    return d


@pytest.fixture(scope="session")
def plane():
    """A flat 2 x 1 rectangle, 21 x 11 vertices, from our own arrays."""
    V, F = grid_arrays(21, 11, 2.0, 1.0)
    return geosep.Mesh(V, F)


@pytest.fixture(scope="session")
def plane_db(plane):
    return geosep.Database.build(plane, vmax=20)


@pytest.fixture(scope="session")
def sphere():
    return geosep.Mesh.generate("sphere:3")


@pytest.fixture(scope="session")
def sphere_db(sphere):
    return geosep.Database.build(sphere)


@pytest.fixture(scope="session")
def two():
    """Two disjoint flat grids: pairs across them are unreachable."""
    return geosep.Mesh.generate("two:6")


@pytest.fixture(scope="session")
def two_db(two):
    return geosep.Database.build(two)
