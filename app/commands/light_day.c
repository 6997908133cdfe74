/*
 * light_day.c - `terrapatch light DEM|STORE --day --date YYYY-MM-DD [-o OUT.tpl]`: the light
 * map of a whole store over a day (issue 15, part 2; docs/light.md "A day's light map"), written
 * as an imagery pyramid of kind TP_IMAGERY_KIND_LIGHT_TIMES (tp_imagery_build_rows) that the
 * viewer streams through its imagery clipmap. With a raster -o HOURS.tif (issue 31), the same
 * texels of the whole grid or of a --radius window around --at turned into the hours each post
 * is lit, written as one Float32 band (tp_float_raster_write).
 *
 * The sun: tp_sun.h at the grid's centre (the place cmd_light.c computes it for), `maps`
 * positions from sunrise to sunset of the date there (tp_sun_day_times: closer where the sun is
 * low), each azimuth turned to grid north by the meridian convergence at the centre
 * (tp_light_sun). The pyramid's writer asks for level-0 rows in order; they are made a band of
 * tiles at a time: each tile of TILE x TILE posts read through the ground module with the
 * margin around it (clamped to the grid: nothing beyond it casts a shadow, as in
 * tp_shadow_compute over the whole grid), tp_light_times_build over tile + margin, the tile's
 * part kept. Two tiles at a time: one read and computed by this thread while a second thread
 * computes the other (the ground module is used by this thread only). Memory: a band of texels
 * (width x band rows x 4 bytes, the band's height cut for very wide grids) and two tiles with
 * their margins (about 34 bytes a post), whatever the grid's height.
 */
#define _POSIX_C_SOURCE 200809L
#include "atomic_file.h"
#include "clock.h"
#include "cli.h"
#include "light.h"
#include "json.h"
#include "memory.h"
#include "output_check.h"
#include "planner_cli.h"
#include "sun_time.h"

#include "tp_core.h"
#include "tp_imagery.h"
#include "tp_io.h"
#include "tp_sun.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define TILE 1024             /* posts a tile side */
#define MARGIN_POSTS_MAX 1024 /* the margin's cap in posts (memory: 3072^2 posts a tile) */
#define BAND_BYTES_MAX ((size_t)256 << 20) /* a band's texels: its rows cut below TILE beyond */

/* The day's sun and the grid's spacing, shared read-only by the tiles' threads. */
typedef struct day_sun {
    double dx_m, dy_m;
    const double *times_s, *azimuth_deg, *elevation_deg;
    int maps;
} day_sun;

/* One tile: its window of posts (tile + margin, clamped to the grid) and the tile in it. */
typedef struct tile_job {
    const day_sun* sun;
    int x0, y0, w, h;   /* the window read */
    int tx, ty, tw, th; /* the tile (grid posts) */
    float* z;
    uint8_t* texels; /* 4 * w * h */
    tp_light_times_stats stats;
    tp_status status;
    tp_error err;
} tile_job;

typedef struct day_run {
    const tp_light_cli* o;
    tp_ground* g;
    int x0, y0;         /* the window's first post on the grid (0, 0 for the light map) */
    int width, height;  /* the window's posts (the whole grid for the light map) */
    int grid_w, grid_h; /* the grid's: a margin reaches that far */
    float* hours;       /* --day -o HOURS.tif: width * height, row by row; else NULL */
    int mx, my;        /* the margin in posts */
    int band_rows;
    day_sun sun;
    uint8_t* band;       /* width * band_rows * 4 */
    int band_y0, band_h; /* the band held (band_h 0: none yet) */
    tile_job job[2];
    size_t simplified, lit_any, valid; /* totals (simplified: over the windows) */
    double given_up_max_s;
    int tiles_done, tiles_total;
    double t0, read_s;
    int tty, last_decile;
} day_run;

static void* compute_tile(void* user)
{
    tile_job* j = user;
    const size_t n = (size_t)j->w * j->h;
    const day_sun* s = j->sun;
    j->status = tp_light_times_build(j->z, n, j->w, j->h, s->dx_m, s->dy_m, s->times_s,
                                     s->azimuth_deg, s->elevation_deg, s->maps, j->texels, 4 * n,
                                     &j->stats, NULL, NULL, &j->err);
    return NULL;
}

/* The tile at grid post (tx, ty) (in the window) and the window read for it: the tile with the
 * margin, clamped to the grid. */
static void place_tile(const day_run* r, tile_job* j, int tx, int ty)
{
    const int x_end = r->x0 + r->width, y_end = r->y0 + r->height;
    j->tx = tx, j->ty = ty;
    j->tw = tx + TILE < x_end ? TILE : x_end - tx;
    j->th = ty + r->band_rows < y_end ? r->band_rows : y_end - ty;
    j->x0 = tx - r->mx > 0 ? tx - r->mx : 0;
    j->y0 = ty - r->my > 0 ? ty - r->my : 0;
    const int x1 = tx + j->tw + r->mx < r->grid_w ? tx + j->tw + r->mx : r->grid_w;
    const int y1 = ty + j->th + r->my < r->grid_h ? ty + j->th + r->my : r->grid_h;
    j->w = x1 - j->x0, j->h = y1 - j->y0;
}

/* The hours a texel is lit in a day of day_s seconds (its intervals, in 1/255 of the day). */
static float texel_hours(const uint8_t t[4], double day_s)
{
    const int steps = (t[1] - t[0]) + (t[3] - t[2]);
    return (float)(steps * day_s / (TP_LIGHT_TIMES_STEPS * 3600.0));
}

/* The tile's part of its window into the band (and the hours); the totals. */
static void keep_tile(day_run* r, const tile_job* j)
{
    const double day_s = r->sun.times_s[r->sun.maps - 1] - r->sun.times_s[0];
    for (int y = 0; y < j->th; ++y) {
        const uint8_t* src =
            j->texels + 4 * ((size_t)(j->ty - j->y0 + y) * j->w + (size_t)(j->tx - j->x0));
        memcpy(r->band + 4 * ((size_t)(j->ty - r->band_y0 + y) * r->width + (j->tx - r->x0)), src,
               4 * (size_t)j->tw);
        const float* z = j->z + (size_t)(j->ty - j->y0 + y) * j->w + (j->tx - j->x0);
        float* hours =
            r->hours ? r->hours + (size_t)(j->ty - r->y0 + y) * r->width + (j->tx - r->x0) : NULL;
        for (int x = 0; x < j->tw; ++x) {
            r->valid += z[x] == z[x];
            r->lit_any += src[4 * x + 3] != 0;
            if (hours)
                hours[x] = z[x] == z[x] ? texel_hours(src + 4 * x, day_s) : NAN;
        }
    }
    r->simplified += j->stats.simplified;
    if (j->stats.given_up_max_s > r->given_up_max_s)
        r->given_up_max_s = j->stats.given_up_max_s;
}

static void show_progress(day_run* r)
{
    if (r->o->quiet)
        return;
    const double f = (double)r->tiles_done / r->tiles_total, el = tp_clock_s() - r->t0;
    const int decile = (int)(f * 10);
    if (!r->tty && decile <= r->last_decile && f < 1)
        return;
    r->last_decile = decile;
    if (r->tty && f < 1)
        fprintf(stderr, "%s%3.0f%% (%d of %d tiles, %.1f s, ETA %.0f s)   \r", tp_cli_prefix(),
                100 * f, r->tiles_done, r->tiles_total, el, f > 0 ? el * (1 - f) / f : 0.0);
    else
        tp_cli_note("%3.0f%% (%d of %d tiles, %.1f s, ETA %.0f s)", 100 * f, r->tiles_done,
                    r->tiles_total, el, f > 0 ? el * (1 - f) / f : 0.0);
}

/* Reads the window's posts (this thread: the ground is not shared). */
static tp_status read_tile(day_run* r, tile_job* j, tp_error* err)
{
    const double t = tp_clock_s();
    tp_status s = tp_ground_read_posts(r->g, j->x0, j->y0, j->w, j->h, j->z, NULL, err);
    r->read_s += tp_clock_s() - t;
    return s;
}

/* Makes the band of rows from grid row y0: its tiles two at a time. */
static tp_status make_band(day_run* r, int y0, tp_error* err)
{
    const int x_end = r->x0 + r->width, y_end = r->y0 + r->height;
    r->band_y0 = y0;
    r->band_h = y0 + r->band_rows < y_end ? r->band_rows : y_end - y0;
    for (int tx = r->x0; tx < x_end; tx += 2 * TILE) {
        tile_job* a = &r->job[0];
        tile_job* b = tx + TILE < x_end ? &r->job[1] : NULL;
        place_tile(r, a, tx, y0);
        tp_status s = read_tile(r, a, err);
        if (s != TP_OK)
            return s;
        pthread_t th;
        const int threaded = b && pthread_create(&th, NULL, compute_tile, a) == 0;
        if (!threaded)
            compute_tile(a);
        if (b) {
            place_tile(r, b, tx + TILE, y0);
            s = read_tile(r, b, err);
            if (s == TP_OK)
                compute_tile(b);
        }
        if (threaded)
            pthread_join(th, NULL);
        if (s != TP_OK)
            return s;
        for (int k = 0; k < (b ? 2 : 1); ++k) {
            const tile_job* j = &r->job[k];
            if (j->status != TP_OK) {
                *err = j->err;
                return j->status;
            }
            keep_tile(r, j);
            r->tiles_done++;
        }
        show_progress(r);
        if (tp_interrupted())
            return tp_error_set(err, TP_ERR_IO, "interrupted");
    }
    return TP_OK;
}

/* tp_imagery_rows.rows: level-0 rows row0 .. row0 + count - 1 (of the window) from the band
 * holding them. */
static tp_status give_rows(void* user, int64_t row0, int count, uint8_t* rgba, tp_error* err)
{
    day_run* r = user;
    const int64_t y = r->y0 + row0;
    if (r->band_h == 0 || y >= r->band_y0 + r->band_h) {
        tp_status s = make_band(r, (int)y, err);
        if (s != TP_OK)
            return s;
    }
    memcpy(rgba, r->band + 4 * (size_t)(y - r->band_y0) * r->width, 4 * (size_t)count * r->width);
    return TP_OK;
}

int tp_light_is_map(const char* path)
{
    tp_output_format f;
    tp_error err = {{0}};
    return tp_output_format_for(path, TP_OUTPUT_LIGHT_MAP, &f, &err) == TP_OK;
}

/* What the hours raster holds: the day's length and its step, the mean and largest hours over
 * the posts with a height. */
typedef struct hours_stats {
    double day_h, step_min, mean_h, max_h;
} hours_stats;

/* The summary as JSON: the light map's (in) or the hours' (hs); the suns either way. */
static int write_json(const char* json, const day_run* r, const tp_light_place* at,
                      const tp_imagery_info* in, const hours_stats* hs, const char* out,
                      double seconds, double rss_mb)
{
    tp_atomic_file af;
    if (!tp_atomic_open(&af, json))
        return TP_EXIT_FAILURE;
    const day_sun* sun = &r->sun;
    const double first = sun->times_s[0], last = sun->times_s[sun->maps - 1];
    char t0[48], t1[48];
    tp_sun_time_format(first, 0, t0, sizeof t0);
    tp_sun_time_format(last, 0, t1, sizeof t1);
    tp_json j;
    tp_json_init(&j, af.f);
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "output", out);
    tp_json_member_string(&j, "kind", hs ? "hours" : "light map");
    tp_json_member_int(&j, "x0", r->x0);
    tp_json_member_int(&j, "y0", r->y0);
    tp_json_member_int(&j, "width", r->width);
    tp_json_member_int(&j, "height", r->height);
    tp_json_member_string(&j, "time_first", t0);
    tp_json_member_string(&j, "time_last", t1);
    tp_json_member_number(&j, "time_first_s", first);
    tp_json_member_number(&j, "time_last_s", last);
    tp_json_member_int(&j, "maps", sun->maps);
    tp_json_member_number(&j, "convergence_deg", at->convergence_deg);
    tp_json_member_int(&j, "margin_posts", r->mx > r->my ? r->mx : r->my);
    tp_json_member_int(&j, "tiles", r->tiles_total);
    tp_json_member_size(&j, "valid_posts", r->valid);
    tp_json_member_size(&j, "lit_posts", r->lit_any);
    tp_json_member_size(&j, "simplified", r->simplified);
    tp_json_member_number(&j, "given_up_max_s", r->given_up_max_s);
    if (in) {
        tp_json_member_int(&j, "levels", in->levels);
        tp_json_member_number(&j, "nonempty_blocks", (double)in->nonempty_blocks);
        tp_json_member_number(&j, "bytes", (double)in->file_bytes);
    } else {
        tp_json_member_number(&j, "day_hours", hs->day_h);
        tp_json_member_number(&j, "step_minutes", hs->step_min);
        tp_json_member_number(&j, "hours_mean", hs->mean_h);
        tp_json_member_number(&j, "hours_max", hs->max_h);
        tp_json_member_number(&j, "nodata", TP_FLOAT_RASTER_NODATA);
    }
    tp_json_key(&j, "suns"); /* each map's sun: grid azimuth, apparent elevation */
    tp_json_array_begin(&j);
    for (int k = 0; k < sun->maps; ++k) {
        tp_json_object_begin(&j);
        tp_json_member_number(&j, "time_s", sun->times_s[k]);
        tp_json_member_number(&j, "azimuth_grid_deg", sun->azimuth_deg[k]);
        tp_json_member_number(&j, "elevation_deg", sun->elevation_deg[k]);
        tp_json_object_end(&j);
    }
    tp_json_array_end(&j);
    tp_json_member_number(&j, "seconds", seconds);
    tp_json_member_number(&j, "read_seconds", r->read_s);
    tp_json_member_number(&j, "rss_peak_mb", rss_mb);
    tp_json_object_end(&j);
    if (!tp_atomic_commit(&af))
        return TP_EXIT_FAILURE;
    return TP_EXIT_OK;
}

/* The default output: the store's path with .tpl for .tpt (appended otherwise); of a store's
 * URL, its last name in the current folder. */
static char* default_out(const char* store_path)
{
    if (tp_input_is_url(store_path))
        store_path = strrchr(store_path, '/') + 1;
    const size_t n = strlen(store_path);
    char* p = malloc(n + 5);
    if (!p)
        return NULL;
    const size_t k = n >= 4 && !strcmp(store_path + n - 4, ".tpt") ? n - 4 : n;
    memcpy(p, store_path, k);
    memcpy(p + k, ".tpl", 5);
    return p;
}

/* The day's sun: count times from sunrise to sunset (a polar day or night: the local mean
 * solar day), their grid azimuths and apparent elevations. */
static tp_status day_sun_make(const tp_light_place* at, int year, int month, int mday, int count,
                              tp_sun_day* day, double* t, double* az, double* el, tp_error* err)
{
    const double start = tp_sun_local_day_start(year, month, mday, at->lon_deg);
    tp_status s = tp_sun_rise_set(at->lat_deg, at->lon_deg, start, day, err);
    if (s != TP_OK)
        return s;
    const int rises = day->kind == TP_SUN_RISES_AND_SETS;
    s = tp_sun_day_times(at->lat_deg, at->lon_deg, rises ? day->rise_unix_s : start,
                         rises ? day->set_unix_s : start + 86400.0, count, t, err);
    for (int k = 0; k < count && s == TP_OK; ++k) {
        tp_sun_pos p;
        s = tp_light_sun(at, t[k], &p, &az[k], err);
        el[k] = p.apparent_elevation_deg;
    }
    return s;
}

/* The day's summary on stdout: the place, the sun's day, the grid or window, the lit posts, the
 * file (the light map's levels, in, or the hours, hs). */
static void print_report(const day_run* r, const tp_light_place* at, const tp_sun_day* day,
                         const tp_imagery_info* in, const hours_stats* hs, const char* out,
                         double seconds, double rss_mb)
{
    const tp_light_cli* o = r->o;
    char t0[48], t1[48];
    tp_sun_time_format(r->sun.times_s[0], 0, t0, sizeof t0);
    tp_sun_time_format(r->sun.times_s[r->sun.maps - 1], 0, t1, sizeof t1);
    printf("place      %.6f %.6f (post %.0f, %.0f: where the sun is computed); grid north "
           "is %.3f deg %s of true north\n",
           at->lat_deg, at->lon_deg, at->x, at->y, fabs(at->convergence_deg),
           at->convergence_deg >= 0.0 ? "east" : "west");
    tp_light_print_day(day, 0);
    printf("day        %s .. %s, %d maps\n", t0, t1, o->maps);
    if (hs)
        printf("window     %dx%d posts from (%d, %d)%s, %d tiles of %d posts, margin %d x %d "
               "posts (%.0f m)\n",
               r->width, r->height, r->x0, r->y0,
               r->width == r->grid_w && r->height == r->grid_h ? " (the whole grid)" : "",
               r->tiles_total, TILE, r->mx, r->my, o->margin_m);
    else
        printf("grid       %dx%d posts, %d tiles of %d posts, margin %d x %d posts (%.0f m)\n",
               r->width, r->height, r->tiles_total, TILE, r->mx, r->my, o->margin_m);
    printf("lit        %zu of %zu posts with a height lit at some time (%.1f%%)\n", r->lit_any,
           r->valid, r->valid ? 100.0 * r->lit_any / r->valid : 0.0);
    printf("simplified %zu samples lit over more than two intervals (tiles with margins), "
           "at most %.0f s given up\n",
           r->simplified, r->given_up_max_s);
    if (hs) {
        printf("hours      %.2f h of sunlight on average, %.2f h at most, of a day of %.2f h "
               "(steps of %.1f min)\n",
               hs->mean_h, hs->max_h, hs->day_h, hs->step_min);
        printf("file       %s: Float32 hours, nodata %.0f\n", out, TP_FLOAT_RASTER_NODATA);
    } else {
        printf("file       %s: %d levels, %llu non-empty blocks, %llu bytes\n", out, in->levels,
               (unsigned long long)in->nonempty_blocks, (unsigned long long)in->file_bytes);
    }
    printf("time       %.1f s (%.1f s reading the ground), peak RSS %.0f MB\n", seconds,
           r->read_s, rss_mb);
}

/* The summary (text and --json) once the output is written: the exit code. */
static int report(const day_run* r, const tp_light_place* at, const tp_sun_day* day,
                  const tp_imagery_info* in, const hours_stats* hs, const char* out, double t_start)
{
    const tp_light_cli* o = r->o;
    const double seconds = tp_clock_s() - t_start;
    const double rss_mb = tp_memory_peak_rss() / (1024.0 * 1024.0);
    int code = TP_EXIT_OK;
    if (o->json)
        code = write_json(o->json, r, at, in, hs, out, seconds, rss_mb);
    if (!o->json || strcmp(o->json, "-"))
        print_report(r, at, day, in, hs, out, seconds, rss_mb);
    if (!o->quiet)
        tp_cli_note("wrote %s", out);
    return code;
}

/* The light map (.tpl) of the grid: its rows made band by band as the pyramid's writer asks. */
static int run_map(day_run* r, const tp_light_place* at, const tp_sun_day* day, const char* out,
                   double t_start)
{
    const tp_light_cli* o = r->o;
    const tp_store_scene* sc = tp_ground_scene(r->g);
    const double* sun = r->sun.times_s;
    const int maps = r->sun.maps;
    char t0[48], t1[48], notes[1024];
    tp_sun_time_format(sun[0], 0, t0, sizeof t0);
    tp_sun_time_format(sun[maps - 1], 0, t1, sizeof t1);
    snprintf(notes, sizeof notes,
             "light map of %s on %s: lit intervals of each post from %s to %s (%s), %d maps "
             "(tp_sun_day_times), the sun at %.6f %.6f (meridian convergence %.3f deg)\n"
             "tiles of %d posts with a margin of %d x %d posts (%.0f m asked)",
             o->src.path, o->date, t0, t1,
             day->kind == TP_SUN_RISES_AND_SETS ? "sunrise to sunset" : "24 hours: polar", maps,
             at->lat_deg, at->lon_deg, at->convergence_deg, TILE, r->mx, r->my, o->margin_m);
    tp_imagery_target target = {
        .crs_wkt = sc->info.header.crs_wkt, .width = r->width, .height = r->height};
    memcpy(target.geotransform, sc->info.header.geotransform, sizeof target.geotransform);
    tp_imagery_rows rows = {.kind = TP_IMAGERY_KIND_LIGHT_TIMES,
                            .texel_shift = 0,
                            .time_first_s = sun[0],
                            .time_last_s = sun[maps - 1],
                            .maps = maps,
                            .notes = notes,
                            .rows = give_rows,
                            .user = r};
    r->t0 = tp_clock_s();
    tp_error err = {{0}};
    if (tp_imagery_build_rows(&target, &rows, NULL, out, &err) != TP_OK)
        return tp_interrupted() ? tp_cli_interrupted()
                                : (tp_cli_error("%s", err.message), TP_EXIT_FAILURE);
    tp_imagery* im = NULL;
    if (tp_imagery_open(out, &im, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    tp_imagery_info info;
    tp_imagery_get_info(im, &info);
    const int code = report(r, at, day, &info, NULL, out, t_start);
    tp_imagery_close(im);
    return code;
}

/* The hours of sunlight of the window: its bands made in turn, the hours kept, one Float32
 * raster written on the window's georeference. */
static int run_hours(day_run* r, const tp_light_place* at, const tp_sun_day* day, const char* out,
                     double t_start)
{
    const tp_light_cli* o = r->o;
    const size_t n = (size_t)r->width * r->height;
    r->hours = malloc(n * sizeof *r->hours);
    if (!r->hours) {
        tp_cli_error("out of memory for %zu posts of hours", n);
        return TP_EXIT_FAILURE;
    }
    tp_error err = {{0}};
    tp_status s = TP_OK;
    r->t0 = tp_clock_s();
    for (int y = r->y0; s == TP_OK && y < r->y0 + r->height; y += r->band_rows)
        s = make_band(r, y, &err);
    hours_stats hs = {0};
    const double first = r->sun.times_s[0], last = r->sun.times_s[r->sun.maps - 1];
    hs.day_h = (last - first) / 3600.0;
    hs.step_min = (last - first) / (60.0 * TP_LIGHT_TIMES_STEPS);
    size_t valid = 0;
    for (size_t i = 0; i < n; ++i)
        if (r->hours[i] == r->hours[i]) {
            valid++;
            hs.mean_h += r->hours[i];
            hs.max_h = r->hours[i] > hs.max_h ? r->hours[i] : hs.max_h;
        }
    hs.mean_h = valid ? hs.mean_h / valid : 0.0;
    char t0[48], t1[48], what[512];
    tp_sun_time_format(first, 0, t0, sizeof t0);
    tp_sun_time_format(last, 0, t1, sizeof t1);
    snprintf(what, sizeof what,
             "hours of direct sunlight on %s from %s to %s (%d suns, steps of %.1f min), the sun "
             "at %.6f %.6f",
             o->date, t0, t1, r->sun.maps, hs.step_min, at->lat_deg, at->lon_deg);
    tp_planner_window win; /* the window's georeference */
    tp_planner_window_set(r->g, r->x0, r->y0, r->x0 + r->width - 1, r->y0 + r->height - 1, &win);
    if (s == TP_OK)
        s = tp_planner_float_raster_write(r->g, out, r->hours, &win, what, &err);
    if (s != TP_OK)
        return tp_interrupted() ? tp_cli_interrupted()
                                : (tp_cli_error("%s", err.message), TP_EXIT_FAILURE);
    return report(r, at, day, NULL, &hs, out, t_start);
}

/* The window of the hours: the whole grid, or the posts --radius reaches around --at; the place
 * the sun is computed for (the grid's centre, or --at). 1, or 0 after one line. */
static int day_window(day_run* r, const tp_position_readings* at_pos, tp_light_place* at)
{
    const tp_light_cli* o = r->o;
    double cx = 0.5 * (r->grid_w - 1), cy = 0.5 * (r->grid_h - 1);
    r->x0 = r->y0 = 0;
    r->width = r->grid_w, r->height = r->grid_h;
    if (o->at) {
        double fh;
        if (!tp_planner_locate("light", o->src.path, r->g, at_pos, o->at, &cx, &cy, &fh))
            return 0;
        cx = (double)lround(cx), cy = (double)lround(cy);
        tp_planner_window win;
        tp_planner_window_around(r->g, (int)cx, (int)cy, o->radius_m, &win);
        r->x0 = win.x0, r->y0 = win.y0, r->width = win.w, r->height = win.h;
    }
    return tp_light_place_at(o->src.path, r->g, cx, cy, at);
}

int tp_light_day_run(const tp_light_cli* o)
{
    const double t_start = tp_clock_s();
    int year, month, mday;
    tp_error why = {{0}};
    if (!tp_sun_date_parse(o->date, &year, &month, &mday, &why)) {
        tp_cli_error("--date %s: %s", o->date, why.message);
        return TP_EXIT_USAGE;
    }
    tp_position_readings at_pos;
    if (o->at && !tp_planner_position("light", "--at", o->at, &at_pos))
        return TP_EXIT_USAGE;
    tp_error err = {{0}};
    int code;
    const tp_output_kind kind = o->hours ? TP_OUTPUT_FLOAT_RASTER : TP_OUTPUT_LIGHT_MAP;
    if (o->out && (code = tp_cli_output_check("light", "-o", o->out, kind)) != TP_EXIT_OK)
        return code;
    tp_ground* g = NULL;
    if ((code = tp_planner_ground_open("light", &o->src, &g)) != TP_EXIT_OK)
        return code;
    const tp_store_scene* sc = tp_ground_scene(g);
    const tp_tree_geometry* geom = &sc->info.header.geometry;
    const double* gt = sc->info.header.geotransform;
    day_run r;
    memset(&r, 0, sizeof r);
    r.o = o;
    r.g = g;
    r.grid_w = geom->src_width, r.grid_h = geom->src_height;
    r.sun.dx_m = fabs(gt[1]), r.sun.dy_m = fabs(gt[5]);
    r.sun.maps = o->maps;
    const double mx = ceil(o->margin_m / r.sun.dx_m), my = ceil(o->margin_m / r.sun.dy_m);
    r.mx = mx < MARGIN_POSTS_MAX ? (int)mx : MARGIN_POSTS_MAX;
    r.my = my < MARGIN_POSTS_MAX ? (int)my : MARGIN_POSTS_MAX;
    r.tty = isatty(2);
    r.last_decile = -1;

    char* def = o->out ? NULL : default_out(sc->path);
    const char* out = o->out ? o->out : def;
    double* sun = malloc(3 * (size_t)o->maps * sizeof *sun);
    tp_light_place at;
    tp_sun_day day;
    code = TP_EXIT_FAILURE;
    if (!out || !sun) {
        tp_cli_error("out of memory");
        goto done;
    }
    if (!o->out && tp_output_check(out, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        goto done;
    }
    if (!strcmp(out, sc->path) || !strcmp(out, o->src.path)) {
        tp_cli_error("%s: the output would replace the input", out);
        goto done;
    }
    if (!day_window(&r, &at_pos, &at))
        goto done;
    r.band_rows = TILE;
    while (r.band_rows > TP_IMAGERY_BLOCK && (size_t)r.width * r.band_rows * 4 > BAND_BYTES_MAX)
        r.band_rows -= TP_IMAGERY_BLOCK;
    r.tiles_total = ((r.width + TILE - 1) / TILE) * ((r.height + r.band_rows - 1) / r.band_rows);
    r.sun.times_s = sun, r.sun.azimuth_deg = sun + o->maps, r.sun.elevation_deg = sun + 2 * o->maps;
    tp_status s = day_sun_make(&at, year, month, mday, o->maps, &day, sun, sun + o->maps,
                               sun + 2 * o->maps, &err);
    if (s != TP_OK) {
        tp_cli_error("%s", err.message);
        goto done;
    }
    /* a tile's window: the tile (at most the window) with its margins (at most the grid) */
    const int tw = r.width < TILE ? r.width : TILE,
              th = r.height < r.band_rows ? r.height : r.band_rows;
    const size_t win = (size_t)(tw + 2 * r.mx < r.grid_w ? tw + 2 * r.mx : r.grid_w) *
                       (size_t)(th + 2 * r.my < r.grid_h ? th + 2 * r.my : r.grid_h);
    r.band = malloc((size_t)r.width * r.band_rows * 4);
    for (int k = 0; k < 2; ++k) {
        r.job[k].sun = &r.sun;
        r.job[k].z = malloc(win * sizeof(float));
        r.job[k].texels = malloc(4 * win);
        if (!r.job[k].z || !r.job[k].texels)
            r.band = (free(r.band), NULL);
    }
    if (!r.band) {
        tp_cli_error("out of memory for tiles of %zu posts", win);
        goto done;
    }
    code = o->hours ? run_hours(&r, &at, &day, out, t_start) : run_map(&r, &at, &day, out, t_start);
done:
    for (int k = 0; k < 2; ++k) {
        free(r.job[k].z);
        free(r.job[k].texels);
    }
    free(r.band);
    free(r.hours);
    free(sun);
    free(def);
    tp_ground_destroy(g);
    return code == TP_EXIT_OK ? tp_cli_finish(code) : tp_planner_finish(code);
}
