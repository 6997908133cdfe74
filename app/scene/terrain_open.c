/* terrain_open.c - what a path names, and the store a command reads for it (terrain_open.h). */
#define _POSIX_C_SOURCE 200809L
#include "terrain_open.h"

#include "cli.h"
#include "store_cache.h"
#include "store_scene.h"

#include "tp_io.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

static int named_tpt(const char* path)
{
    const size_t len = strlen(path);
    return len > 4 && !strcasecmp(path + len - 4, ".tpt");
}

/* 1 when a regular file's first bytes look like a store's magic (0x89 "TPT"), whole or not. */
static int starts_like_store(const char* path)
{
    unsigned char head[4];
    return tp_file_head(path, head, sizeof head) && !memcmp(head + 1, "TPT", 3);
}

int tp_terrain_kind_of(const char* path)
{
    if (tp_is_store_path(path))
        return TP_TERRAIN_STORE;
    if (tp_input_is_url(path)) {
        tp_error err;
        unsigned char head[8];
        if (tp_input_url_head(path, head, sizeof head, &err) != TP_OK)
            tp_cli_error("%s", err.message);
        else
            tp_cli_error("%s: not a terrapatch store (its first bytes are not a store's magic): "
                         "over HTTP terrapatch reads stores (.tpt) and their pyramids; read a "
                         "DEM on a server as /vsicurl/%s",
                         path, path);
        return -1;
    }
    if (tp_input_is_virtual(path)) {
        if (named_tpt(path)) {
            tp_cli_error("%s: a store inside a GDAL virtual path cannot be read "
                         "(stores are read from local files): extract it first",
                         path);
            return -1;
        }
        return TP_TERRAIN_DEM;
    }
    struct stat st;
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode) && access(path, R_OK) != 0)
        return named_tpt(path) ? TP_TERRAIN_STORE : TP_TERRAIN_DEM; /* its reader says why */
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode) &&
        (named_tpt(path) || starts_like_store(path))) {
        tp_cli_error("%s: not a terrapatch store, or its header is damaged (its "
                     "first 8 bytes are not a store's magic; %lld bytes): rebuild it with "
                     "terrapatch build",
                     path, (long long)st.st_size);
        return -1;
    }
    return TP_TERRAIN_DEM;
}

int tp_terrain_refuse_store_options(const char* cmd, const char* path, const tp_scene_options* o)
{
    (void)cmd; /* messages name the command main() dispatched to (tp_cli_error) */
    if (!o || !o->given)
        return -1;
    char names[160];
    tp_scene_options_names(o->given, names, sizeof names);
    tp_cli_error("%s is a store: %s shape%s a DEM when it is read or built; a "
                 "store keeps those it was built with (build it again from the DEM with "
                 "terrapatch build)",
                 path, names, strchr(names, ',') ? "" : "s");
    return TP_EXIT_USAGE;
}

int tp_terrain_classify(const char* cmd, const char* path, const tp_scene_options* o, int* is_store)
{
    const int kind = tp_terrain_kind_of(path);
    if (kind < 0)
        return TP_EXIT_FAILURE;
    *is_store = kind == TP_TERRAIN_STORE;
    return *is_store ? tp_terrain_refuse_store_options(cmd, path, o) : -1;
}

/* tp_terrain_store, and tp_terrain_store_begin when job is given. */
static int terrain_store(const char* cmd, const char* path, const tp_scene_options* o,
                         const char* cache_dir, char* out, size_t cap, int* temporary,
                         double preview_samples, char* preview, size_t pcap,
                         tp_store_cache_job** job)
{
    *temporary = 0;
    int is_store, code = tp_terrain_classify(cmd, path, o, &is_store);
    if (code >= 0)
        return code;
    if (is_store) {
        if (snprintf(out, cap, "%s", path) >= (int)cap) {
            tp_cli_error("%s: the path is too long", path);
            return TP_EXIT_FAILURE;
        }
        return TP_EXIT_OK;
    }
    tp_scene_options dflt;
    if (!o) {
        tp_scene_options_default(&dflt);
        o = &dflt;
    }
    /* a heightmap image placed with --spacing/--zscale/--origin: made a georeferenced GeoTIFF
     * in the cache first (once), whose store is then built as any DEM's */
    char placed[4096];
    tp_scene_options eff;
    if (o->image_given) {
        code = tp_store_cache_heightmap(path, &o->image, cache_dir, placed, sizeof placed);
        if (code != TP_EXIT_OK)
            return code;
        eff = *o;
        eff.image_given = 0;
        eff.given &= ~(unsigned)(TP_SCENE_GIVEN(TP_OPT_SPACING) | TP_SCENE_GIVEN(TP_OPT_ZSCALE) |
                                 TP_SCENE_GIVEN(TP_OPT_ORIGIN));
        o = &eff;
        path = placed;
    }
    const unsigned whole_only = o->given & ~(unsigned)TP_SCENE_STORE_OPTIONS;
    if (whole_only) {
        char names[160];
        tp_scene_options_names(whole_only, names, sizeof names);
        tp_cli_error("%s shape%s a DEM drawn whole (view --whole, export, "
                     "bench, info); %s reads %s through its store, which takes any size and "
                     "is built from what GDAL reads",
                     names, strchr(names, ',') ? "" : "s", cmd, path);
        return TP_EXIT_USAGE;
    }
    tp_store_cache_options co = {.cache_dir = cache_dir,
                                 .patch_size = o->patch_size,
                                 .crs = o->grid.crs,
                                 .resampling = o->grid.resampling,
                                 .fill_max_px = o->grid.fill_max_px,
                                 .fill_from = o->grid.fill_from,
                                 .z_unit = o->z_unit,
                                 .cmd = cmd};
    if (job)
        return tp_store_cache_begin(path, &co, preview_samples, out, cap, temporary, preview,
                                    pcap, job);
    return tp_store_cache_get(path, &co, out, cap, temporary);
}

int tp_terrain_store(const char* cmd, const char* path, const tp_scene_options* o,
                     const char* cache_dir, char* out, size_t cap, int* temporary)
{
    return terrain_store(cmd, path, o, cache_dir, out, cap, temporary, 0, NULL, 0, NULL);
}

int tp_terrain_store_begin(const char* cmd, const char* path, const tp_scene_options* o,
                           const char* cache_dir, double preview_samples, char* out, size_t cap,
                           int* temporary, char* preview, size_t pcap, tp_store_cache_job** job)
{
    *job = NULL;
    if (pcap)
        preview[0] = '\0';
    return terrain_store(cmd, path, o, cache_dir, out, cap, temporary, preview_samples, preview,
                         pcap, job);
}
