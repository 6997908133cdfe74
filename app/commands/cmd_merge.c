/*
 * cmd_merge.c - `terrapatch merge PART... -o NAME.tpt`: the parts of a build in parts
 * (`terrapatch build --part I/N`) joined into the store one build writes (scene/store_merge.c),
 * with its summary as JSON (--json).
 */
#include "atomic_file.h"
#include "cli.h"
#include "json.h"
#include "options.h"
#include "store_merge.h"
#include "terrapatch.h"

#include <stdio.h>
#include <string.h>

static void print_help(void)
{
    fputs("usage: terrapatch merge [options] PART... -o NAME.tpt\n"
          "\n"
          "Joins the parts of a build in parts into one terrain store: the parts are what\n"
          "'terrapatch build SOURCE... --part I/N -o PART' writes for I = 1 .. N, each on any\n"
          "machine, from the same sources and options. The store is the one 'terrapatch build\n"
          "SOURCE... -o NAME.tpt' writes, byte for byte: the parts' nodes are copied as stored\n"
          "(each checked against its CRC32) and the nodes above them computed from the parts'\n"
          "top nodes, as one build computes them. Every part is checked first: a part missing\n"
          "or given twice, one of other sources or options or of another split, and a damaged\n"
          "one are refused in one line, and nothing is written.\n"
          "\n"
          "options:\n"
          "  -o, --output FILE   the store to write, NAME.tpt (written whole or not at all)\n"
          "  --json FILE|-       statistics as JSON (nodes, computed, bytes, seconds, ...)\n"
          "  --quiet             no progress, no notes\n"
          "  -h, --help          show this help\n"
          "\n"
          "Exit status: 0 success, 1 a part is missing, given twice, mismatched or damaged, or\n"
          "the store could not be written, 2 usage error, 130/143 after SIGINT/SIGTERM (no\n"
          "store and no temporary file left).\n",
          stdout);
}

static int write_json(const char* path, const tp_merge_options* o, const tp_merge_result* r)
{
    tp_atomic_file af;
    if (!tp_atomic_open(&af, path))
        return TP_EXIT_FAILURE;
    tp_json j;
    tp_json_init(&j, af.f);
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "output", o->out);
    tp_json_member_int(&j, "parts", r->parts);
    tp_json_member_int(&j, "width", r->width);
    tp_json_member_int(&j, "height", r->height);
    tp_json_member_int(&j, "split_scale", r->split_scale);
    tp_json_member_number(&j, "nodes", (double)r->nodes);
    tp_json_member_number(&j, "copied", (double)r->copied);
    tp_json_member_number(&j, "computed", (double)r->computed);
    tp_json_member_number(&j, "bytes", (double)r->bytes);
    tp_json_member_number(&j, "check_seconds", r->check_seconds);
    tp_json_member_number(&j, "above_seconds", r->above_seconds);
    tp_json_member_number(&j, "seconds", r->seconds);
    tp_json_member_number(&j, "rss_peak_mb", r->rss_peak_mb);
    tp_json_object_end(&j);
    return tp_atomic_commit(&af) ? TP_EXIT_OK : TP_EXIT_FAILURE;
}

int tp_cli_merge(int argc, char** argv)
{
    tp_merge_options o = {0};
    const char* json = NULL;
    const tp_option options[] = {
        TP_OPT_TEXT("--output", "-o", &o.out),
        TP_OPT_TEXT("--json", NULL, &json),
        TP_OPT_FLAG("--quiet", &o.quiet),
    };
    tp_options p;
    tp_options_init(&p, "merge", argc, argv, print_help);
    tp_options_add(&p, options, TP_OPTIONS_COUNT(options), NULL, NULL);
    for (int c; (c = tp_options_next(&p)) != TP_OPTIONS_END;) {
        if (c == TP_OPTIONS_EXIT)
            return p.exit;
        if (c == TP_OPTIONS_OPERAND)
            tp_options_keep(&p, &o.part_count);
    }
    if (!o.part_count)
        return tp_cli_usage_at("merge", "missing PART", "");
    if (!o.out)
        return tp_cli_usage_at("merge", "missing -o NAME.tpt", "");
    o.parts = (const char**)(argv + 1);
    if (json && strcmp(json, "-") && !tp_atomic_check_dir(json))
        return TP_EXIT_FAILURE;
    tp_merge_result r;
    int rc = tp_store_merge(&o, &r);
    if (rc == TP_EXIT_OK && json)
        rc = write_json(json, &o, &r);
    return tp_cli_finish(rc);
}
