/* db_internal.h - an opened database (struct gs_db): the file's bytes,
 * validated at attach (doc/database-format.md, format version 6) and used
 * in place; nothing is built at open. The packer the builder calls.
 * Internal. */
#ifndef GS_DB_INTERNAL_H
#define GS_DB_INTERNAL_H

#include "db_content.h"
#include "db_near.h"
#include "format.h"

#include <stddef.h>
#include <stdint.h>

struct gs_db {
    /* storage: either a mapping (munmap) or a malloc'ed buffer (free) */
    void *storage;
    size_t storage_size;
    int mapped;
    const unsigned char *bytes; /* the whole file                         */
    uint64_t size;
    /* header */
    uint32_t nv, n_nodes, n_curves, n_leaves, max_depth;
    uint64_t n_functions, records_bytes, leaf_entries;
    uint32_t version; /* the file's format version (GS__DB_VERSION_MIN..) */
    uint32_t flags, build_flags, method, vmax, mmax;
    double avg_depth, tol, cost;
    double sample_spacing, heat_time, fmm_exact_start, dgg_eps;
    uint32_t seed, max_samples;
    uint32_t n_input, alias_exceptions; /* n_input: nv without aliases      */
    uint64_t alias_entries;
    /* sections, in place */
    const double *xyz;
    const uint32_t *leaf;
    const gs__db_node *nodes;
    const gs__db_disk_curve *curves;
    const uint32_t *index;         /* nv+1: records in 2-byte units          */
    const unsigned char *records;
    /* leaf tables (NULL without): per node, its table; per vertex, its
     * number in its leaf (u8, or u16 with GS__DB_FLAG_LEAF_LOCAL16) */
    const gs__db_leaf_node *leaf_nodes;
    const uint8_t *leaf_local8;
    const uint16_t *leaf_local16;
    const uint16_t *leaf_q;
    /* input-id aliases (NULL without) */
    const gs__db_alias_head *alias_index; /* alias_exceptions + 1          */
    const uint32_t *alias_list;
    gs__db_near near;              /* near.start NULL without the section   */
    /* data a later stage derives from the file on first use and keeps (the
     * neighbourhood bounds of src/query/within.c): NULL until then; set
     * once with an atomic compare-and-swap; gs_db_free calls its free */
    struct gs__db_derived *derived;
};

/* Vertex x's number in its leaf (leaf tables present). */
static inline uint32_t gs__db_leaf_local(const gs_db *db, uint32_t x)
{
    return db->leaf_local8 ? db->leaf_local8[x] : db->leaf_local16[x];
}

/* The head of such derived data. */
typedef struct gs__db_derived {
    void (*free)(struct gs__db_derived *self);
} gs__db_derived;

/* Vertex x's record: its nf minima (u16) then its function blocks;
 * *end receives the byte after it. Guaranteed in bounds by the structural
 * validation (index increasing, last entry = records_bytes). */
static inline const unsigned char *gs__db_record(const gs_db *db, uint32_t x, const unsigned char **end)
{
    *end = db->records + GS__DB_RECORD_UNIT * (uint64_t)db->index[x + 1];
    return db->records + GS__DB_RECORD_UNIT * (uint64_t)db->index[x];
}

/* Serialise c into the on-disk layout and attach the result. *out: new
 * database (gs_db_free). */
int gs__db_pack(const gs__db_content *c, gs_db **out, gs_error *err);

/* Validate the structure of `size` bytes (checksums too when verify) and
 * wrap them in a database. On success the database owns `storage`
 * (munmap'ed if mapped, else freed); on failure the caller keeps it.
 * `name` prefixes messages ("db.gsdb: ..."). */
int gs__db_attach(void *storage, size_t size, int mapped, const char *name, int verify, gs_db **out,
                  gs_error *err);

#endif
