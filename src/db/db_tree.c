/* db_tree.c - read-only access to the database's bisection tree (the nodes'
 * parents and depths) and to each vertex's leaf, for code outside src/db
 * that needs the tree's shape (the renderer draws the separators from it). */
#include "db_internal.h"

uint32_t gs_db_vertex_leaf(const gs_db *db, uint32_t v)
{
    return db && v < db->nv ? db->leaf[v] : GS_NONE;
}

int gs_db_tree_node(const gs_db *db, uint32_t node, uint32_t *parent, uint32_t *depth, gs_error *err)
{
    if (!db) return gs__fail(err, GS_EARG, "gs_db_tree_node: db is NULL");
    if (node >= db->n_nodes)
        return gs__fail(err, GS_EARG, "gs_db_tree_node: node %u out of range (the database has %u nodes)", node,
                        db->n_nodes);
    if (parent) *parent = db->nodes[node].parent;
    if (depth) *depth = db->nodes[node].depth;
    return GS_OK;
}
