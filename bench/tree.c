/* tree.c - timing of the nested bisection tree (paper sec. 3.1, 4.1):
 * bench_tree [--dump FILE] MESH_OR_SPEC... prints nodes, depth, curves and
 * seconds; --dump writes every curve's sample positions (text) to FILE. */
#include "geosep.h"
#include "../src/partition/tree.h"

#include <stdio.h>
#include <string.h>

static void dump(const gs_mesh *m, const gs__tree *t, const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f) return;
    for (uint32_t k = 0; k < t->n_curves; ++k) {
        const gs__sep_curve *c = &t->curves[k];
        fprintf(f, "c %u %u %u\n", t->nodes[c->node].depth, c->closed, c->n_samples);
        for (uint32_t j = 0; j < c->n_samples; ++j) {
            const gs__sep_sample *s = &t->samples[c->sample_start + j];
            double p[3] = {0, 0, 0};
            for (int i = 0; i < 3; ++i)
                for (int d = 0; d < 3; ++d)
                    p[d] += s->bary[i] * m->xyz[3 * (size_t)m->tri[3 * (size_t)s->face + i] + d];
            fprintf(f, "%.9g %.9g %.9g\n", p[0], p[1], p[2]);
        }
    }
    fclose(f);
}

int main(int argc, char **argv)
{
    const char *dump_path = NULL;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--dump") && i + 1 < argc) {
            dump_path = argv[++i];
            continue;
        }
        gs_mesh *m = NULL;
        gs_error err = {0};
        int rc = strchr(argv[i], ':') && !strchr(argv[i], '/')
                     ? gs_mesh_generate(argv[i], &m, &err)
                     : gs_mesh_load(argv[i], GS_FORMAT_AUTO, &m, &err);
        if (rc) {
            fprintf(stderr, "%s: %s\n", argv[i], err.message);
            return 1;
        }
        gs__tree_options opt;
        gs__tree_options_default(&opt);
        gs__tree *t = NULL;
        double t0 = gs__now();
        rc = gs__tree_build(m, &opt, &t, &err);
        double s = gs__now() - t0;
        if (rc) {
            fprintf(stderr, "%s: %s\n", argv[i], err.message);
            return 1;
        }
        printf("%s: %u vertices, %u nodes, %u leaves, depth %.2f/%u, %.2f curves/sep, "
               "%.1f samples/curve, %zu face refs (%.1f/face), %.3f s\n",
               argv[i], gs_mesh_num_vertices(m), t->n_nodes, t->n_leaves, t->avg_leaf_depth,
               t->max_depth, t->avg_curves_per_separator, t->avg_samples_per_curve,
               t->n_face_refs, (double)t->n_face_refs / gs_mesh_num_faces(m), s);
        if (dump_path) dump(m, t, dump_path);
        gs__tree_free(t);
        gs_mesh_free(m);
    }
    return 0;
}
