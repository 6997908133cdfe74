/*
 * cmd_imagery.c - `terrapatch imagery STORE.tpt IMAGE... [-o OUT.tpi]`: orthophotos or scanned
 * maps warped onto a store's render grid as a mip pyramid of blocks (tp_imagery_build,
 * docs/imagery.md), which the viewer streams. tp_imagery_cli_run is also what `terrapatch build
 * --imagery` calls once its store is written.
 */
#include "terrapatch.h"
#include "cmd_imagery.h"
#include "clock.h"

#include "atomic_file.h"
#include "cli.h"
#include "json.h"
#include "memory.h"
#include "options.h"
#include "output_check.h"
#include "progress.h"

#include "tp_core.h"
#include "tp_imagery.h"
#include "tp_io.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The smallest --memory accepted (MB), as build's */
#define IMAGERY_MIN_MEMORY_MB 64

char* tp_imagery_default_path(const char* store_path)
{
    if (tp_input_is_url(store_path)) /* its last name, in the current folder */
        store_path = strrchr(store_path, '/') + 1;
    size_t n = strlen(store_path);
    char* p = malloc(n + 5);
    if (!p)
        return NULL;
    memcpy(p, store_path, n + 1);
    if (n >= 4 && !strcmp(p + n - 4, ".tpt"))
        n -= 4;
    memcpy(p + n, ".tpi", 5);
    return p;
}

/* tp_imagery_build_options.progress: the share done */
static void on_progress(void* user, double f)
{
    tp_progress_update(user, f, 1.0, -1.0);
}

static int fail_line(const char* msg)
{
    tp_cli_error("%s", msg);
    return TP_EXIT_FAILURE;
}

static int write_json(const char* json, const char* out, const tp_imagery* im, int sources,
                      double seconds, double rss_mb)
{
    tp_imagery_info info;
    tp_imagery_get_info(im, &info);
    tp_atomic_file af;
    if (!tp_atomic_open(&af, json))
        return TP_EXIT_FAILURE;
    FILE* f = af.f;
    uint64_t blocks = 0;
    for (int l = 0; l < info.levels; l++) {
        int c, r;
        tp_imagery_level_size(im, l, NULL, NULL, &c, &r);
        blocks += (uint64_t)c * r;
    }
    tp_json j;
    tp_json_init(&j, f);
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "output", out);
    tp_json_member_int(&j, "sources", sources);
    tp_json_member_number(&j, "width", (double)info.width);
    tp_json_member_number(&j, "height", (double)info.height);
    tp_json_member_int(&j, "texel_shift", info.texel_shift);
    tp_json_member_number(&j, "texel_m", fabs(info.geotransform[1]));
    tp_json_member_int(&j, "levels", info.levels);
    tp_json_member_number(&j, "blocks", (double)blocks);
    tp_json_member_number(&j, "nonempty_blocks", (double)info.nonempty_blocks);
    tp_json_member_number(&j, "bytes", (double)info.file_bytes);
    tp_json_member_number(&j, "seconds", seconds);
    tp_json_member_number(&j, "rss_peak_mb", rss_mb);
    tp_json_object_end(&j);
    if (!tp_atomic_commit(&af))
        return TP_EXIT_FAILURE;
    return TP_EXIT_OK;
}

int tp_imagery_cli_run(const char* store_path, const tp_imagery_cli* c)
{
    const double t0 = tp_clock_s();
    tp_error err = {0};
    char* def = c->out ? NULL : tp_imagery_default_path(store_path);
    const char* out = c->out ? c->out : def;
    if (!out)
        return fail_line("imagery: out of memory");
    int rc = TP_EXIT_FAILURE;
    tp_store* s = NULL;
    tp_imagery* im = NULL;
    if (c->out) { /* the one the user named: its extension says its format */
        if ((rc = tp_cli_output_check("imagery", "-o", c->out, TP_OUTPUT_IMAGERY)) != TP_EXIT_OK)
            goto done;
        rc = TP_EXIT_FAILURE;
    } else if (tp_output_check(out, &err) != TP_OK) {
        rc = fail_line(err.message);
        goto done;
    }
    for (int i = 0; i < c->count; i++)
        if (!strcmp(c->images[i], out) || !strcmp(store_path, out)) {
            tp_cli_error("%s: the output would replace an input", out);
            goto done;
        }
    if (tp_store_open(store_path, &s, &err) != TP_OK) {
        rc = fail_line(err.message);
        goto done;
    }
    tp_store_info si;
    tp_store_get_info(s, &si);
    tp_imagery_target t;
    t.crs_wkt = si.header.crs_wkt;
    memcpy(t.geotransform, si.header.geotransform, sizeof t.geotransform);
    t.width = si.header.geometry.src_width;
    t.height = si.header.geometry.src_height;
    tp_imagery_build_options o = {0};
    o.texel_shift = c->texel_shift;
    if (c->resolution_m > 0) {
        const double px = sqrt(fabs(t.geotransform[1] * t.geotransform[5]));
        const double k = round(log2(px / c->resolution_m));
        if (k < TP_IMAGERY_SHIFT_MIN || k > TP_IMAGERY_SHIFT_MAX) {
            tp_cli_error("%s: --resolution %g m is %g times the grid's %g m posts: outside "
                         "2^%d .. 2^%d",
                         out, c->resolution_m, c->resolution_m / px, px, -TP_IMAGERY_SHIFT_MAX,
                         -TP_IMAGERY_SHIFT_MIN);
            goto done;
        }
        o.texel_shift = (int)k;
    }
    o.memory_bytes = (double)c->memory_mb * 1024 * 1024;
    o.threads = c->threads;
    tp_progress p;
    tp_progress_start(&p, !c->quiet, c->who, "imagery");
    if (!c->quiet) {
        o.progress = on_progress;
        o.progress_user = &p;
    }
    tp_status st = tp_imagery_build(c->images, c->count, &t, &o, out, &err);
    if (st != TP_OK) {
        rc = tp_interrupted() ? tp_cli_interrupted() : fail_line(err.message);
        goto done;
    }
    if (tp_imagery_open(out, &im, &err) != TP_OK) {
        rc = fail_line(err.message);
        goto done;
    }
    tp_imagery_info info;
    tp_imagery_get_info(im, &info);
    const double seconds = tp_clock_s() - t0;
    const double rss_mb = tp_memory_peak_rss() / (1024.0 * 1024.0);
    if (!c->quiet)
        tp_cli_note("%s: %lldx%lld texels of %.3g m, %d levels, %llu non-empty blocks, "
                    "%.1f MB, %.1f s, peak RSS %.0f MB",
                    out, (long long)info.width, (long long)info.height, fabs(info.geotransform[1]),
                    info.levels, (unsigned long long)info.nonempty_blocks, info.file_bytes / 1e6,
                    seconds, rss_mb);
    rc = c->json ? write_json(c->json, out, im, c->count, seconds, rss_mb) : TP_EXIT_OK;
done:
    tp_imagery_close(im);
    tp_store_close(s);
    free(def);
    return rc;
}

/* ---- terrapatch imagery ---- */

static void print_help(void)
{
    fputs("usage: terrapatch imagery [options] STORE.tpt IMAGE... [-o OUT.tpi]\n"
          "\n"
          "Prepares orthophotos or scanned maps (any raster GDAL reads, georeferenced, in any\n"
          "CRS; RGB(A), grey or paletted) for the viewer: GDAL warps them onto the store's\n"
          "render grid (its CRS and extent), several mosaicked with a later image drawn over\n"
          "an earlier one, and the result is cut into a mip pyramid of 256x256 blocks (each\n"
          "level half the one below, alpha-weighted), compressed, in one file (.tpi,\n"
          "docs/imagery.md). Memory stays within --memory whatever the image size: level 0 is\n"
          "made one block row at a time and never held whole.\n"
          "\n"
          "options:\n"
          "  -o, --output FILE   the pyramid (default: STORE with .tpi for .tpt); written\n"
          "                      whole or not at all\n"
          "  --texel-shift K     2^K level-0 texels per grid post along each axis, -8 .. 8\n"
          "                      (default: from the finest image's pixel size on the grid)\n"
          "  --resolution M      level-0 texels of about M metres (the nearest power of two\n"
          "                      of the post spacing); instead of --texel-shift\n"
          "  --memory MB         memory budget (default 1024)\n"
          "  --threads N         threads (default: every core)\n"
          "  --json FILE|-       statistics as JSON (size, levels, blocks, bytes, seconds)\n"
          "  --quiet             no progress\n"
          "  -h, --help          show this help\n"
          "\n"
          "Exit status: 0 success, 1 an image or the store could not be read or the pyramid\n"
          "not written, 2 usage error, 130/143 after SIGINT/SIGTERM (nothing left behind).\n",
          stdout);
}

int tp_cli_imagery(int argc, char** argv)
{
    tp_imagery_cli c = {0};
    c.texel_shift = TP_IMAGERY_SHIFT_AUTO;
    c.memory_mb = 1024;
    c.who = "imagery";
    const tp_option options[] = {
        TP_OPT_TEXT("--output", "-o", &c.out),
        TP_OPT_INTEGER("--texel-shift", &c.texel_shift, TP_IMAGERY_SHIFT_MIN, TP_IMAGERY_SHIFT_MAX,
                       "-8 .. 8"),
        TP_OPT_NUMBER_ABOVE("--resolution", &c.resolution_m, 0, DBL_MAX, "metres > 0"),
        TP_OPT_INTEGER("--memory", &c.memory_mb, IMAGERY_MIN_MEMORY_MB, 1 << 24,
                       "megabytes, 64 or more"),
        TP_OPT_INTEGER("--threads", &c.threads, 1, 1024, "1 .. 1024"),
        TP_OPT_TEXT("--json", NULL, &c.json),
        TP_OPT_FLAG("--quiet", &c.quiet),
    };
    tp_options p;
    tp_options_init(&p, "imagery", argc, argv, print_help);
    tp_options_add(&p, options, TP_OPTIONS_COUNT(options), NULL, NULL);
    int operands = 0;
    for (int r; (r = tp_options_next(&p)) != TP_OPTIONS_END;) {
        if (r == TP_OPTIONS_EXIT)
            return p.exit;
        tp_options_keep(&p, &operands); /* no CODE options: an operand */
    }
    if (c.texel_shift != TP_IMAGERY_SHIFT_AUTO && c.resolution_m > 0)
        return tp_cli_usage_at("imagery", "give --texel-shift or --resolution, not both", "");
    if (operands < 1)
        return tp_cli_usage_at("imagery", "missing STORE.tpt", "");
    if (operands < 2)
        return tp_cli_usage_at("imagery", "missing IMAGE", "");
    c.images = (const char* const*)(argv + 2);
    c.count = operands - 1;
    if (c.json && strcmp(c.json, "-") && !tp_atomic_check_dir(c.json))
        return TP_EXIT_FAILURE;
    int rc = tp_imagery_cli_run(argv[1], &c);
    return rc == TP_EXIT_OK ? tp_cli_finish(rc) : rc;
}
