/*
 * cmd_imagery.h - imagery pyramids (.tpi) from the command line (cmd_imagery.c): `terrapatch
 * imagery STORE.tpt IMAGE...`, and the same work after `terrapatch build ... --imagery IMAGE`.
 */
#ifndef TP_APP_CMD_IMAGERY_H
#define TP_APP_CMD_IMAGERY_H

typedef struct tp_imagery_cli {
    const char* const* images; /* count source rasters, later ones drawn over earlier ones */
    int count;
    const char* out;     /* NULL: the store's path with .tpi for .tpt */
    int texel_shift;     /* TP_IMAGERY_SHIFT_AUTO unless given */
    double resolution_m; /* > 0: the texel size wanted (the nearest power of two of the grid's) */
    int memory_mb;
    int threads;      /* 0: every core */
    const char* json; /* NULL, "-" or a path */
    int quiet;
    const char* who; /* "imagery" or "build" (the lines' prefix is tp_cli_prefix's) */
} tp_imagery_cli;

/* The pyramid of store_path's grid (its CRS, geotransform and source width x height) from
 * c->images, written atomically; progress and a summary on stderr unless quiet. Returns an exit
 * code (app/base/cli.h), having printed one line for a failure. */
int tp_imagery_cli_run(const char* store_path, const tp_imagery_cli* c);

/* The default output of a store: its path with ".tpi" in place of ".tpt" (appended when it
 * does not end so); of a store's URL, its last name so in the current folder. Malloc'd; NULL
 * when out of memory. */
char* tp_imagery_default_path(const char* store_path);

#endif /* TP_APP_CMD_IMAGERY_H */
