/* distance.c - geosep from C: get a mesh, build a distance database, query it.
 *
 *   distance                    a generated flat 41 x 41 grid
 *   distance --generate SPEC    a generated mesh, e.g. "torus:96,48" (see geosep.h)
 *   distance MESH               a mesh file (.obj .off .ply .stl)
 *
 * Prints the geodesic distance between a few vertex pairs next to their
 * straight-line distance (a lower bound; equal on a flat mesh). Every call
 * that can fail is checked: on failure the program prints the library's
 * message and exits with status 1. */
#include <geosep.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#define N_PAIRS 5

static double straight_line(const double *xyz, uint32_t a, uint32_t b)
{
    double dx = xyz[3 * a] - xyz[3 * b], dy = xyz[3 * a + 1] - xyz[3 * b + 1],
           dz = xyz[3 * a + 2] - xyz[3 * b + 2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

int main(int argc, char **argv)
{
    gs_error err = {0};
    gs_mesh *mesh = NULL;
    gs_db *db = NULL;
    const char *step = "reading the mesh";
    int rc;

    printf("geosep %s\n", gs_version_string());

    /* 1. The mesh: validated on load; a bad file gives a message naming the
     *    file, the line and what is wrong. */
    const char *what = "grid:41,41";
    if (argc == 1) {
        rc = gs_mesh_generate(what, &mesh, &err);
    } else if (argc == 3 && !strcmp(argv[1], "--generate")) {
        what = argv[2];
        rc = gs_mesh_generate(what, &mesh, &err);
    } else if (argc == 2 && argv[1][0] != '-') {
        what = argv[1];
        rc = gs_mesh_load(what, GS_FORMAT_AUTO, &mesh, &err);
    } else {
        fprintf(stderr, "usage: distance [MESH | --generate SPEC]\n");
        return 2;
    }
    if (rc != GS_OK) goto done;
    printf("mesh %s: %u vertices, %u faces\n", what, gs_mesh_num_vertices(mesh),
           gs_mesh_num_faces(mesh));

    /* 2. The database: built once per mesh (save it with gs_db_save, open it
     *    later with gs_db_open). Default options: exact distance fields, all
     *    cores. */
    gs_build_options opt;
    gs_build_options_default(&opt);
    gs_build_stats stats;
    gs_db_info info;
    step = "building the database";
    rc = gs_db_build(mesh, &opt, &db, &stats, &err);
    if (rc == GS_OK) rc = gs_db_get_info(db, &info, &err);
    if (rc != GS_OK) goto done;
    printf("database: %u nodes, %.0f bytes per vertex, built in %.2f s\n", info.n_nodes,
           info.bytes_per_vertex, stats.seconds_total);

    /* 3. Queries: a few pairs of distinct vertices used by faces, drawn
     *    deterministically, answered in one batch (gs_db_distance answers
     *    one pair). */
    uint32_t v[2 * N_PAIRS];
    double d[N_PAIRS];
    step = "querying";
    rc = gs_mesh_random_vertices(mesh, 2 * N_PAIRS, 1, v, &err);
    if (rc == GS_OK) rc = gs_db_distances(db, v, N_PAIRS, d, &err);
    if (rc != GS_OK) goto done;
    const double *xyz = gs_mesh_positions(mesh);
    for (int i = 0; i < N_PAIRS; i++)
        printf("distance(%u, %u) = %.6f   straight line %.6f\n", v[2 * i], v[2 * i + 1], d[i],
               straight_line(xyz, v[2 * i], v[2 * i + 1]));

done:
    if (rc != GS_OK)
        fprintf(stderr, "distance: %s failed (%s): %s\n", step, gs_status_string(rc), err.message);
    gs_db_free(db); /* both accept NULL */
    gs_mesh_free(mesh);
    return rc == GS_OK ? 0 : 1;
}
