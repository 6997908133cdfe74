/* qm_export.c - a Cesium quantized-mesh tile set of a store (see qm_export.h): the levels and
 * their tiles, the resumable run, the neighbours' shared edges checked, layer.json and
 * errors.json. */
#include "qm_export.h"
#include "qm_tile.h"
#include "qm_workers.h"

#include "atomic_file.h"
#include "cli.h"
#include "clock.h"
#include "ground.h"
#include "json.h"
#include "progress.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define QM_MAX_ZOOM 22

double tp_qm_level_bound(int z, int max_zoom, double max_error_m)
{
    if (max_error_m < 0)
        return tp_qmesh_level_error_m(z);
    return ldexp(max_error_m, max_zoom - z);
}

/* One tile's record: built now or read back from tiles.log. */
typedef struct tile_rec {
    int done;
    double measured_m, bound_m;
    size_t vertices, triangles, gz_bytes, raw_bytes, posts;
    uint64_t edge[4];
} tile_rec;

typedef struct level {
    int z, x0, x1, y0, y1; /* tiles x0..x1, y0..y1 */
    tile_rec* tiles;       /* (x1 - x0 + 1) * (y1 - y0 + 1) */
} level;

typedef struct qm_run {
    const tp_qm_request* r;
    qm_source src;
    int max_zoom;
    level lv[QM_MAX_ZOOM + 1];
    size_t total, done_before;
    char options[1024];
    double proj_interp_m;
} qm_run;

static tile_rec* rec_at(level* l, int x, int y)
{
    return &l->tiles[(size_t)(y - l->y0) * (l->x1 - l->x0 + 1) + (x - l->x0)];
}

static int fail_line(const qm_run* q, const char* what)
{
    tp_cli_error("%s: %s", q->r->path, what);
    return TP_EXIT_FAILURE;
}

/* ---- the store's extent, spacing and heights ---- */

static int extent(qm_run* q)
{
    qm_source* s = &q->src;
    s->lat_lo = s->lon_lo = INFINITY;
    s->lat_hi = s->lon_hi = -INFINITY;
    const int k = 64;
    for (int i = 0; i <= k; i++)
        for (int side = 0; side < 4; side++) {
            double f = (double)i / k, x, y;
            x = side < 2 ? f * (s->width - 1) : side == 2 ? 0 : s->width - 1;
            y = side >= 2 ? f * (s->height - 1) : side == 0 ? 0 : s->height - 1;
            double e, n, lat, lon;
            tp_georef_grid_to_proj(s->georef, x, y, &e, &n);
            if (tp_georef_proj_to_geo(s->georef, e, n, &lat, &lon, NULL) != TP_OK)
                continue;
            s->lat_lo = fmin(s->lat_lo, lat);
            s->lat_hi = fmax(s->lat_hi, lat);
            s->lon_lo = fmin(s->lon_lo, lon);
            s->lon_hi = fmax(s->lon_hi, lon);
        }
    if (!(s->lat_lo <= s->lat_hi && s->lon_lo <= s->lon_hi))
        return 0;
    /* padded by 4 posts (a post is at most ~ spacing / 111 km degrees of latitude) */
    const tp_tree_info* ti = &tp_ground_scene(s->ground)->tree_info;
    const double sp = fmax(fabs(ti->geotransform[1]), fabs(ti->geotransform[5]));
    const double pad = 4 * sp / 111000.0 / fmax(0.05, cos(fmax(fabs(s->lat_lo), fabs(s->lat_hi)) * M_PI / 180));
    s->lat_lo = fmax(-90, s->lat_lo - pad);
    s->lat_hi = fmin(90, s->lat_hi + pad);
    s->lon_lo = fmax(-180, s->lon_lo - pad);
    s->lon_hi = fmin(180, s->lon_hi + pad);
    return 1;
}

/* The default deepest level: the first whose lattice cell (at the store's middle latitude) is
 * no larger in area than a post's cell. */
static int default_zoom(const qm_run* q)
{
    const tp_tree_info* ti = &tp_ground_scene(q->src.ground)->tree_info;
    const double post_area = fabs(ti->geotransform[1] * ti->geotransform[5]);
    const double lat = 0.5 * (q->src.lat_lo + q->src.lat_hi) * M_PI / 180;
    for (int z = 0; z < QM_MAX_ZOOM; z++) {
        const double d = 180.0 / ldexp(TP_QM_CELLS, z);
        const double cell = (d * 111132.0) * (d * 111320.0 * cos(lat));
        if (cell <= post_area)
            return z;
    }
    return QM_MAX_ZOOM;
}

/* The common height step: the smallest power of two whose 32767 steps span every height a
 * tile may hold (the store's, the geoid's undulation added, and 0 where there is no data). */
static int height_step(qm_run* q)
{
    const tp_tree_info* ti = &tp_ground_scene(q->src.ground)->tree_info;
    double lo = isnan(ti->min_height_m) ? 0 : fmin(0, ti->min_height_m);
    double hi = isnan(ti->max_height_m) ? 0 : fmax(0, ti->max_height_m);
    if (q->src.geoid) {
        double nlo = INFINITY, nhi = -INFINITY;
        for (int i = 0; i <= 8; i++)
            for (int j = 0; j <= 8; j++) {
                double lat = q->src.lat_lo + (q->src.lat_hi - q->src.lat_lo) * i / 8;
                double lon = q->src.lon_lo + (q->src.lon_hi - q->src.lon_lo) * j / 8, n;
                tp_error err;
                if (tp_geoid_undulation(q->src.geoid, 1, &lat, &lon, &n, &err) != TP_OK)
                    return fail_line(q, err.message), 0;
                nlo = fmin(nlo, n);
                nhi = fmax(nhi, n);
            }
        lo = fmin(lo, lo + nlo - 10); /* the undulation varies between the 81 points: 10 m */
        hi = fmax(hi, hi + nhi + 10);
    }
    const double range = hi - lo + 16;
    q->src.height_step_m = ldexp(1.0, (int)ceil(log2(range / TP_QMESH_MAX_CODE)));
    return 1;
}

/* ---- the levels and their tiles ---- */

static int plan(qm_run* q)
{
    double w = q->src.lon_lo, s = q->src.lat_lo, e = q->src.lon_hi, n = q->src.lat_hi;
    if (q->r->has_bounds) {
        w = fmax(w, q->r->bounds[0]);
        s = fmax(s, q->r->bounds[1]);
        e = fmin(e, q->r->bounds[2]);
        n = fmin(n, q->r->bounds[3]);
        if (!(w < e && s < n)) {
            tp_cli_error("--bounds %g,%g,%g,%g: no part of %s lies inside (its extent: %.6f,%.6f,"
                         "%.6f,%.6f)",
                         q->r->bounds[0], q->r->bounds[1], q->r->bounds[2], q->r->bounds[3],
                         q->r->path, q->src.lon_lo, q->src.lat_lo, q->src.lon_hi, q->src.lat_hi);
            return 0;
        }
    }
    q->total = 0;
    for (int z = 0; z <= q->max_zoom; z++) {
        level* l = &q->lv[z];
        const double size = 180.0 / ldexp(1.0, z);
        const int nx = 2 << z, ny = 1 << z;
        l->z = z;
        if (z == 0) { /* both roots, always: Cesium starts from them */
            l->x0 = 0, l->x1 = 1, l->y0 = 0, l->y1 = 0;
        } else {
            l->x0 = (int)fmax(0, floor((w + 180) / size));
            l->x1 = (int)fmin(nx - 1, floor((e + 180) / size));
            l->y0 = (int)fmax(0, floor((s + 90) / size));
            l->y1 = (int)fmin(ny - 1, floor((n + 90) / size));
        }
        const size_t count = (size_t)(l->x1 - l->x0 + 1) * (size_t)(l->y1 - l->y0 + 1);
        l->tiles = calloc(count, sizeof *l->tiles);
        if (!l->tiles)
            return fail_line(q, "out of memory"), 0;
        q->total += count;
    }
    return 1;
}

/* ---- DIR/export.txt, DIR/tiles.log ---- */

static void path_in(const qm_run* q, char* out, size_t cap, const char* name)
{
    snprintf(out, cap, "%s/%s", q->r->out_dir, name);
}

static int make_dir(const char* p)
{
    struct stat st;
    if (mkdir(p, 0777) == 0 || (errno == EEXIST && stat(p, &st) == 0 && S_ISDIR(st.st_mode)))
        return 1;
    if (errno == EEXIST) {
        tp_cli_error("%s: exists and is not a folder (-o names the tile set's folder)", p);
        return 0;
    }
    tp_cli_error("%s: cannot create the folder: %s", p, strerror(errno));
    return 0;
}

/* Removes the temporary files a killed run left beside its tiles (tp_file_write's PATH.tmp and
 * 8 characters: a SIGKILL during a write runs no handler); their count. */
static size_t remove_stale(const qm_run* q)
{
    size_t removed = 0;
    char p[4200];
    for (int z = 0; z <= q->max_zoom; z++) {
        const level* l = &q->lv[z];
        for (int x = l->x0; x <= l->x1; x++) {
            snprintf(p, sizeof p, "%s/%d/%d", q->r->out_dir, z, x);
            DIR* d = opendir(p);
            if (!d)
                continue;
            struct dirent* e;
            while ((e = readdir(d))) {
                const char* t = strstr(e->d_name, ".terrain.tmp");
                if (!t || strlen(t) != strlen(".terrain.tmp") + 8)
                    continue;
                char f[4500];
                snprintf(f, sizeof f, "%s/%s", p, e->d_name);
                removed += unlink(f) == 0;
            }
            closedir(d);
        }
    }
    return removed;
}

/* Reads an earlier run's options and tiles, or starts one; 0 after a message. */
static int resume(qm_run* q)
{
    char p[4096];
    if (!make_dir(q->r->out_dir))
        return 0;
    path_in(q, p, sizeof p, "export.txt");
    FILE* f = fopen(p, "r");
    if (f) {
        char line[1024] = "";
        if (!fgets(line, sizeof line, f))
            line[0] = 0;
        fclose(f);
        line[strcspn(line, "\n")] = 0;
        if (strcmp(line, q->options)) {
            tp_cli_error("%s holds an export with other options (%s; now %s): remove the folder "
                         "or choose another -o",
                         q->r->out_dir, line, q->options);
            return 0;
        }
        const size_t stale = remove_stale(q);
        if (stale)
            tp_cli_note("%s: %zu temporary files of a killed run removed", q->r->out_dir, stale);
    } else {
        char text[1100];
        snprintf(text, sizeof text, "%s\n", q->options);
        tp_error err;
        if (tp_file_write(p, text, strlen(text), &err) != TP_OK) {
            tp_cli_error("%s", err.message);
            return 0;
        }
    }
    path_in(q, p, sizeof p, "tiles.log");
    f = fopen(p, "r");
    if (!f)
        return 1;
    char line[512];
    while (fgets(line, sizeof line, f)) {
        int z, x, y;
        tile_rec t;
        memset(&t, 0, sizeof t);
        t.done = 1;
        unsigned long long e[4];
        if (sscanf(line, "%d %d %d %lf %lf %zu %zu %zu %zu %zu %llx %llx %llx %llx", &z, &x, &y,
                   &t.measured_m, &t.bound_m, &t.vertices, &t.triangles, &t.gz_bytes,
                   &t.raw_bytes, &t.posts, &e[0], &e[1], &e[2], &e[3]) != 14 ||
            !strchr(line, '\n') || z < 0 || z > q->max_zoom)
            continue; /* a line cut short by a kill: that tile is built again */
        level* l = &q->lv[z];
        if (x < l->x0 || x > l->x1 || y < l->y0 || y > l->y1)
            continue;
        char tp[4200];
        snprintf(tp, sizeof tp, "%s/%d/%d/%d.terrain", q->r->out_dir, z, x, y);
        struct stat st;
        if (stat(tp, &st) != 0 || (size_t)st.st_size != t.gz_bytes)
            continue;
        for (int k = 0; k < 4; k++)
            t.edge[k] = e[k];
        tile_rec* slot = rec_at(l, x, y);
        q->done_before += !slot->done;
        *slot = t;
    }
    fclose(f);
    return 1;
}

static int write_tile(qm_run* q, FILE* log, int z, int x, int y, const qm_tile_result* t)
{
    char p[4200];
    snprintf(p, sizeof p, "%s/%d", q->r->out_dir, z);
    if (!make_dir(p))
        return 0;
    snprintf(p, sizeof p, "%s/%d/%d", q->r->out_dir, z, x);
    if (!make_dir(p))
        return 0;
    snprintf(p, sizeof p, "%s/%d/%d/%d.terrain", q->r->out_dir, z, x, y);
    tp_error err;
    if (tp_file_write(p, t->gz, t->gz_size, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return 0;
    }
    fprintf(log, "%d %d %d %.17g %.17g %zu %zu %zu %zu %zu %llx %llx %llx %llx\n", z, x, y,
            t->measured_m, t->bound_m, t->vertices, t->triangles, t->gz_size, t->raw_size,
            t->posts_measured, (unsigned long long)t->edge_hash[0],
            (unsigned long long)t->edge_hash[1], (unsigned long long)t->edge_hash[2],
            (unsigned long long)t->edge_hash[3]);
    if (fflush(log) != 0) {
        tp_cli_error("%s/tiles.log: %s", q->r->out_dir, strerror(errno));
        return 0;
    }
    return 1;
}

/* ---- the run ---- */

/* What the tiles of a level, delivered in order (qm_workers.h), are written with. */
typedef struct level_run {
    qm_run* q;
    FILE* log;
    level* l;
    const int* xy;
    tp_progress* pr;
    size_t *done, built;
    int code;
} level_run;

static int deliver(void* ctx, size_t i, int ok, qm_tile_result* t, const tp_error* err)
{
    level_run* c = ctx;
    qm_run* q = c->q;
    const int z = c->l->z, x = c->xy[2 * i], y = c->xy[2 * i + 1];
    if (!ok) {
        c->code = fail_line(q, err->message);
        return 0;
    }
    q->proj_interp_m = fmax(q->proj_interp_m, t->proj_interp_m);
    if (t->measured_m > t->bound_m) /* the refinement stopped short: said, and written */
        tp_cli_note("tile %d/%d/%d: measured %.3f m, above its level's bound %.3f m "
                    "(%d refinement passes; a post on a vertex's code at %.3f m)",
                    z, x, y, t->measured_m, t->bound_m, t->passes, t->stuck_m);
    const int written = write_tile(q, c->log, z, x, y, t);
    const tile_rec r = {1, t->measured_m, t->bound_m, t->vertices, t->triangles,
                        t->gz_size, t->raw_size, t->posts_measured,
                        {t->edge_hash[0], t->edge_hash[1], t->edge_hash[2], t->edge_hash[3]}};
    free(t->gz);
    if (!written) {
        c->code = TP_EXIT_FAILURE;
        return 0;
    }
    *rec_at(c->l, x, y) = r;
    c->built++;
    (*c->done)++;
    tp_progress_update(c->pr, (double)*c->done, (double)q->total, -1);
    if (tp_interrupted()) {
        c->code = tp_cli_interrupted();
        return 0;
    }
    return 1;
}

/* Level z's tiles not written yet, built on the workers' threads and written in order (the
 * order and bytes of one thread). */
static int build_level(qm_run* q, qm_workers* wk, FILE* log, int z, tp_progress* pr, size_t* done)
{
    level* l = &q->lv[z];
    const size_t count = (size_t)(l->x1 - l->x0 + 1) * (size_t)(l->y1 - l->y0 + 1);
    int* xy = malloc(2 * count * sizeof *xy);
    if (!xy)
        return fail_line(q, "out of memory");
    size_t n = 0;
    for (int y = l->y0; y <= l->y1; y++)
        for (int x = l->x0; x <= l->x1; x++)
            if (!rec_at(l, x, y)->done)
                xy[2 * n] = x, xy[2 * n + 1] = y, n++;
    *done += count - n;
    tp_progress_update(pr, (double)*done, (double)q->total, -1);
    const double lw = tp_clock_s(), lc = (double)clock() / CLOCKS_PER_SEC;
    level_run c = {q, log, l, xy, pr, done, 0, TP_EXIT_OK};
    tp_error err;
    const int ran = tp_qm_workers_run(wk, z, xy, n, tp_qm_level_bound(z, q->max_zoom,
                                                                      q->r->max_error_m),
                                      deliver, &c, &err);
    free(xy);
    if (ran < 0)
        return fail_line(q, err.message);
    if (c.code == TP_EXIT_OK && c.built)
        tp_cli_note("level %d: %zu tiles built in %.2f s (%.2f s of CPU, %d thread%s)", z,
                    c.built, tp_clock_s() - lw, (double)clock() / CLOCKS_PER_SEC - lc,
                    tp_qm_workers_threads(wk), tp_qm_workers_threads(wk) > 1 ? "s" : "");
    return c.code;
}

static int build_all(qm_run* q, double* seconds)
{
    char p[4096];
    path_in(q, p, sizeof p, "tiles.log");
    /* no more threads (each with its ground's tree and cache) than a level has tiles to build */
    size_t most = 1;
    for (int z = 0; z <= q->max_zoom; z++) {
        const level* l = &q->lv[z];
        size_t n = 0;
        for (size_t i = 0; i < (size_t)(l->x1 - l->x0 + 1) * (size_t)(l->y1 - l->y0 + 1); i++)
            n += !l->tiles[i].done;
        most = n > most ? n : most;
    }
    qm_workers* wk = NULL;
    tp_error err;
    const int threads = (size_t)q->r->threads < most ? q->r->threads : (int)most;
    if (!tp_qm_workers_create(&q->src, threads, &wk, &err))
        return fail_line(q, err.message);
    FILE* log = fopen(p, "a");
    if (!log) {
        tp_cli_error("%s: cannot open: %s", p, strerror(errno));
        tp_qm_workers_destroy(wk);
        return TP_EXIT_FAILURE;
    }
    tp_progress pr;
    tp_progress_start(&pr, 1, "export", "tiles");
    size_t done = 0;
    const double t0 = tp_clock_s();
    int code = TP_EXIT_OK;
    for (int z = 0; z <= q->max_zoom && code == TP_EXIT_OK; z++)
        code = build_level(q, wk, log, z, &pr, &done);
    *seconds = tp_clock_s() - t0;
    tp_qm_workers_destroy(wk);
    if (fclose(log) != 0 && code == TP_EXIT_OK) {
        tp_cli_error("%s: %s", p, strerror(errno));
        code = TP_EXIT_FAILURE;
    }
    return code;
}

/* Every pair of neighbouring tiles of a level has the same vertices (position, height) on the
 * side they share; the pairs compared in *pairs. 0 after a message naming the first that
 * differs. */
static int check_edges(qm_run* q, size_t* pairs)
{
    *pairs = 0;
    for (int z = 0; z <= q->max_zoom; z++) {
        level* l = &q->lv[z];
        for (int y = l->y0; y <= l->y1; y++)
            for (int x = l->x0; x <= l->x1; x++) {
                const tile_rec* t = rec_at(l, x, y);
                if (x > l->x0) {
                    const tile_rec* west = rec_at(l, x - 1, y);
                    if (west->edge[2] != t->edge[0]) {
                        tp_cli_error("%s: tiles %d/%d/%d and %d/%d/%d do not share their edge "
                                     "vertices",
                                     q->r->out_dir, z, x - 1, y, z, x, y);
                        return 0;
                    }
                    (*pairs)++;
                }
                if (y > l->y0) {
                    const tile_rec* south = rec_at(l, x, y - 1);
                    if (south->edge[3] != t->edge[1]) {
                        tp_cli_error("%s: tiles %d/%d/%d and %d/%d/%d do not share their edge "
                                     "vertices",
                                     q->r->out_dir, z, x, y - 1, z, x, y);
                        return 0;
                    }
                    (*pairs)++;
                }
            }
    }
    return 1;
}

/* ---- layer.json, errors.json, the summary ---- */

static void level_stats(level* l, size_t* n, double* max_m, size_t* tris, size_t* bytes)
{
    *n = 0, *max_m = 0, *tris = 0, *bytes = 0;
    for (int y = l->y0; y <= l->y1; y++)
        for (int x = l->x0; x <= l->x1; x++) {
            const tile_rec* t = rec_at(l, x, y);
            (*n)++;
            *max_m = fmax(*max_m, t->measured_m);
            *tris += t->triangles;
            *bytes += t->gz_bytes;
        }
}

static int write_layer(qm_run* q)
{
    char p[4096];
    path_in(q, p, sizeof p, "layer.json");
    tp_atomic_file a;
    if (!tp_atomic_open(&a, p))
        return 0;
    tp_json j;
    tp_json_init(&j, a.f);
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "tilejson", "2.1.0");
    tp_json_member_string(&j, "name", "terrapatch");
    tp_json_member_string(&j, "description", "Cesium terrain tiles written by terrapatch export");
    tp_json_member_string(&j, "version", "1.0.0");
    tp_json_member_string(&j, "format", "quantized-mesh-1.0");
    tp_json_member_string(&j, "attribution", "");
    tp_json_member_string(&j, "scheme", "tms");
    tp_json_member_string(&j, "projection", "EPSG:4326");
    tp_json_key(&j, "extensions");
    tp_json_array_begin(&j);
    tp_json_string(&j, "octvertexnormals");
    tp_json_array_end(&j);
    tp_json_key(&j, "tiles");
    tp_json_array_begin(&j);
    tp_json_string(&j, "{z}/{x}/{y}.terrain?v={version}");
    tp_json_array_end(&j);
    const double b[4] = {q->src.lon_lo, q->src.lat_lo, q->src.lon_hi, q->src.lat_hi};
    tp_json_key(&j, "bounds");
    tp_json_array_begin(&j);
    for (int k = 0; k < 4; k++)
        tp_json_number(&j, q->r->has_bounds ? (k < 2 ? fmax(b[k], q->r->bounds[k])
                                                     : fmin(b[k], q->r->bounds[k]))
                                            : b[k]);
    tp_json_array_end(&j);
    tp_json_member_int(&j, "minzoom", 0);
    tp_json_member_int(&j, "maxzoom", q->max_zoom);
    tp_json_key(&j, "available");
    tp_json_array_begin(&j);
    for (int z = 0; z <= q->max_zoom; z++) {
        const level* l = &q->lv[z];
        tp_json_array_begin(&j);
        tp_json_object_begin(&j);
        tp_json_member_int(&j, "startX", l->x0);
        tp_json_member_int(&j, "startY", l->y0);
        tp_json_member_int(&j, "endX", l->x1);
        tp_json_member_int(&j, "endY", l->y1);
        tp_json_object_end(&j);
        tp_json_array_end(&j);
    }
    tp_json_array_end(&j);
    tp_json_key(&j, "terrapatch");
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "heights", q->r->ellipsoid ? "ellipsoid" : "geoid");
    tp_json_member_string(&j, "geoid_model",
                          q->src.geoid ? tp_geoid_name(q->src.geoid)
                                       : "none applied: the store's heights as stored (EGM96 for "
                                         "SRTM)");
    tp_json_member_string(&j, "source", q->r->path);
    tp_json_member_int(&j, "max_zoom", q->max_zoom);
    tp_json_member_int(&j, "lattice_cells", TP_QM_CELLS);
    tp_json_member_number(&j, "height_step_m", q->src.height_step_m);
    tp_json_member_string(&j, "error_measured_against",
                          "every full-resolution post of the store inside the tile and every "
                          "lattice post, decoded tile heights");
    tp_json_key(&j, "levels");
    tp_json_array_begin(&j);
    for (int z = 0; z <= q->max_zoom; z++) {
        size_t n, tris, bytes;
        double mx;
        level_stats(&q->lv[z], &n, &mx, &tris, &bytes);
        tp_json_object_begin(&j);
        tp_json_member_int(&j, "zoom", z);
        tp_json_member_number(&j, "geometric_error_m",
                              tp_qm_level_bound(z, q->max_zoom, q->r->max_error_m));
        tp_json_member_number(&j, "cesium_geometric_error_m", tp_qmesh_level_error_m(z));
        tp_json_member_number(&j, "max_measured_error_m", mx);
        tp_json_member_size(&j, "tiles", n);
        tp_json_member_size(&j, "triangles", tris);
        tp_json_member_size(&j, "bytes", bytes);
        tp_json_object_end(&j);
    }
    tp_json_array_end(&j);
    tp_json_object_end(&j);
    tp_json_object_end(&j);
    fputc('\n', a.f);
    return tp_atomic_commit(&a);
}

static int write_errors(qm_run* q)
{
    char p[4096];
    path_in(q, p, sizeof p, "errors.json");
    tp_atomic_file a;
    if (!tp_atomic_open(&a, p))
        return 0;
    fputs("{", a.f);
    int first = 1;
    for (int z = 0; z <= q->max_zoom; z++) {
        level* l = &q->lv[z];
        for (int y = l->y0; y <= l->y1; y++)
            for (int x = l->x0; x <= l->x1; x++) {
                fprintf(a.f, "%s\n  \"%d/%d/%d\": %.6f", first ? "" : ",", z, x, y,
                        rec_at(l, x, y)->measured_m);
                first = 0;
            }
    }
    fputs("\n}\n", a.f);
    return tp_atomic_commit(&a);
}

static void print_summary(qm_run* q, size_t pairs, double seconds)
{
    size_t tiles = 0, tris = 0, bytes = 0, built = q->total - q->done_before;
    for (int z = 0; z <= q->max_zoom; z++) {
        size_t n, t, b;
        double mx;
        level_stats(&q->lv[z], &n, &mx, &t, &b);
        tiles += n, tris += t, bytes += b;
    }
    const level* top = &q->lv[q->max_zoom];
    size_t n, t, b;
    double mx;
    level_stats((level*)top, &n, &mx, &t, &b);
    printf("wrote %s: %zu tiles, levels 0..%d, %zu triangles, %.2f MB (%.0f bytes a tile); %zu "
           "built in %.1f s (%.1f tiles/s), %zu kept; level %d: bound %.3f m, measured error "
           "max %.3f m; %zu neighbour pairs share their edge vertices\n",
           q->r->out_dir, tiles, q->max_zoom, tris, bytes / 1e6, tiles ? (double)bytes / tiles : 0.0,
           built, seconds, seconds > 0 ? built / seconds : 0.0, q->done_before, q->max_zoom,
           tp_qm_level_bound(q->max_zoom, q->max_zoom, q->r->max_error_m), mx, pairs);
}

int tp_export_qm(const tp_qm_request* r)
{
    qm_run* q = calloc(1, sizeof *q);
    if (!q) {
        tp_cli_error("out of memory");
        return TP_EXIT_FAILURE;
    }
    q->r = r;
    int code = TP_EXIT_FAILURE;
    tp_ground_options go = {.cmd = "export", .dem = r->dem};
    if ((code = tp_ground_open(r->path, &go, &q->src.ground)) != TP_EXIT_OK)
        goto done;
    code = TP_EXIT_FAILURE;
    const tp_store_scene* sc = tp_ground_scene(q->src.ground);
    q->src.georef = sc->georef;
    const tp_tree_geometry* g = tp_tree_get_geometry(sc->tree);
    q->src.width = g->src_width;
    q->src.height = g->src_height;
    q->src.interp_max_m = 400;
    if (!tp_georef_has_geo(sc->georef)) {
        fail_line(q, "has no geographic position (no CRS): Cesium tiles need one");
        goto done;
    }
    if (!extent(q)) {
        fail_line(q, "its extent has no WGS84 position");
        goto done;
    }
    tp_error err;
    if (r->ellipsoid && tp_geoid_open(&q->src.geoid, &err) != TP_OK) {
        fail_line(q, err.message);
        goto done;
    }
    q->max_zoom = r->max_zoom >= 0 ? r->max_zoom : default_zoom(q);
    if (q->max_zoom > QM_MAX_ZOOM) {
        tp_cli_error("--max-zoom %d: at most %d", q->max_zoom, QM_MAX_ZOOM);
        code = TP_EXIT_USAGE;
        goto done;
    }
    if (!height_step(q) || !plan(q))
        goto done;
    snprintf(q->options, sizeof q->options,
             "terrapatch quantized-mesh 2 source=%s heights=%s max_zoom=%d bounds=%.9g,%.9g,"
             "%.9g,%.9g max_error=%.9g lattice=%d step=%.9g",
             r->path, r->ellipsoid ? "ellipsoid" : "geoid", q->max_zoom,
             r->has_bounds ? r->bounds[0] : -180.0, r->has_bounds ? r->bounds[1] : -90.0,
             r->has_bounds ? r->bounds[2] : 180.0, r->has_bounds ? r->bounds[3] : 90.0,
             r->max_error_m, TP_QM_CELLS, q->src.height_step_m);
    if (!resume(q))
        goto done;
    if (q->done_before)
        tp_cli_note("%s: %zu of %zu tiles already written by an earlier run: kept", r->out_dir,
                    q->done_before, q->total);
    double seconds = 0;
    if ((code = build_all(q, &seconds)) != TP_EXIT_OK)
        goto done;
    size_t pairs = 0;
    code = TP_EXIT_FAILURE;
    if (!check_edges(q, &pairs) || !write_layer(q) || !write_errors(q))
        goto done;
    print_summary(q, pairs, seconds);
    code = TP_EXIT_OK;
done:
    for (int z = 0; z <= QM_MAX_ZOOM; z++)
        free(q->lv[z].tiles);
    tp_geoid_close(q->src.geoid);
    tp_ground_destroy(q->src.ground);
    free(q);
    return code;
}
