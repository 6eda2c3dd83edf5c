/* heap.h - an indexed binary min-heap of (key, id) with decrease-key, for
 * Dijkstra-like propagation over ids 0..capacity-1. Header-only, internal. */
#ifndef GS_HEAP_H
#define GS_HEAP_H

#include <stdint.h>
#include <stdlib.h>

typedef struct gs__iheap {
    uint32_t n, cap;
    uint32_t *ids;  /* heap order -> id          */
    uint32_t *pos;  /* id -> heap slot or UINT32_MAX */
    double *key;    /* id -> key                 */
} gs__iheap;

static inline int gs__iheap_init(gs__iheap *h, uint32_t cap)
{
    h->n = 0;
    h->cap = cap;
    h->ids = malloc((cap ? cap : 1) * sizeof *h->ids);
    h->pos = malloc((cap ? cap : 1) * sizeof *h->pos);
    h->key = malloc((cap ? cap : 1) * sizeof *h->key);
    if (!h->ids || !h->pos || !h->key) return -1;
    for (uint32_t i = 0; i < cap; ++i) h->pos[i] = UINT32_MAX;
    return 0;
}

static inline void gs__iheap_free(gs__iheap *h)
{
    free(h->ids);
    free(h->pos);
    free(h->key);
    h->ids = h->pos = NULL;
    h->key = NULL;
}

/* Empty the heap in O(n) of its current size. */
static inline void gs__iheap_clear(gs__iheap *h)
{
    for (uint32_t i = 0; i < h->n; ++i) h->pos[h->ids[i]] = UINT32_MAX;
    h->n = 0;
}

static inline void gs__iheap_up(gs__iheap *h, uint32_t i)
{
    uint32_t id = h->ids[i];
    double k = h->key[id];
    while (i > 0) {
        uint32_t p = (i - 1) / 2;
        if (h->key[h->ids[p]] <= k) break;
        h->ids[i] = h->ids[p];
        h->pos[h->ids[i]] = i;
        i = p;
    }
    h->ids[i] = id;
    h->pos[id] = i;
}

static inline void gs__iheap_down(gs__iheap *h, uint32_t i)
{
    uint32_t id = h->ids[i];
    double k = h->key[id];
    for (;;) {
        uint32_t c = 2 * i + 1;
        if (c >= h->n) break;
        if (c + 1 < h->n && h->key[h->ids[c + 1]] < h->key[h->ids[c]]) c++;
        if (h->key[h->ids[c]] >= k) break;
        h->ids[i] = h->ids[c];
        h->pos[h->ids[i]] = i;
        i = c;
    }
    h->ids[i] = id;
    h->pos[id] = i;
}

/* Insert id with key, or lower its key if present and larger. */
static inline void gs__iheap_push_or_decrease(gs__iheap *h, uint32_t id, double key)
{
    if (h->pos[id] == UINT32_MAX) {
        h->key[id] = key;
        h->ids[h->n] = id;
        h->pos[id] = h->n;
        h->n++;
        gs__iheap_up(h, h->n - 1);
    } else if (key < h->key[id]) {
        h->key[id] = key;
        gs__iheap_up(h, h->pos[id]);
    }
}

/* Remove and return the id with the smallest key (heap must not be empty). */
static inline uint32_t gs__iheap_pop(gs__iheap *h, double *key)
{
    uint32_t id = h->ids[0];
    if (key) *key = h->key[id];
    h->pos[id] = UINT32_MAX;
    h->n--;
    if (h->n) {
        h->ids[0] = h->ids[h->n];
        h->pos[h->ids[0]] = 0;
        gs__iheap_down(h, 0);
    }
    return id;
}

#endif
