/* sample.c - farthest-point sampling by the database's distances: greedy,
 * each new sample's distances folded into a running minimum. A sample only
 * brings closer the vertices within the current largest minimum (the
 * distance of the sample itself to the ones before), so after the first
 * samples each fold is a gs_db_within of that radius, whose cost shrinks
 * with it; while some vertex is unreached (the first sample, other
 * components) it is a whole gs_db_field. Uses only the public query
 * functions. */
#include "../core/internal.h"

#include <math.h>
#include <stdlib.h>

int gs_db_farthest_point_sampling(const gs_db *db, uint32_t k, uint32_t seed_vertex, uint32_t *out, gs_error *err)
{
    if (!db || (!out && k)) return gs__fail(err, GS_EARG, "gs_db_farthest_point_sampling: NULL argument");
    gs_db_info info;
    int rc = gs_db_get_info(db, &info, err);
    if (rc) return rc;
    const uint32_t n = info.n_vertices;
    if (seed_vertex >= n)
        return gs__fail(err, GS_EARG, "gs_db_farthest_point_sampling: seed vertex %u >= n_vertices %u", seed_vertex,
                        n);
    if (gs_db_vertex_leaf(db, seed_vertex) == GS_NONE)
        return gs__fail(err, GS_EARG, "gs_db_farthest_point_sampling: seed vertex %u is used by no face",
                        seed_vertex);
    /* mind[v]: distance from v to the nearest sample so far (+inf: none
     * reached it yet); -inf marks a vertex that is never chosen again (a
     * sample, or a vertex used by no face). */
    double *mind = malloc((size_t)n * sizeof *mind);
    if (!mind) return gs__fail(err, GS_ENOMEM, "gs_db_farthest_point_sampling: out of memory (%u vertices)", n);
    uint32_t n_ref = 0;
    for (uint32_t v = 0; v < n; ++v) {
        int used = gs_db_vertex_leaf(db, v) != GS_NONE;
        mind[v] = used ? INFINITY : -INFINITY;
        n_ref += (uint32_t)used;
    }
    if (k > n_ref) {
        free(mind);
        return gs__fail(err, GS_EARG,
                        "gs_db_farthest_point_sampling: k = %u exceeds the %u vertices used by faces", k, n_ref);
    }
    double *field = k > 1 ? malloc((size_t)n * sizeof *field) : NULL;
    if (k > 1 && !field) {
        free(mind);
        return gs__fail(err, GS_ENOMEM, "gs_db_farthest_point_sampling: out of memory (%u vertices)", n);
    }
    uint32_t s = seed_vertex;
    double reach = INFINITY; /* the largest mind[] over the candidates left */
    for (uint32_t i = 0; i < k; ++i) {
        out[i] = s;
        mind[s] = -INFINITY;
        if (i + 1 == k) break;
        if (reach == INFINITY) { /* some vertex is still unreached: the whole field */
            rc = gs_db_field(db, s, field, err);
            if (rc) break;
            for (uint32_t v = 0; v < n; ++v)
                if (field[v] < mind[v]) mind[v] = field[v]; /* -inf stays; NaN is ignored */
        } else { /* only vertices within `reach` of s can come closer: mind <= reach */
            gs_neighbors *nb = NULL;
            rc = gs_db_within(db, s, reach, &nb, err);
            if (rc) break;
            for (size_t j = 0; j < nb->n; ++j)
                if (nb->dist[j] < mind[nb->ids[j]]) mind[nb->ids[j]] = nb->dist[j];
            gs_neighbors_free(nb);
        }
        uint32_t best = GS_NONE;
        double best_d = -INFINITY;
        for (uint32_t v = 0; v < n; ++v)
            if (mind[v] > best_d) best_d = mind[v], best = v; /* strict: ties to the lowest id */
        reach = best_d;
        if (best == GS_NONE) { /* cannot happen: k <= the vertices used by faces */
            rc = gs__fail(err, GS_EINTERNAL, "gs_db_farthest_point_sampling: no vertex left for sample %u", i + 1);
            break;
        }
        s = best;
    }
    free(field);
    free(mind);
    return rc;
}
