/*
 * store_cut.h - what a store export (store_export.c) shares with the cuts it draws: a camera's
 * and --full's (store_cut.c), --max-error's (store_cut_max_error.c). The export's state, its
 * one-line failures, and the nodes a static cut chooses before they are installed as the cut.
 */
#ifndef TP_APP_STORE_CUT_H
#define TP_APP_STORE_CUT_H

#include "store_export.h"
#include "store_mesh.h"
#include "store_tin.h"

#include <stddef.h>
#include <stdint.h>

/* One export: the store open, its nodes read here (res), the cut that draws them. */
typedef struct store_export {
    const tp_store_export_request* r;
    tp_store_scene sc;
    const tp_tree_geometry* g;
    const tp_node_meta* metas;
    residency res;
    leaf_cache* cache;
    tp_cut* cut;
    tp_tin_cache* tins;     /* r->view_tins: the cut's TINs, built as it asks */
    double step_m, unit, quant_m;
    int n;
    size_t tris_cut;        /* triangles of the final cut (for the size check) */
    size_t drawn;           /* nodes of the final cut */
    tp_store_tin_stats tin; /* r->tin: the tiles built */
} store_export;

/* The export's failures (store_export.c): one line on stderr naming the store, and
 * TP_EXIT_FAILURE. tp_store_export_fail prints "STORE: WHAT" (just WHAT when it names the store
 * already); tp_store_export_too_many, "STORE: HOW TRIS triangles, over the export limit of
 * TP_STORE_EXPORT_MAX_TRIANGLES; export a coarser mesh ..." for a mesh over that limit. */
int tp_store_export_fail(store_export* x, const char* what);
int tp_store_export_too_many(store_export* x, size_t tris, const char* how);

/* 1 if `more` bytes fit in what the process may still use (TP_MEMORY_LIMIT, ulimit -v, the
 * cgroup, MemAvailable), else 0 after one line saying what needs them. */
int tp_store_export_room_for(store_export* x, uint64_t more, const char* what);

/* ---- the cuts (each returns TP_EXIT_*, after a message on failure) ---- */

/* The camera's cut with every node it draws resident: update, read what it requests, again,
 * until it requests nothing (then nothing is substituted); x->tris_cut its triangles. */
int tp_store_cut_camera(store_export* x, const tp_camera* cam, const tp_lod_params* lod);

/* --full: every leaf at level n (the size was checked before). */
int tp_store_cut_full(store_export* x);

/* --max-error M (x->r->max_error_m): a static crack-free cut whose every drawn node's bound is
 * <= M (store_cut_max_error.c); x->tris_cut its triangles. */
int tp_store_cut_max_error(store_export* x);

/* ---- the nodes a static cut chooses (store_cut.c) ---- */

typedef struct choice {
    int8_t* level; /* per node: drawn level, -1 when not chosen */
    int64_t* ids;  /* chosen ids (may hold stale ones: level -1) */
    size_t count, cap;
    uint8_t* keep; /* per node, all 0 between installs: tp_choice_install's */
} choice;

/* Nothing chosen yet, for x's tree; TP_EXIT_OK, or a failure (out of memory). Free it with
 * tp_choice_free either way. */
int tp_choice_init(store_export* x, choice* ch);
void tp_choice_free(choice* ch);

/* Chooses node id at level k; 0 when out of memory. */
int tp_choice_add(choice* ch, int64_t id, int k);

/* Installs the chosen nodes as the cut (tp_cut_set_nodes stitches them) with them resident and
 * nothing else. */
int tp_choice_install(store_export* x, choice* ch);

#endif
