/* planner_cli.c - what the planner commands share (see planner_cli.h). */
#define _POSIX_C_SOURCE 200809L
#include "planner_cli.h"
#include "clock.h"

#include "atomic_file.h"
#include "cli.h"
#include "ground_locate.h"

#include "tp_io.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

void tp_planner_source_init(tp_planner_source* s)
{
    memset(s, 0, sizeof *s);
    tp_scene_options_default(&s->dem);
}

/* --cache-dir (tp_option_handler): a group of one, so that the table needs no slot. */
static int cache_dir_option(void* ctx, int code, const char* value, const char* cmd)
{
    (void)code, (void)cmd;
    ((tp_planner_source*)ctx)->cache_dir = value;
    return 1;
}

void tp_planner_source_add(tp_options* p, tp_planner_source* s)
{
    static const tp_option cache_dir[] = {TP_OPT_CODE("--cache-dir", NULL, 1, 1)};
    tp_options_add(p, cache_dir, 1, cache_dir_option, s);
    tp_scene_options_add(p, &s->dem);
}

int tp_planner_parse(const char* cmd, int argc, char** argv, void (*help)(void),
                     tp_option_table own, tp_planner_source* src, const char* hint)
{
    tp_options p;
    tp_options_init(&p, cmd, argc, argv, help);
    tp_options_add(&p, own.options, own.count, own.handler, own.ctx);
    tp_planner_source_add(&p, src);
    for (int c; (c = tp_options_next(&p)) != TP_OPTIONS_END;) {
        if (c == TP_OPTIONS_OPERAND && !src->path)
            src->path = p.value;
        else if (c == TP_OPTIONS_OPERAND)
            return tp_options_stray(&p, NULL, hint), p.exit;
        else if (c == TP_OPTIONS_EXIT)
            return p.exit;
        else /* a CODE option without a handler: none in the planners' tables */
            return tp_options_stray(&p, NULL, ""), p.exit;
    }
    return src->path ? -1 : tp_cli_usage(cmd, "missing DEM");
}

void tp_planner_window_set(tp_ground* g, int x0, int y0, int x1, int y1, tp_planner_window* win)
{
    const double* gt = tp_ground_scene(g)->info.header.geotransform;
    memset(win, 0, sizeof *win);
    win->x0 = x0, win->y0 = y0, win->w = x1 - x0 + 1, win->h = y1 - y0 + 1;
    win->n = (size_t)win->w * (size_t)win->h;
    const double moved[6] = {gt[0] + x0 * gt[1], gt[1], 0.0, gt[3] + y0 * gt[5], 0.0, gt[5]};
    memcpy(win->gt, moved, sizeof moved);
}

void tp_planner_window_around(tp_ground* g, int cx, int cy, double radius_m,
                              tp_planner_window* win)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    const double* gt = sc->info.header.geotransform;
    int x0 = 0, y0 = 0, x1 = sc->info.header.geometry.src_width - 1,
        y1 = sc->info.header.geometry.src_height - 1;
    if (radius_m > 0.0) {
        const double rx = floor(radius_m / fabs(gt[1])), ry = floor(radius_m / fabs(gt[5]));
        if (rx < cx - x0)
            x0 = cx - (int)rx;
        if (rx < x1 - cx)
            x1 = cx + (int)rx;
        if (ry < cy - y0)
            y0 = cy - (int)ry;
        if (ry < y1 - cy)
            y1 = cy + (int)ry;
    }
    tp_planner_window_set(g, x0, y0, x1, y1, win);
}

tp_status tp_planner_window_read(tp_ground* g, tp_planner_window* win, const char* progress_cmd,
                                 tp_error* err)
{
    if (!(win->z = malloc(win->n * sizeof *win->z)))
        return tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory for a %dx%d window",
                            win->w, win->h);
    const double t0 = tp_clock_s();
    tp_status s = tp_ground_read_posts(g, win->x0, win->y0, win->w, win->h, win->z, progress_cmd,
                                       err);
    win->read_s = tp_clock_s() - t0;
    return s;
}

void tp_planner_window_free(tp_planner_window* win)
{
    free(win->z);
    win->z = NULL;
}

/* Writes with SIGINT/SIGTERM only recorded during the write (tp_interrupt_finished once the
 * output is whole): values bytes, or floats when floats is not NULL. */
static tp_status raster_write(tp_ground* g, const char* out, const uint8_t* values,
                              const float* floats, const tp_planner_window* win,
                              const char* description, tp_error* err)
{
    tp_interrupt_hold(); /* a signal during the write is only recorded (tp_interrupt_finished) */
    const char* crs = tp_ground_scene(g)->info.header.crs_wkt;
    tp_status s = floats ? tp_float_raster_write(out, floats, win->n, win->w, win->h, win->gt,
                                                 crs, description, err)
                         : tp_byte_raster_write(out, values, win->n, win->w, win->h, win->gt,
                                                crs, description, err);
    if (s == TP_OK)
        tp_interrupt_finished();
    tp_interrupt_release();
    return s;
}

tp_status tp_planner_raster_write(tp_ground* g, const char* out, const uint8_t* values,
                                  const tp_planner_window* win, const char* description,
                                  tp_error* err)
{
    return raster_write(g, out, values, NULL, win, description, err);
}

tp_status tp_planner_float_raster_write(tp_ground* g, const char* out, const float* values,
                                        const tp_planner_window* win, const char* description,
                                        tp_error* err)
{
    return raster_write(g, out, NULL, values, win, description, err);
}

/* The hint that a position is latitude first, after the text of a message. */
#define LATITUDE_FIRST "a position is LAT LON, latitude first"

int tp_planner_position(const char* cmd, const char* what, const char* text,
                        tp_position_readings* pos)
{
    (void)cmd; /* messages name the command main() dispatched to (tp_cli_error) */
    char hint[200] = "";
    tp_error err = {{0}};
    if (tp_position_parse_readings(text, strlen(text), 0, pos, &err))
        return 1;
    char swapped[128];
    if (tp_position_swapped(text, swapped, sizeof swapped)) /* "139.7 35.6" */
        snprintf(hint, sizeof hint, "; " LATITUDE_FIRST ": '%s'?", swapped);
    tp_cli_error("%s '%s': %s%s", what, text, err.message, hint);
    return 0;
}

int tp_planner_choose(const char* cmd, const char* path, tp_ground* g,
                      const tp_position_readings* pos, const char* input, tp_position* out)
{
    (void)cmd; /* messages name the command main() dispatched to (tp_cli_error) */
    if (pos->count < 2) {
        *out = pos->reading[0];
        return 1;
    }
    char r0[128], r1[128];
    double x, y;
    int on0 = tp_ground_on_dem(g, &pos->reading[0], &x, &y);
    int on1 = tp_ground_on_dem(g, &pos->reading[1], &x, &y);
    tp_position_reading_text(pos, 0, r0, sizeof r0);
    tp_position_reading_text(pos, 1, r1, sizeof r1);
    if (on0 != on1) {
        tp_cli_note("note: read '%s' as %s; the other reading, %s, is off %s", input, on0 ? r0 : r1,
                    on0 ? r1 : r0, path);
        *out = pos->reading[on0 ? 0 : 1];
        return 1;
    }
    tp_cli_error("%s: '%s' is ambiguous: %s or %s, and %s on the DEM; write the "
                 "zone's hemisphere as %dnorth or %dsouth, or give the position in MGRS",
                 path, input, r0, r1, on0 ? "both are" : "neither is", pos->reading[0].zone,
                 pos->reading[0].zone);
    return 0;
}

void tp_planner_swap_hint(tp_ground* g, const tp_position* pos, char* out, size_t cap)
{
    tp_position swapped = {.lat_deg = pos->lon_deg, .lon_deg = pos->lat_deg};
    double x, y;
    if (cap)
        out[0] = '\0';
    if (!pos->has_grid && fabs(pos->lon_deg) <= 90.0 && !tp_ground_on_dem(g, pos, &x, &y) &&
        tp_ground_on_dem(g, &swapped, &x, &y))
        snprintf(
            out, cap,
            "; with latitude and longitude swapped (%.6f %.6f) it is on the DEM: " LATITUDE_FIRST,
            swapped.lat_deg, swapped.lon_deg);
}

void tp_planner_positions_free(tp_planner_positions* p)
{
    for (size_t i = 0; p->text && i < p->count; ++i)
        free(p->text[i]);
    free(p->text);
    free(p->readings);
    memset(p, 0, sizeof *p);
}

int tp_planner_positions_read(const char* cmd, const char* what, const char* const* values,
                              size_t count, tp_planner_positions* out)
{
    memset(out, 0, sizeof *out);
    size_t n = 0;
    for (size_t i = 0; i < count; ++i) {
        ++n;
        for (const char* c = values[i]; *c; ++c)
            n += *c == ';';
    }
    out->text = calloc(n ? n : 1, sizeof *out->text);
    out->readings = calloc(n ? n : 1, sizeof *out->readings);
    if (!out->text || !out->readings) {
        tp_cli_error("out of memory for %zu positions", n);
        tp_planner_positions_free(out);
        return 0;
    }
    for (size_t i = 0; i < count; ++i) {
        const char* at = values[i];
        for (;;) {
            const char* end = strchr(at, ';');
            size_t len = end ? (size_t)(end - at) : strlen(at);
            while (len && (*at == ' ' || *at == '\t'))
                ++at, --len;
            while (len && (at[len - 1] == ' ' || at[len - 1] == '\t'))
                --len;
            char* text = malloc(len + 1);
            if (!text) {
                tp_cli_error("out of memory for %zu positions", n);
                tp_planner_positions_free(out);
                return 0;
            }
            memcpy(text, at, len);
            text[len] = '\0';
            out->text[out->count] = text;
            if (!tp_planner_position(cmd, what, text, &out->readings[out->count++])) {
                tp_planner_positions_free(out);
                return 0;
            }
            if (!end)
                break;
            at = end + 1;
        }
    }
    return 1;
}

int tp_planner_positions_place(const char* cmd, const char* path, tp_ground* g, const char* what,
                               const tp_planner_positions* p, double* en)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    for (size_t i = 0; i < p->count; ++i) {
        char hint[256];
        tp_error err = {{0}};
        tp_position pos;
        double x, y, h;
        if (!tp_planner_choose(cmd, path, g, &p->readings[i], p->text[i], &pos))
            return 0;
        if (!tp_ground_locate(g, &pos, p->text[i], &x, &y, &h, &err)) {
            tp_planner_swap_hint(g, &pos, hint, sizeof hint);
            tp_cli_error("%s: %s: %s%s", path, what, tp_cli_unprefixed(path, err.message), hint);
            return 0;
        }
        /* where tp_ground_locate found it on the ground: the render CRS's E, N */
        if (tp_georef_geo_to_proj(sc->georef, pos.lat_deg, pos.lon_deg, &en[2 * i], &en[2 * i + 1],
                                  &err) != TP_OK) {
            tp_cli_error("%s: %s: position '%s': %s", path, what, p->text[i], err.message);
            return 0;
        }
    }
    return 1;
}

int tp_planner_check_outputs(const char* const* paths, int count)
{
    for (int i = 0; i < count; ++i)
        if (paths[i] && strcmp(paths[i], "-") && !tp_atomic_check_dir(paths[i]))
            return 0;
    return 1;
}

int tp_planner_ground_open(const char* cmd, const tp_planner_source* src, tp_ground** g)
{
    tp_ground_options go = {.cache_dir = src->cache_dir, .cmd = cmd, .dem = &src->dem};
    return tp_ground_open(src->path, &go, g);
}

void tp_planner_help(const char* text, const char* after)
{
    fputs(text, stdout);
    fputs("\nDEM options (as every command that opens a DEM takes them; a DEM is read through\n"
          "its store in the cache, built with --patch, --crs, --resampling, --fill-max and\n"
          "--fill-from; a store keeps those it was built with and refuses them):\n"
          "  --cache-dir DIR     the store cache for a DEM (as 'terrapatch view')\n",
          stdout);
    tp_scene_options_help(stdout);
    fputs("\n", stdout);
    fputs(after, stdout);
}

int tp_planner_locate(const char* cmd, const char* path, tp_ground* g,
                      const tp_position_readings* pos, const char* input, double* x, double* y,
                      double* height_m)
{
    char hint[256];
    tp_error err = {{0}};
    tp_position p;
    if (!tp_planner_choose(cmd, path, g, pos, input, &p))
        return 0;
    if (tp_ground_locate(g, &p, input, x, y, height_m, &err))
        return 1;
    tp_planner_swap_hint(g, &p, hint, sizeof hint);
    tp_cli_error("%s: %s%s", path, tp_cli_unprefixed(path, err.message), hint);
    return 0;
}

/* What write prints, added to set as path; 1, or 0 after the writer's message. */
static int add_printed(tp_file_set* set, const char* path, tp_planner_write_fn write, void* report)
{
    tp_atomic_file af;
    if (!tp_atomic_open(&af, path))
        return 0;
    write(af.f, report);
    return tp_atomic_add_to_set(&af, set);
}

/* The gnuplot PNG added to set as png; 1, or 0 after a line. */
static int add_plot(tp_file_set* set, const char* cmd, const tp_planner_outputs* o, void* report)
{
    size_t size = 0;
    unsigned char* bytes = tp_gnuplot_draw(o->png, o->png_width_px, o->png_height_px, o->write_plot,
                                           report, cmd, &size);
    tp_error err;
    int ok = bytes && tp_file_set_add(set, o->png, bytes, size, &err) == TP_OK;
    if (bytes && !ok && !tp_interrupted())
        tp_cli_error("%s", err.message);
    free(bytes);
    return ok;
}

int tp_planner_write_outputs(const char* cmd, const tp_planner_outputs* o, void* report)
{
    const int json_stdout = o->json && !strcmp(o->json, "-");
    if (json_stdout)
        o->write_json(stdout, report);
    else
        o->write_text(stdout, report);
    const char* files[3];
    int count = 0;
    if (o->json && !json_stdout)
        files[count++] = o->json;
    if (o->csv)
        files[count++] = o->csv;
    if (o->png)
        files[count++] = o->png;
    if (!count)
        return 1;
    /* every file to its temporary first, then all renamed or none (tp_file_set_*); held until
     * tp_interrupt_finished, so a signal after the renames cannot undo the "wrote" lines */
    tp_interrupt_hold();
    tp_file_set* set = NULL;
    tp_error err;
    int ok = tp_file_set_begin(&set, &err) == TP_OK;
    if (!ok)
        tp_cli_error("%s", err.message);
    if (ok && o->json && !json_stdout)
        ok = add_printed(set, o->json, o->write_json, report);
    if (ok && o->csv)
        ok = add_printed(set, o->csv, o->write_csv, report);
    if (ok && o->png)
        ok = add_plot(set, cmd, o, report);
    if (ok) {
        ok = tp_file_set_commit(set, &err) == TP_OK;
        if (!ok && !tp_interrupted())
            tp_cli_error("%s", err.message);
    } else {
        tp_file_set_abort(set);
    }
    if (ok) {
        tp_interrupt_finished();
        for (int i = 0; i < count; ++i)
            tp_cli_note("wrote %s", files[i]);
    } else if (count > 1 && !tp_interrupted()) {
        char names[2048] = "";
        for (int i = 0; i < count; ++i)
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i ? ", " : "",
                     files[i]);
        tp_cli_error("none of %s written (all or none: older files as they were)", names);
    }
    tp_interrupt_release();
    return ok;
}

int tp_planner_finish(int code)
{
    if (tp_interrupted())
        return tp_cli_interrupted();
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}

/* The render-CRS point (e, n) at the centre of the window around pos: the grid post nearest
 * it, or pos itself in a void. 1, or 0 after a line. */
static int window_centre(const char* cmd, const char* path, tp_ground* g,
                         const tp_position_readings* around, const char* around_text, double* e,
                         double* n)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    const double* gt = sc->info.header.geotransform;
    double fx, fy, fh;
    char hint[256] = "";
    tp_error lerr = {{0}}, err = {{0}};
    tp_position pos;
    if (!tp_planner_choose(cmd, path, g, around, around_text, &pos))
        return 0;
    if (tp_ground_locate(g, &pos, around_text, &fx, &fy, &fh, &lerr)) {
        *e = gt[0] + (fx + 0.5) * gt[1], *n = gt[3] + (fy + 0.5) * gt[5];
        return 1;
    }
    /* a centre in a void is fine: the ground around it is still wanted */
    if (strstr(lerr.message, "is in a void") &&
        tp_georef_geo_to_proj(sc->georef, pos.lat_deg, pos.lon_deg, e, n, &err) == TP_OK)
        return 1;
    tp_planner_swap_hint(g, &pos, hint, sizeof hint);
    tp_cli_error("%s: %s%s", path, tp_cli_unprefixed(path, lerr.message), hint);
    return 0;
}

int tp_planner_window_choose(const char* cmd, const char* path, tp_ground* g, const double* area,
                             const tp_position_readings* around, const char* around_text,
                             double radius_m, tp_planner_window* win)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    const tp_tree_geometry* geom = &sc->info.header.geometry;
    const double* gt = sc->info.header.geotransform;
    const int W = geom->src_width, H = geom->src_height;
    if (!area && !around) {
        tp_planner_window_set(g, 0, 0, W - 1, H - 1, win);
        return 1;
    }
    double e0, n0, e1, n1;
    if (around) {
        double e, n;
        if (!window_centre(cmd, path, g, around, around_text, &e, &n))
            return 0;
        e0 = e - radius_m, e1 = e + radius_m, n0 = n - radius_m, n1 = n + radius_m;
    } else {
        e0 = area[0], n0 = area[1], e1 = area[2], n1 = area[3];
    }
    /* grid x of E: (E - gt0) / gt1 - 0.5; posts inside [e0, e1] x [n0, n1] */
    double ax = (e0 - gt[0]) / gt[1] - 0.5, bx = (e1 - gt[0]) / gt[1] - 0.5;
    double ay = (n0 - gt[3]) / gt[5] - 0.5, by = (n1 - gt[3]) / gt[5] - 0.5;
    double lx = fmin(ax, bx), hx = fmax(ax, bx), ly = fmin(ay, by), hy = fmax(ay, by);
    lx = fmax(ceil(lx - 1e-9), 0.0), ly = fmax(ceil(ly - 1e-9), 0.0);
    hx = fmin(floor(hx + 1e-9), W - 1.0), hy = fmin(floor(hy + 1e-9), H - 1.0);
    if (lx > hx || ly > hy) {
        tp_cli_error("%s: the area E %.1f .. %.1f, N %.1f .. %.1f is outside the DEM (E %.1f .. "
                     "%.1f, N %.1f .. %.1f, render CRS)",
                     path, e0, e1, n0, n1, gt[0] + 0.5 * gt[1], gt[0] + (W - 0.5) * gt[1],
                     gt[3] + (H - 0.5) * gt[5], gt[3] + 0.5 * gt[5]);
        return 0;
    }
    tp_planner_window_set(g, (int)lx, (int)ly, (int)hx, (int)hy, win);
    return 1;
}

int tp_planner_window_fits(const char* path, const tp_planner_window* pw, size_t max_posts,
                           size_t bytes_per_post)
{
    tp_memory_room room;
    tp_memory_room_now(&room);
    if (pw->n > max_posts) {
        tp_cli_error("%s: a %dx%d window is %zu posts, more than one run takes (%zu, 8192 x "
                     "8192); choose a part with --area or --around",
                     path, pw->w, pw->h, pw->n, max_posts);
        return 0;
    }
    if ((uint64_t)pw->n * bytes_per_post > room.bytes) {
        tp_cli_error("%s: a %dx%d window needs about %.0f MiB, %.0f MiB left (%s); choose a part "
                     "with --area or --around",
                     path, pw->w, pw->h, pw->n * (double)bytes_per_post / 1048576.0,
                     room.bytes / 1048576.0, room.bound);
        return 0;
    }
    return 1;
}

void tp_planner_print_ground(const tp_planner_window* pw, int grid_w, int grid_h, int part,
                             double step_m)
{
    size_t voids = 0;
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < pw->n; ++i) {
        const float z = pw->z[i];
        voids += z != z;
        lo = fminf(lo, z), hi = fmaxf(hi, z); /* NaN passed over */
    }
    if (part)
        printf("window     %dx%d posts from (%d, %d) of %dx%d\n", pw->w, pw->h, pw->x0, pw->y0,
               grid_w, grid_h);
    else
        printf("window     %dx%d posts: the whole DEM\n", pw->w, pw->h);
    char step[64] = "";
    if (step_m > 0.0)
        snprintf(step, sizeof step, " (stored in steps of %g m)", step_m);
    if (lo <= hi)
        printf("ground     %.1f .. %.1f m%s, %zu void posts\n", (double)lo, (double)hi, step,
               voids);
    else
        printf("ground     all %zu posts void\n", voids);
}
