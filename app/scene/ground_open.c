/*
 * ground_open.c - tp_ground_open (ground.h): a DEM or store path opened for ground queries by a
 * command, the DEM built into the store cache first as `terrapatch view` builds it. Apart from
 * ground.c so that the queries link without the store build behind the cache.
 */
#include "ground.h"

#include "cli.h"
#include "store_cache.h"
#include "terrain_open.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct opened {
    tp_store_scene sc;
    char store_path[4096]; /* sc.path points here */
    int temporary;         /* a store built in a temporary folder: removed when done */
} opened;

static void release(void* owner)
{
    opened* op = owner;
    tp_store_scene_close(&op->sc);
    if (op->temporary)
        tp_store_cache_remove_temporary(op->store_path);
    free(op);
}

int tp_ground_open(const char* path, const tp_ground_options* o, tp_ground** out)
{
    tp_ground_options opts = o ? *o : (tp_ground_options){0};
    opened* op = calloc(1, sizeof *op);
    if (!op) {
        tp_cli_error("%s: out of memory", path);
        return TP_EXIT_FAILURE;
    }
    /* a DEM's store: the options view uses by default, so that both share one cached store */
    tp_scene_options dem;
    tp_scene_options_default(&dem);
    int code =
        tp_terrain_store(opts.cmd ? opts.cmd : "point", path, opts.dem ? opts.dem : &dem,
                         opts.cache_dir, op->store_path, sizeof op->store_path, &op->temporary);
    if (code != TP_EXIT_OK) {
        free(op);
        return code;
    }
    code = tp_store_scene_open(op->store_path, &op->sc);
    if (code != TP_EXIT_OK) {
        op->sc = (tp_store_scene){0};
        release(op);
        return code;
    }
    tp_ground* g = NULL;
    tp_error err = {{0}};
    if (tp_ground_create(&op->sc, &opts, &g, &err) != TP_OK) {
        tp_cli_error("%s: %s", path, err.message);
        release(op);
        return TP_EXIT_FAILURE;
    }
    tp__ground_set_owner(g, release, op);
    *out = g;
    return TP_EXIT_OK;
}
