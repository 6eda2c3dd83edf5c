/* format.c - what the reader and the writer share of format version 6
 * (doc/database-format.md): the checksum, the section sizes and names. */
#include "format.h"

#define HASH_P 0x9E3779B97F4A7C15ull

/* ---- checksum ----------------------------------------------------------- */

static uint64_t load_le64(const unsigned char *p)
{
    uint64_t w;
    memcpy(&w, p, 8);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    w = __builtin_bswap64(w);
#endif
    return w;
}

typedef struct hash_state {
    uint64_t lane[4];
    unsigned j;             /* lane of the next word                  */
    unsigned char part[8];  /* pending partial word                   */
    unsigned n_part;
    uint64_t length;
} hash_state;

static void hash_init(hash_state *h)
{
    memset(h, 0, sizeof *h);
    for (unsigned j = 0; j < 4; ++j) h->lane[j] = 0x243F6A8885A308D3ull + j * 0x13198A2E03707344ull;
}

static void hash_word(hash_state *h, uint64_t w)
{
    h->lane[h->j] = (h->lane[h->j] ^ w) * HASH_P;
    h->j = (h->j + 1) & 3u;
}

static void hash_bytes(hash_state *h, const unsigned char *p, size_t n)
{
    h->length += n;
    while (n && h->n_part) { /* finish a partial word first */
        h->part[h->n_part++] = *p++;
        --n;
        if (h->n_part == 8) {
            hash_word(h, load_le64(h->part));
            h->n_part = 0;
        }
    }
    if (h->j == 0) { /* fast path: four lanes in step */
        uint64_t a = h->lane[0], b = h->lane[1], c = h->lane[2], d = h->lane[3];
        for (; n >= 32; n -= 32, p += 32) {
            a = (a ^ load_le64(p)) * HASH_P;
            b = (b ^ load_le64(p + 8)) * HASH_P;
            c = (c ^ load_le64(p + 16)) * HASH_P;
            d = (d ^ load_le64(p + 24)) * HASH_P;
        }
        h->lane[0] = a, h->lane[1] = b, h->lane[2] = c, h->lane[3] = d;
    }
    for (; n >= 8; n -= 8, p += 8) hash_word(h, load_le64(p));
    while (n--) h->part[h->n_part++] = *p++;
}

static uint64_t hash_final(hash_state *h)
{
    if (h->n_part) {
        memset(h->part + h->n_part, 0, 8 - h->n_part);
        hash_word(h, load_le64(h->part));
    }
    uint64_t r = h->length * HASH_P;
    for (unsigned j = 0; j < 4; ++j) {
        r = (r ^ h->lane[j]) * HASH_P;
        r ^= r >> 29;
    }
    return r;
}

uint64_t gs__db_checksum(const void *a, size_t na, const void *b, size_t nb)
{
    hash_state h;
    hash_init(&h);
    hash_bytes(&h, a, na);
    if (b && nb) hash_bytes(&h, b, nb);
    return hash_final(&h);
}

/* ---- layout ------------------------------------------------------------- */

int gs__db_host_little_endian(void)
{
    const uint32_t one = 1;
    unsigned char c;
    memcpy(&c, &one, 1);
    return c == 1;
}

const char *const gs__db_section_name[GS__SEC_MAX + 1] = {
    "?",          "positions",  "leaves", "nodes",       "curves",    "vertex_index",
    "records",    "leaf_nodes", "leaf_local", "leaf_q", "alias_index", "alias_list", "near_pairs"};

uint32_t gs__db_section_ids(uint32_t flags, uint32_t ids[GS__SEC_MAX])
{
    uint32_t n = 0;
    for (uint32_t s = GS__SEC_POSITIONS; s <= GS__SEC_RECORDS; ++s) ids[n++] = s;
    if (flags & GS__DB_FLAG_LEAF_EXACT)
        for (uint32_t s = GS__SEC_LEAF_NODES; s <= GS__SEC_LEAF_Q; ++s) ids[n++] = s;
    if (flags & GS__DB_FLAG_ALIASES)
        for (uint32_t s = GS__SEC_ALIAS_INDEX; s <= GS__SEC_ALIAS_LIST; ++s) ids[n++] = s;
    if (flags & GS__DB_FLAG_NEAR) ids[n++] = GS__SEC_NEAR;
    return n;
}

int gs__db_layout(const gs__db_counts *c, uint64_t size[GS__SEC_MAX + 1])
{
    const uint64_t lim = (uint64_t)1 << 62;
    if (c->records_bytes > lim || c->leaf_entries > lim / 8 || c->alias_entries > lim / 8) return 0;
    memset(size, 0, sizeof(uint64_t) * (GS__SEC_MAX + 1));
    size[GS__SEC_POSITIONS] = 24 * (uint64_t)c->nv;
    size[GS__SEC_LEAVES] = gs__pad8(4 * (uint64_t)c->nv);
    size[GS__SEC_NODES] = gs__pad8(20 * (uint64_t)c->n_nodes);
    size[GS__SEC_CURVES] = 24 * (uint64_t)c->n_curves;
    size[GS__SEC_INDEX] = gs__pad8(4 * ((uint64_t)c->nv + 1));
    size[GS__SEC_RECORDS] = c->records_bytes;
    if (c->flags & GS__DB_FLAG_LEAF_EXACT) {
        size[GS__SEC_LEAF_NODES] = 16 * (uint64_t)c->n_nodes;
        size[GS__SEC_LEAF_LOCAL] = gs__pad8((c->flags & GS__DB_FLAG_LEAF_LOCAL16 ? 2 : 1) * (uint64_t)c->nv);
        size[GS__SEC_LEAF_Q] = gs__pad8(2 * c->leaf_entries);
    }
    if (c->flags & GS__DB_FLAG_ALIASES) {
        size[GS__SEC_ALIAS_INDEX] = 8 * ((uint64_t)c->alias_exceptions + 1);
        size[GS__SEC_ALIAS_LIST] = gs__pad8(4 * c->alias_entries);
    }
    return 1;
}
