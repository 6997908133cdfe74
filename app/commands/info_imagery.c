/*
 * info_imagery.c - `terrapatch info [--json] PYRAMID.tpi|LIGHT.tpl`: an imagery pyramid
 * (tp_imagery.h, docs/imagery.md) or a day's light map (the same file, kind light times)
 * described level by level, every block read and checked; and the lines `info STORE.tpt`
 * prints about the pyramid and the light map beside a store.
 */
#include "info.h"
#include "cli.h"
#include "json.h"
#include "sun_time.h"

#include "tp_imagery.h"
#include "tp_io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct level_stats {
    int64_t width, height;
    int cols, rows;
    long long nonempty, damaged;
} level_stats;

static void print_notes(const char* notes)
{
    while (*notes) {
        const char* e = strchr(notes, '\n');
        int len = e ? (int)(e - notes) : (int)strlen(notes);
        printf("note:           %.*s\n", len, notes);
        notes += len + (e ? 1 : 0);
    }
}

int tp_info_imagery(const char* path, int json)
{
    tp_imagery* im = NULL;
    tp_error err = {0};
    if (tp_imagery_open(path, &im, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    tp_imagery_info info;
    tp_imagery_get_info(im, &info);
    level_stats lv[TP_IMAGERY_MAX_LEVELS];
    uint8_t* blk = malloc((size_t)info.block * info.block * 4);
    if (!blk) {
        tp_imagery_close(im);
        tp_cli_error("%s: out of memory", path);
        return TP_EXIT_FAILURE;
    }
    long long blocks = 0, damaged = 0;
    char first[sizeof err.message] = "";
    for (int l = 0; l < info.levels; l++) {
        level_stats* s = &lv[l];
        memset(s, 0, sizeof *s);
        tp_imagery_level_size(im, l, &s->width, &s->height, &s->cols, &s->rows);
        for (int by = 0; by < s->rows; by++)
            for (int bx = 0; bx < s->cols; bx++) {
                blocks++;
                if (tp_imagery_block_is_empty(im, l, bx, by))
                    continue;
                s->nonempty++;
                if (tp_imagery_read_block(im, l, bx, by, blk, &err) != TP_OK) {
                    if (!damaged++)
                        snprintf(first, sizeof first, "%s", err.message);
                    s->damaged++;
                }
            }
    }
    free(blk);
    const double texel = hypot(info.geotransform[1], info.geotransform[4]);
    const int light = info.kind == TP_IMAGERY_KIND_LIGHT_TIMES;
    const char* with = light ? "lit at some time" : "with imagery";
    char t0[48], t1[48];
    tp_sun_time_format(info.time_first_s, 0, t0, sizeof t0);
    tp_sun_time_format(info.time_last_s, 0, t1, sizeof t1);
    if (json) {
        tp_json j;
        tp_json_init(&j, stdout);
        tp_json_object_begin(&j);
        tp_json_member_string(&j, "path", path);
        tp_json_member_string(&j, "format", "terrapatch imagery pyramid");
        tp_json_member_string(&j, "kind", light ? "light times" : "image");
        if (light) {
            tp_json_member_string(&j, "time_first", t0);
            tp_json_member_string(&j, "time_last", t1);
            tp_json_member_number(&j, "time_first_s", info.time_first_s);
            tp_json_member_number(&j, "time_last_s", info.time_last_s);
            tp_json_member_int(&j, "maps", info.maps);
        }
        tp_json_member_number(&j, "width", (double)info.width);
        tp_json_member_number(&j, "height", (double)info.height);
        tp_json_member_int(&j, "texel_shift", info.texel_shift);
        tp_json_member_number(&j, "texel_m", texel);
        tp_json_member_int(&j, "grid_width", info.grid_width);
        tp_json_member_int(&j, "grid_height", info.grid_height);
        tp_json_member_int(&j, "levels", info.levels);
        tp_json_member_number(&j, "blocks", (double)blocks);
        tp_json_member_number(&j, "nonempty_blocks", (double)info.nonempty_blocks);
        tp_json_member_number(&j, "damaged_blocks", (double)damaged);
        tp_json_member_number(&j, "bytes", (double)info.file_bytes);
        tp_json_key(&j, "per_level");
        tp_json_array_begin(&j);
        for (int l = 0; l < info.levels; l++) {
            tp_json_object_begin(&j);
            tp_json_member_number(&j, "width", (double)lv[l].width);
            tp_json_member_number(&j, "height", (double)lv[l].height);
            tp_json_member_number(&j, "texel_m", ldexp(texel, l));
            tp_json_member_number(&j, "blocks", (double)lv[l].cols * lv[l].rows);
            tp_json_member_number(&j, "nonempty_blocks", (double)lv[l].nonempty);
            tp_json_object_end(&j);
        }
        tp_json_array_end(&j);
        tp_json_member_string(&j, "notes", info.notes);
        tp_json_object_end(&j);
        putchar('\n');
    } else {
        printf("%s        %s\n", light ? "light map:" : "imagery:  ", path);
        printf("format:         terrapatch imagery pyramid\n");
        if (light) {
            printf("kind:           light times: each post's lit intervals over a day, in %d "
                   "steps\n",
                   TP_LIGHT_TIMES_STEPS);
            printf("day:            %s .. %s (%.2f h)\n", t0, t1,
                   (info.time_last_s - info.time_first_s) / 3600.0);
            printf("maps:           %d sun positions\n", info.maps);
        } else {
            printf("kind:           image (RGBA)\n");
        }
        printf("size:           %.1f MB (%llu bytes)\n", info.file_bytes / 1e6,
               (unsigned long long)info.file_bytes);
        printf("level 0:        %lld x %lld texels of %.4g m (texel shift %d: 2^%d texels per "
               "post of the %d x %d grid)\n",
               (long long)info.width, (long long)info.height, texel, info.texel_shift,
               info.texel_shift, info.grid_width, info.grid_height);
        printf("blocks:         %d x %d texels, %lld in %d levels, %llu %s\n", info.block,
               info.block, blocks, info.levels, (unsigned long long)info.nonempty_blocks, with);
        for (int l = 0; l < info.levels; l++)
            printf("level %-2d        %lld x %lld texels of %.4g m, %d x %d blocks, %lld %s\n", l,
                   (long long)lv[l].width, (long long)lv[l].height, ldexp(texel, l), lv[l].cols,
                   lv[l].rows, lv[l].nonempty, with);
        printf("checked:        %llu blocks read, %lld damaged\n",
               (unsigned long long)info.nonempty_blocks, damaged);
        print_notes(info.notes);
    }
    tp_imagery_close(im);
    if (damaged)
        tp_cli_error("%s (%lld damaged block%s in all)", first, damaged, damaged == 1 ? "" : "s");
    return tp_cli_finish(damaged ? TP_EXIT_FAILURE : TP_EXIT_OK);
}

/* The line about the pyramid with suffix (".tpi", ".tpl") beside a store, if there is one. */
static void beside(const char* store_path, const char* suffix)
{
    size_t n = strlen(store_path);
    char* p = malloc(n + 5);
    if (!p)
        return;
    memcpy(p, store_path, n + 1);
    if (n >= 4 && !strcmp(p + n - 4, ".tpt"))
        n -= 4;
    memcpy(p + n, suffix, 5);
    const char* what = suffix[3] == 'l' ? "light map:    " : "imagery:      ";
    tp_imagery* im = NULL;
    tp_error err = {0};
    unsigned char head[8];
    if (tp_input_is_url(p) ? tp_input_url_head(p, head, sizeof head, NULL) == TP_OK
                           : access(p, F_OK) == 0) {
        if (tp_imagery_open(p, &im, &err) == TP_OK) {
            tp_imagery_info info;
            tp_imagery_get_info(im, &info);
            printf("%s  %s: %lld x %lld texels of %.4g m, %d levels, %.1f MB "
                   "('terrapatch info %s')\n",
                   what, p, (long long)info.width, (long long)info.height,
                   hypot(info.geotransform[1], info.geotransform[4]), info.levels,
                   info.file_bytes / 1e6, p);
            tp_imagery_close(im);
        } else {
            printf("%s  %s\n", what, err.message);
        }
    }
    free(p);
}

void tp_info_imagery_beside(const char* store_path)
{
    beside(store_path, ".tpi");
    beside(store_path, ".tpl");
}
