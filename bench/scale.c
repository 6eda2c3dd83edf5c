/* scale.c - the scaling benchmark (paper Figure 9, issue 4): one shape at
 * several resolutions (bunny-5k, -10k, -20k, stanford-bunny from ../shared)
 * and homer-60k, subdivided 1-to-4 once and twice by the benchmark itself.
 * For each mesh, in a child process (so that its peak memory is its own):
 * n, build time per stage, peak memory, bytes per vertex, query times
 * (single queries: median; one after the other: median of 1000-query
 * means; the batch API) and their ratios to the first mesh's, also
 * measured paired: both databases, kept in temporary files, timed in
 * alternating rounds, each in a fresh process, so that the ratio does not
 * ride on how busy a shared machine was in each mesh's minutes; then the
 * fitted exponent of build time (wall, and CPU over all threads) against n
 * (the paper expects 1.5). Usage:
 *   bench_scale [--method exact|graph|fmm|heat|dgg] [--threads N] [--max-samples N]
 *               [--heat-refine N|auto] [--dgg-eps E] [--max-n N] [MESH|SPEC ...]
 * Heat fields are solved on each mesh as it is (--heat-refine 0) unless
 * asked otherwise. */
#define _DEFAULT_SOURCE /* wait4: the peak memory of each child build */
#include "bench_util.h"
#include "geosep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* "name" = a shared mesh, "name*4" / "name*16" = subdivided once / twice,
 * "spec:..." = a generated mesh. */
static int load(const char *what, gs_mesh **m, gs_error *err)
{
    char name[256], path[4096];
    int subdiv = 0;
    snprintf(name, sizeof name, "%s", what);
    char *star = strchr(name, '*');
    if (star) {
        subdiv = strcmp(star + 1, "16") == 0 ? 2 : 1;
        *star = 0;
    }
    int rc;
    if (strchr(name, ':'))
        rc = gs_mesh_generate(name, m, err);
    else {
        snprintf(path, sizeof path, "%s/meshes/%s.obj", GEOSEP_SHARED_DIR, name);
        rc = gs_mesh_load(path, GS_FORMAT_AUTO, m, err);
    }
    for (int i = 0; rc == GS_OK && i < subdiv; ++i) {
        gs_mesh *s = NULL;
        rc = gs_mesh_subdivide(*m, &s, err);
        gs_mesh_free(*m);
        *m = s;
    }
    return rc;
}

/* Query times of n-vertex database db, ns, over random pairs (nb blocks
 * of Q_BATCH for each measure): *single the median of individually timed
 * queries (the clock's own cost subtracted), *seq the median of the
 * 1000-query blocks' means (queries one after the other), *batch the batch
 * API (gs_db_distances, 1000 pairs a call) per pair. */
enum { Q_BATCH = 1000, Q_NB = 300, PAIRED_ROUNDS = 6, PAIRED_NB = 100 };

static uint64_t q_rng = 7;
static void random_pairs(uint32_t *p, int k, uint32_t n)
{
    for (int i = 0; i < 2 * k; ++i) {
        q_rng = q_rng * 6364136223846793005ull + 1442695040888963407ull;
        p[i] = (uint32_t)((q_rng >> 33) % n);
    }
}

static void query_times(const gs_db *db, uint32_t n, int nb, double *single, double *seq, double *batch)
{
    static double t[Q_NB], ts[Q_NB * Q_BATCH], out[Q_BATCH];
    static uint32_t p[2 * Q_BATCH];
    double sink = 0, clock_cost[1000];
    for (int i = 0; i < 1000; ++i) {
        double a = now();
        clock_cost[i] = now() - a;
    }
    qsort(clock_cost, 1000, sizeof *clock_cost, cmp_double);
    for (int b = 0; b < nb; ++b) { /* sequential: batch means */
        random_pairs(p, Q_BATCH, n);
        double t0 = now();
        for (int i = 0; i < Q_BATCH; ++i) sink += gs_db_distance(db, p[2 * i], p[2 * i + 1]);
        t[b] = (now() - t0) / Q_BATCH;
    }
    qsort(t, (size_t)nb, sizeof *t, cmp_double);
    *seq = 1e9 * t[nb / 2];
    for (int b = 0; b < nb; ++b) { /* each timed on its own */
        random_pairs(p, Q_BATCH, n);
        for (int i = 0; i < Q_BATCH; ++i) {
            double t0 = now();
            sink += gs_db_distance(db, p[2 * i], p[2 * i + 1]);
            ts[b * Q_BATCH + i] = now() - t0 - clock_cost[500];
        }
    }
    qsort(ts, (size_t)nb * Q_BATCH, sizeof *ts, cmp_double);
    *single = 1e9 * ts[(size_t)nb * Q_BATCH / 2];
    double tb = 0;
    for (int b = 0; b < nb; ++b) { /* the batch API */
        random_pairs(p, Q_BATCH, n);
        double t0 = now();
        gs_db_distances(db, p, Q_BATCH, out, NULL);
        tb += now() - t0;
        sink += out[0];
    }
    *batch = 1e9 * tb / ((double)nb * Q_BATCH);
    if (sink == 42.4242) puts(""); /* keep the loops */
}

/* Anonymous memory on 2 MiB pages and resident memory, MiB, from
 * /proc/self/smaps_rollup (Linux; -1 elsewhere): the query cache asks for
 * huge pages, which a fragmented heap may not get. */
static void huge_pages(double *huge, double *rss)
{
    *huge = *rss = -1;
    FILE *f = fopen("/proc/self/smaps_rollup", "r");
    if (!f) return;
    char line[256];
    double kb;
    while (fgets(line, sizeof line, f)) {
        if (sscanf(line, "AnonHugePages: %lf kB", &kb) == 1) *huge = kb / 1024;
        else if (sscanf(line, "Rss: %lf kB", &kb) == 1) *rss = kb / 1024;
    }
    fclose(f);
}

/* The child: build, measure, print one line "n tree fields fits total bpv
 * query seq batch cost"; on stderr, how much of its memory is on huge
 * pages. keep (may be NULL): where to save the database for the paired
 * rounds. */
static int run_one(const char *what, const gs_build_options *opt, int fd, const char *keep)
{
    gs_mesh *m = NULL;
    gs_error err;
    if (load(what, &m, &err)) {
        fprintf(stderr, "bench_scale: %s: %s\n", what, err.message);
        return 1;
    }
    gs_db *db = NULL;
    gs_build_stats st;
    struct rusage r0, r1;
    getrusage(RUSAGE_SELF, &r0);
    if (gs_db_build(m, opt, &db, &st, &err)) {
        fprintf(stderr, "bench_scale: %s: %s\n", what, err.message);
        return 1;
    }
    getrusage(RUSAGE_SELF, &r1);
    double cpu = (double)(r1.ru_utime.tv_sec - r0.ru_utime.tv_sec) + 1e-6 * (double)(r1.ru_utime.tv_usec - r0.ru_utime.tv_usec) +
                 (double)(r1.ru_stime.tv_sec - r0.ru_stime.tv_sec) + 1e-6 * (double)(r1.ru_stime.tv_usec - r0.ru_stime.tv_usec);
    gs_mesh_free(m);
    gs_db_info info;
    gs_db_get_info(db, &info, &err);
    double qs, qq, qb, huge, rss;
    query_times(db, info.n_vertices, Q_NB, &qs, &qq, &qb);
    huge_pages(&huge, &rss);
    if (huge >= 0) fprintf(stderr, "%s: while querying, %.0f of %.0f MiB resident on 2 MiB pages\n", what, huge, rss);
    int kept = keep && gs_db_save(db, keep, &err) == GS_OK;
    if (keep && !kept) fprintf(stderr, "bench_scale: %s: not kept for the paired rounds: %s\n", what, err.message);
    dprintf(fd, "%u %.3f %.3f %.3f %.3f %.1f %.1f %.1f %.1f %.2f %d %.3f\n", info.n_vertices, st.seconds_tree,
            st.seconds_fields, st.seconds_fits, st.seconds_total, info.bytes_per_vertex, qs, qq, qb, info.cost, kept,
            cpu);
    gs_db_free(db);
    return 0;
}

/* A paired round's child: open the database at path, run untimed random
 * queries (so that it starts from its steady state, its cache in the L3 if
 * it fits), then time it; prints "single seq batch" (ns). */
static int time_one(const char *path, int fd)
{
    gs_db *db = NULL;
    gs_db_info info;
    gs_error err;
    if (gs_db_open(path, &db, &err) || gs_db_get_info(db, &info, &err)) {
        fprintf(stderr, "bench_scale: %s: %s\n", path, err.message);
        return 1;
    }
    static uint32_t p[2 * Q_BATCH];
    double sink = 0, qs, qq, qb;
    for (int b = 0; b < PAIRED_NB; ++b) {
        random_pairs(p, Q_BATCH, info.n_vertices);
        for (int i = 0; i < Q_BATCH; ++i) sink += gs_db_distance(db, p[2 * i], p[2 * i + 1]);
    }
    query_times(db, info.n_vertices, PAIRED_NB, &qs, &qq, &qb);
    dprintf(fd, "%.1f %.1f %.1f\n", qs, qq, qb);
    if (sink == 42.4242) puts(""); /* keep the warm-up */
    gs_db_free(db);
    return 0;
}

/* Fork fn's child (run_one or time_one through a small trampoline) and
 * read its line into line (size bytes, read to its end); *ru its resource
 * use. Returns the number of bytes read (<= 0: nothing). */
typedef int (*child_fn)(const void *arg, int fd);
static ssize_t in_child(child_fn fn, const void *arg, char *line, size_t size, struct rusage *ru)
{
    int pfd[2];
    if (pipe(pfd)) return -1;
    pid_t pid = fork();
    if (pid < 0) {
        close(pfd[0]), close(pfd[1]);
        return -1;
    }
    if (pid == 0) {
        close(pfd[0]);
        _exit(fn(arg, pfd[1]));
    }
    close(pfd[1]);
    ssize_t k = 0, got;
    while (k < (ssize_t)size - 1 && (got = read(pfd[0], line + k, size - 1 - (size_t)k)) > 0) k += got;
    line[k > 0 ? k : 0] = '\0';
    close(pfd[0]);
    int status = 0;
    wait4(pid, &status, 0, ru);
    return k;
}

typedef struct build_arg {
    const char *what, *keep;
    const gs_build_options *opt;
} build_arg;

static int build_child(const void *arg, int fd)
{
    const build_arg *a = arg;
    return run_one(a->what, a->opt, fd, a->keep);
}

static int time_child(const void *arg, int fd)
{
    return time_one(arg, fd);
}

/* Paired ratios of the database at path against the reference at ref:
 * PAIRED_ROUNDS rounds, each timing both in fresh processes one after the
 * other (their order alternating), so that the ratio does not ride on how
 * busy a shared machine was in each mesh's minutes, and neither database
 * shares a process with the other. r[0..2] the median over the rounds of
 * the single, seq and batch ratios, r[3..5] the lowest, r[6..8] the
 * highest, r[9..11] the reference's median times, r[12..14] the
 * database's. Returns 0 when some round failed. */
static int paired_ratios(const char *path, const char *ref, double r[15])
{
    double q[3][PAIRED_ROUNDS], t[2][3][PAIRED_ROUNDS];
    for (int k = 0; k < PAIRED_ROUNDS; ++k)
        for (int o = 0; o < 2; ++o) {
            int which = (o == 0) == (k % 2 == 0); /* 1: the reference */
            char line[256];
            struct rusage ru;
            double v[3];
            if (in_child(time_child, which ? ref : path, line, sizeof line, &ru) <= 0 ||
                sscanf(line, "%lf %lf %lf", &v[0], &v[1], &v[2]) != 3)
                return 0;
            for (int j = 0; j < 3; ++j) t[which][j][k] = v[j];
        }
    for (int j = 0; j < 3; ++j) {
        for (int k = 0; k < PAIRED_ROUNDS; ++k) q[j][k] = t[0][j][k] / t[1][j][k];
        r[j] = median(q[j], PAIRED_ROUNDS);
        r[3 + j] = q[j][0], r[6 + j] = q[j][PAIRED_ROUNDS - 1];
        r[9 + j] = median(t[1][j], PAIRED_ROUNDS), r[12 + j] = median(t[0][j], PAIRED_ROUNDS);
    }
    return 1;
}

int main(int argc, char **argv)
{
    /* The builder runs its own threads (OpenMP) over batches of heat solves;
     * OpenBLAS threads inside CHOLMOD would only compete with them (measured:
     * ~10% more CPU time on stanford-bunny). OpenBLAS reads the variable
     * when it loads, so set it and start again. */
    if (!getenv("OPENBLAS_NUM_THREADS")) {
        setenv("OPENBLAS_NUM_THREADS", "1", 1);
        execv("/proc/self/exe", argv);
    }
    gs_build_options opt;
    gs_build_options_default(&opt);
    /* heat on every mesh as it is, unless asked: the build's default
     * refines meshes under GS_HEAT_REFINE_AUTO_VERTICES vertices, which
     * would make the small meshes' builds slower and the fitted exponent
     * not the method's */
    opt.solver.heat_refine = 0;
    const char *list[32];
    int nl = 0;
    double max_n = INFINITY;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--method") && i + 1 < argc) {
            gs_error e;
            if (gs_method_from_name(argv[++i], &opt.method, &e)) {
                fprintf(stderr, "bench_scale: %s\n", e.message);
                return 2;
            }
        } else if (!strcmp(argv[i], "--threads") && i + 1 < argc)
            opt.threads = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--max-samples") && i + 1 < argc)
            opt.max_samples = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--heat-refine") && i + 1 < argc) {
            const char *v = argv[++i];
            opt.solver.heat_refine = !strcmp(v, "auto") ? GS_HEAT_REFINE_AUTO : (uint32_t)atoi(v);
        } else if (!strcmp(argv[i], "--dgg-eps") && i + 1 < argc)
            opt.solver.dgg_eps = atof(argv[++i]);
        else if (!strcmp(argv[i], "--max-n") && i + 1 < argc)
            max_n = atof(argv[++i]);
        else if (nl < 32)
            list[nl++] = argv[i];
    }
    static const char *defaults[] = {"bunny-5k", "bunny-10k", "bunny-20k", "stanford-bunny",
                                     "homer-60k", "homer-60k*4", "homer-60k*16"};
    if (nl == 0)
        for (size_t i = 0; i < sizeof defaults / sizeof *defaults; ++i) list[nl++] = defaults[i];
    char refine[16];
    if (opt.solver.heat_refine == GS_HEAT_REFINE_AUTO) snprintf(refine, sizeof refine, "auto");
    else snprintf(refine, sizeof refine, "%u", opt.solver.heat_refine);
    printf("method %s, threads %u, max_samples %u, field_memory_mib %u, heat_refine %s, dgg_eps %g, "
           "OPENBLAS_NUM_THREADS=%s\n",
           gs_method_name(opt.method), opt.threads, opt.max_samples, opt.field_memory_mib, refine, opt.solver.dgg_eps,
           getenv("OPENBLAS_NUM_THREADS") ? getenv("OPENBLAS_NUM_THREADS") : "(unset)");
    printf("%-16s %9s %8s %9s %8s %9s %9s %9s %8s %9s %9s %9s %6s\n", "mesh", "n", "tree s", "fields s", "fits s",
           "total s", "CPU s", "peak MiB", "B/vert", "query ns", "seq ns", "batch ns", "cost");
    double lx[32], ly[32], lc[32], q0[3] = {0, 0, 0};
    const char *first = NULL;
    int nfit = 0;
    /* the databases, kept in temporary files for the paired rounds: the
     * first mesh's for the whole run, each later one's for its own rounds */
    char ref[] = "/tmp/geosep-bench-scale-ref-XXXXXX", cur[] = "/tmp/geosep-bench-scale-XXXXXX";
    int rfd = mkstemp(ref), cfd = mkstemp(cur), have_ref = 0;
    if (rfd >= 0) close(rfd);
    if (cfd >= 0) close(cfd);
    if (rfd < 0 || cfd < 0) fprintf(stderr, "bench_scale: no temporary files: no paired ratios\n");
    for (int i = 0; i < nl; ++i) {
        char line[512];
        struct rusage ru;
        build_arg ba = {list[i], rfd < 0 || cfd < 0 ? NULL : (first ? cur : ref), &opt};
        ssize_t k = in_child(build_child, &ba, line, sizeof line, &ru);
        unsigned n = 0;
        int kept = 0;
        double tt, tf, tfi, tot, bpv, qs, qq, qb, cost, cpu;
        if (k <= 0 || sscanf(line, "%u %lf %lf %lf %lf %lf %lf %lf %lf %lf %d %lf", &n, &tt, &tf, &tfi, &tot, &bpv, &qs,
                             &qq, &qb, &cost, &kept, &cpu) != 12) {
            printf("%-16s skipped (see the message above)\n", list[i]);
            continue;
        }
        printf("%-16s %9u %8.2f %9.2f %8.2f %9.2f %9.2f %9.1f %8.1f %9.0f %9.0f %9.0f %6.1f\n", list[i], n, tt, tf,
               tfi, tot, cpu, ru.ru_maxrss / 1024.0, bpv, qs, qq, qb, cost);
        if (!first) first = list[i], q0[0] = qs, q0[1] = qq, q0[2] = qb, have_ref = kept;
        else {
            printf("%-16s query time / %s's: %.2fx single (median), %.2fx sequential (mean), %.2fx batch\n", "",
                   first, qs / q0[0], qq / q0[1], qb / q0[2]);
            double r[15];
            if (have_ref && kept && paired_ratios(cur, ref, r))
                printf("%-16s paired, %d rounds alternating %s and this mesh, each in a fresh process (median, "
                       "lowest-highest): %.2fx (%.2f-%.2f) single, %.2fx (%.2f-%.2f) sequential, %.2fx (%.2f-%.2f) "
                       "batch; medians, %s %.0f / %.0f / %.0f ns, this mesh %.0f / %.0f / %.0f ns\n",
                       "", PAIRED_ROUNDS, first, r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8], first, r[9],
                       r[10], r[11], r[12], r[13], r[14]);
        }
        fflush(stdout);
        if (n <= max_n && nfit < 32) lx[nfit] = log((double)n), lc[nfit] = log(cpu), ly[nfit++] = log(tot);
    }
    if (rfd >= 0) remove(ref);
    if (cfd >= 0) remove(cur);
    if (nfit >= 2) { /* least-squares slope of log(time) against log(n) */
        double mx = 0, my = 0, mc = 0, sxx = 0, sxy = 0, sxc = 0;
        for (int i = 0; i < nfit; ++i) mx += lx[i] / nfit, my += ly[i] / nfit, mc += lc[i] / nfit;
        for (int i = 0; i < nfit; ++i)
            sxx += (lx[i] - mx) * (lx[i] - mx), sxy += (lx[i] - mx) * (ly[i] - my), sxc += (lx[i] - mx) * (lc[i] - mc);
        printf("fitted exponent of build time against n: %.2f wall, %.2f CPU (paper, Figure 9: 1.5)\n",
               sxx > 0 ? sxy / sxx : 0, sxx > 0 ? sxc / sxx : 0);
    }
    return 0;
}
