/*
 * cmd_build.c - `terrapatch build SOURCE... -o NAME.tpt`: the options read (build_options.c),
 * the store built (tp_store_build, scene/store_build.c), then the imagery pyramid of --imagery
 * beside it (cmd_imagery.h) and the summary as JSON (--json).
 */
#include "atomic_file.h"
#include "build_options.h"
#include "cli.h"
#include "cmd_imagery.h"
#include "json.h"
#include "output_check.h"
#include "store_build.h"
#include "terrapatch.h"

#include "tp_core.h"
#include "tp_io.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int fail_line(const char* msg)
{
    tp_cli_error("%s", msg);
    return TP_EXIT_FAILURE;
}

int tp_cli_build(int argc, char** argv)
{
    build_options o;
    int rc = tp_build_parse_options(argc, argv, &o);
    if (rc >= 0)
        return rc;
    tp_error err = {0};
    if (o.json && strcmp(o.json, "-") && !tp_atomic_check_dir(o.json))
        return TP_EXIT_FAILURE;
    if (o.imagery_count > 0) { /* the pyramid's path too, before the long work */
        char* tpi = tp_imagery_default_path(o.build.out);
        if (!tpi)
            return fail_line("build: out of memory");
        tp_status s = tp_output_check(tpi, &err);
        free(tpi);
        if (s != TP_OK)
            return fail_line(err.message);
        for (int i = 0; i < o.imagery_count; i++) /* a missing image, before the store */
            if (strncmp(o.imagery[i], "/vsi", 4) && access(o.imagery[i], R_OK) != 0)
                return tp_cli_error("%s: cannot open: %s", o.imagery[i], strerror(errno)),
                       TP_EXIT_FAILURE;
    }

    tp_build_result r;
    if ((rc = tp_store_build(&o.build, &r)) != TP_EXIT_OK)
        return rc;
    if (o.imagery_count > 0) { /* NAME.tpi beside the store, as `terrapatch imagery` makes it */
        tp_imagery_cli ic = {.images = o.imagery,
                             .count = o.imagery_count,
                             .texel_shift = o.imagery_cli.texel_shift,
                             .resolution_m = o.imagery_cli.resolution_m,
                             .memory_mb = r.memory_mb,
                             .threads = r.threads,
                             .quiet = o.build.quiet,
                             .who = "build"};
        int irc = tp_imagery_cli_run(o.build.out, &ic);
        if (irc != TP_EXIT_OK)
            return irc;
    }
    if (o.json) {
        tp_atomic_file af;
        if (!tp_atomic_open(&af, o.json))
            return TP_EXIT_FAILURE;
        FILE* f = af.f;
        tp_json j;
        tp_json_init(&j, f);
        tp_json_object_begin(&j);
        tp_json_member_string(&j, "output", o.build.out);
        tp_json_member_int(&j, "sources", o.build.source_count);
        tp_json_member_int(&j, "width", r.width);
        tp_json_member_int(&j, "height", r.height);
        tp_json_member_number(&j, "samples", r.samples);
        tp_json_member_size(&j, "valid_samples", r.valid_samples);
        tp_json_member_int(&j, "patch_size", r.patch_size);
        tp_json_member_int(&j, "nodes", r.nodes);
        tp_json_member_number(&j, "bytes", (double)r.bytes);
        tp_json_member_number(&j, "bytes_per_sample", r.bytes / r.samples);
        tp_json_member_number(&j, "step", r.step_m);
        tp_json_member_number(&j, "quant_max_error_m", r.quant_max_error_m);
        tp_json_member_number(&j, "min_m", r.min_m);
        tp_json_member_number(&j, "max_m", r.max_m);
        tp_json_member_string(&j, "crs", r.crs_name);
        tp_json_member_bool(&j, "warped", r.warped);
        tp_json_member_int(&j, "threads", r.threads);
        tp_json_member_int(&j, "memory_mb", r.memory_mb);
        tp_json_member_int(&j, "fill_max", o.build.fill_max);
        tp_json_member_number(&j, "filled_samples", (double)r.filled_samples);
        tp_json_member_number(&j, "filled_from_samples", (double)r.filled_from_samples);
        tp_json_key(&j, "void_samples_too_large"),
            tp_json_number(&j, (double)r.void_samples_too_large);
        tp_json_member_number(&j, "seconds", r.seconds);
        tp_json_member_number(&j, "rss_peak_mb", r.rss_peak_mb);
        tp_json_object_end(&j);
        if (!tp_atomic_commit(&af))
            return TP_EXIT_FAILURE;
    }
    return tp_cli_finish(TP_EXIT_OK);
}
