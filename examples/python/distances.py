"""distances.py - geodesic distances on a triangle mesh with geosep.

    python3 distances.py [MESH]

MESH: an .obj, .off, .ply or .stl file (default: a generated torus).
"""
import os
import sys
import tempfile

import numpy as np

import geosep

# A mesh from a file, from numpy arrays (geosep.Mesh(V, F)) or generated.
mesh = geosep.Mesh.load(sys.argv[1]) if len(sys.argv) > 1 else geosep.Mesh.generate("torus:48,24")
print(mesh, "genus", mesh.report()["genus"])

# Exact geodesic distances from vertex 0 to every vertex.
exact = geosep.distance_field(mesh, 0)

# Build the database once and save it; Database.open() maps it back in
# milliseconds, in this process or another.
db = geosep.Database.build(mesh, progress=True)
with tempfile.TemporaryDirectory() as folder:
    path = os.path.join(folder, "mesh.gsdb")
    db.save(path)
    db = geosep.Database.open(path)
    print(f"database: {db.info()['file_bytes']} bytes for {db.n_vertices} vertices")

    # Queries: one pair, many pairs (numpy broadcasting), all pairs of a set.
    n = db.n_vertices
    print("d(0, 10) =", db.distance(0, 10))
    approx = db.distance(0, np.arange(n))  # (n,): the same as db.field(0)
    ok = exact > 0
    print(f"mean relative error against the exact field: {np.mean(np.abs(approx[ok] - exact[ok]) / exact[ok]):.3%}")
    rng = np.random.default_rng(0)
    some = rng.choice(n, 5, replace=False)
    print("pairwise distances of 5 vertices:\n", np.round(db.pairwise(some), 4))

    # Surface points: a face and barycentric weights each.
    face_a, face_b = rng.integers(0, mesh.n_faces, (2, 3))
    weight_a, weight_b = rng.dirichlet([1, 1, 1], (2, 3))
    print("point distances:", db.point_distance(face_a, weight_a, face_b, weight_b, mesh=mesh))
