"""geosep: fast geodesic distance queries on triangle meshes.

A Python interface to the geosep C library, an implementation of Gotsman &
Hormann, "Compressing geodesic information for fast point-to-point geodesic
distance queries" (SIGGRAPH Asia 2022). A database built once per mesh
answers distance queries between vertices or surface points in well under a
microsecond each::

    import geosep
    mesh = geosep.Mesh.load("bunny.obj")        # or geosep.Mesh(V, F)
    db = geosep.Database.build(mesh, progress=True)
    db.save("bunny.gsdb")
    d = db.distance(0, 100)                       # float
    D = db.pairwise([0, 1, 2])                    # (3, 3) array
    ids, dist = db.within(0, 0.05)                # every vertex within 0.05
    exact = geosep.distance_field(mesh, 0)        # (n,) exact distances
    path = geosep.geodesic_path(mesh, 0, 100)     # (k, 3) exact shortest path
    geosep.render(mesh, exact, separators=db, path="bunny.png")

Errors: MeshError (an invalid mesh), DatabaseError (a corrupt or
incompatible database file), both subclasses of Error and ValueError;
OSError for files that cannot be read or written; IndexError for a vertex
or face id out of range; ValueError for arrays of the wrong shape or dtype.
"""

from ._geosep import (
    __version__,
    Error,
    MeshError,
    DatabaseError,
    Mesh,
    Solver,
    Database,
    distance_field,
    geodesic_path,
    render,
)

__all__ = [
    "__version__",
    "Error",
    "MeshError",
    "DatabaseError",
    "Mesh",
    "Solver",
    "Database",
    "distance_field",
    "geodesic_path",
    "render",
]
