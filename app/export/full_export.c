/* full_export.c - export --full streamed, a piece at a time (see full_export.h). */
#include "full_export.h"
#include "clock.h"

#include "cli.h"
#include "memory.h"
#include "progress.h"
#include "store_mesh.h"
#include "store_scene.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Bytes of memory a piece takes per sample while it is built and handed to VTK (our arrays
 * ~115, VTK's copy ~125, its 32-bit id buffers and compressor a little more); measured with
 * /usr/bin/time -v (docs/PERFORMANCE.md, "export --full"). */
#define BYTES_PER_PIECE_SAMPLE 260
/* What the process needs besides a piece (libraries, GDAL's block cache, a leaf). */
#define FULL_EXPORT_BASE_BYTES ((uint64_t)160 << 20)
/* The smallest piece worth making: below it the room is too small to export anything. */
#define MIN_PIECE_SAMPLES ((size_t)1 << 14)

typedef struct full_export {
    const tp_full_export_request* r;
    /* the grid */
    int width, height; /* samples */
    double gt[6];
    int north_up;
    const char* crs_wkt;
    int epsg;
    tp_georef* georef;
    double origin[3];
    int lod;         /* the level the mesh's triangles are: n */
    int patch_shift; /* cell (x, y) is in patch (x >> shift, y >> shift) */
    int patch_cols;  /* patch id = row * patch_cols + col (a DEM); a store: leaf id */
    /* the pieces: blocks of piece_cw x piece_ch cells */
    int piece_cw, piece_ch, pieces_x, pieces_y;
    /* a DEM */
    tp_mosaic* mosaic;
    /* a store */
    tp_store_scene sc;
    int have_store;
    const tp_tree_geometry* g;
    const tp_node_meta* metas;
    uint16_t* block; /* one leaf */
    size_t block_words;
    /* one piece's samples and mesh */
    float* z;
    uint8_t* filled;
    int32_t* index;
    double *xyz, *elev, *err;
    uint8_t *vf, *lodv;
    int32_t* patch;
    uint64_t* tri;
    size_t piece_samples;
    /* totals */
    size_t points, triangles;
    tp_progress progress;
    size_t steps_done, steps;
} full_export;

void tp_export_zone_of_crs(const char* crs_wkt, int* epsg, char zone[TP_ZONE_TEXT_SIZE])
{
    tp_crs_info ci;
    memset(&ci, 0, sizeof ci);
    ci.utm_zone = -1;
    tp_crs_describe(crs_wkt ? crs_wkt : "", &ci, NULL);
    *epsg = ci.epsg;
    zone[0] = '\0';
    if (ci.utm_zone >= 0)
        tp_zone_format(ci.utm_zone, ci.northp, TP_ZONE_STYLE_SHORT, zone, TP_ZONE_TEXT_SIZE, NULL);
}

int tp_full_export_streams(const char* path, int is_store, const tp_scene_options* scene,
                           tp_mesh_format format)
{
    if (format != TP_MESH_VTP)
        return 0;
    if (is_store)
        return 1;
    return !scene->image_given && !tp_is_heightmap_image(path) && scene->fit != TP_FIT_RESAMPLE;
}

static int fail(full_export* x, const char* what)
{
    if (strstr(what, x->r->path) || strstr(what, x->r->out)) /* io's messages name the file */
        tp_cli_error("%s", what);
    else
        tp_cli_error("%s: %s", x->r->path, what);
    return TP_EXIT_FAILURE;
}

/* ---- the sources ---- */

/* A DEM: its render grid through the mosaic reader, with the scene's options. */
static int open_dem(full_export* x)
{
    const tp_scene_options* o = x->r->scene;
    const int fmax = o->grid.fill_max_px;
    tp_mosaic_options mo = {
        .crs = o->grid.crs,
        .resampling = o->grid.resampling,
        .memory_mb = 256,
        .fill_max = fmax == 0  ? TP_FILL_MAX_ANY
                    : fmax < 0 ? 0
                               : fmax,
        .fill_from = o->grid.fill_from,
        .z_unit = o->z_unit,
    };
    tp_error err;
    const char* paths[1] = {x->r->path};
    if (tp_mosaic_open(paths, 1, &mo, &x->mosaic, &err) != TP_OK)
        return fail(x, err.message);
    tp_mosaic_info mi;
    tp_mosaic_get_info(x->mosaic, &mi);
    for (const char* w = mi.notes; w && *w;) { /* the unit and nodata warnings, as a view's */
        const char* nl = strchr(w, '\n');
        int len = nl ? (int)(nl - w) : (int)strlen(w);
        if (!strncmp(w, "warning: ", 9))
            tp_cli_error("%.*s", len, w);
        w += len + (nl ? 1 : 0);
    }
    x->width = mi.width;
    x->height = mi.height;
    memcpy(x->gt, mi.geotransform, sizeof x->gt);
    x->crs_wkt = mi.crs_wkt;
    if (tp_georef_create(mi.crs_wkt, mi.geotransform, &x->georef, &err) != TP_OK)
        return fail(x, err.message);
    int cells = o->patch_size - 1;
    x->lod = 0;
    while ((1 << x->lod) < cells)
        x->lod++;
    x->patch_shift = x->lod;
    x->patch_cols = (int)(((int64_t)x->width - 1 + cells - 1) / cells);
    return TP_EXIT_OK;
}

/* A store: its leaves, each read once a pass. */
static int open_store(full_export* x)
{
    if (tp_store_scene_open(x->r->path, &x->sc) != TP_EXIT_OK)
        return TP_EXIT_FAILURE;
    x->have_store = 1;
    x->g = tp_tree_get_geometry(x->sc.tree);
    size_t count;
    x->metas = tp_store_metas(x->sc.store, &count);
    x->width = x->g->src_width;
    x->height = x->g->src_height;
    memcpy(x->gt, x->sc.info.header.geotransform, sizeof x->gt);
    x->crs_wkt = x->sc.info.header.crs_wkt;
    x->georef = NULL; /* the scene's */
    x->lod = x->patch_shift = x->g->n;
    x->block_words = tp_tree_block_words(x->g->n);
    if (!(x->block = malloc(x->block_words * sizeof *x->block)))
        return fail(x, "out of memory");
    return TP_EXIT_OK;
}

static const tp_georef* georef_of(const full_export* x)
{
    return x->have_store ? x->sc.georef : x->georef;
}

/* Heights (NaN: none) and filled marks of samples [x0, x0 + w) x [y0, y0 + h) into x->z and
 * x->filled (w * h each, row-major). A failure's message (naming the file) is in *err. */
static tp_status read_block(full_export* x, int x0, int y0, int w, int h, tp_error* err)
{
    if (x->mosaic) /* whole rows: the pieces are bands */
        return tp_mosaic_read_rows_filled(x->mosaic, y0, h, x->z, (size_t)w * h, x->filled, err);
    for (size_t i = 0; i < (size_t)w * h; i++) {
        x->z[i] = NAN;
        x->filled[i] = 0;
    }
    const int n = x->g->n, side = 1 << n;
    int c1 = (x0 + w - 1) >> n, r1 = (y0 + h - 1) >> n;
    c1 = c1 < x->g->cols ? c1 : x->g->cols - 1;
    r1 = r1 < x->g->rows ? r1 : x->g->rows - 1;
    for (int r = y0 >> n; r <= r1; r++)
        for (int c = x0 >> n; c <= c1; c++) {
            int64_t leaf = tp_tree_node_id(x->g, 0, c, r);
            const tp_node_meta* meta = &x->metas[leaf];
            if (!(meta->flags & TP_NODE_HAS_DRAWN))
                continue;
            tp_status st = tp_store_read_node(x->sc.store, leaf, x->block, x->block_words, err);
            if (st != TP_OK)
                return st;
            /* the leaf holds samples (c << n) .. (c << n) + side, edges shared with the next */
            int ya = r << n, xa = c << n;
            int jy0 = ya > y0 ? ya : y0, jy1 = ya + side < y0 + h - 1 ? ya + side : y0 + h - 1;
            int ix0 = xa > x0 ? xa : x0, ix1 = xa + side < x0 + w - 1 ? xa + side : x0 + w - 1;
            for (int yy = jy0; yy <= jy1; yy++)
                for (int xx = ix0; xx <= ix1; xx++) {
                    int f;
                    double v = tp_leaf_block_sample(
                        x->block, meta, n, x->sc.info.header.height_step_m, xx - xa, yy - ya, &f);
                    size_t k = (size_t)(yy - y0) * w + (xx - x0);
                    x->z[k] = (float)v;
                    x->filled[k] = (uint8_t)f;
                }
        }
    return TP_OK;
}

/* ---- pieces ---- */

typedef struct piece_rect {
    int x0, y0, w, h; /* samples */
} piece_rect;

static piece_rect rect_of(const full_export* x, size_t piece)
{
    int px = (int)(piece % (size_t)x->pieces_x), py = (int)(piece / (size_t)x->pieces_x);
    piece_rect r;
    r.x0 = px * x->piece_cw;
    r.y0 = py * x->piece_ch;
    int x1 = r.x0 + x->piece_cw < x->width - 1 ? r.x0 + x->piece_cw : x->width - 1;
    int y1 = r.y0 + x->piece_ch < x->height - 1 ? r.y0 + x->piece_ch : x->height - 1;
    r.w = x1 - r.x0 + 1;
    r.h = y1 - r.y0 + 1;
    return r;
}

/* Whether cell (i, j) of the block (w wide) has four drawn samples. */
static int full_cell(const float* z, int w, int i, int j)
{
    const float* a = z + (size_t)j * w + i;
    return !isnan(a[0]) && !isnan(a[1]) && !isnan(a[w]) && !isnan(a[w + 1]);
}

/* Numbers the block's points (samples of a full cell) in x->index (-1: none); returns the count
 * and the full cells' count in *cells. */
static size_t number_points(full_export* x, const piece_rect* r, size_t* cells)
{
    size_t samples = (size_t)r->w * r->h;
    for (size_t i = 0; i < samples; i++)
        x->index[i] = -1;
    *cells = 0;
    for (int j = 0; j + 1 < r->h; j++)
        for (int i = 0; i + 1 < r->w; i++)
            if (full_cell(x->z, r->w, i, j)) {
                size_t k = (size_t)j * r->w + i;
                x->index[k] = x->index[k + 1] = x->index[k + r->w] = x->index[k + r->w + 1] = 0;
                ++*cells;
            }
    size_t points = 0;
    for (size_t i = 0; i < samples; i++)
        if (x->index[i] == 0)
            x->index[i] = (int32_t)points++;
    return points;
}

static void step_done(full_export* x)
{
    x->steps_done++;
    tp_progress_update(&x->progress, (double)x->steps_done, (double)x->steps, -1);
}

/* Pass 1: the points and triangles the file will hold. */
static int count_all(full_export* x)
{
    size_t pieces = (size_t)x->pieces_x * x->pieces_y;
    for (size_t p = 0; p < pieces; p++) {
        piece_rect r = rect_of(x, p);
        tp_error err;
        if (read_block(x, r.x0, r.y0, r.w, r.h, &err) != TP_OK)
            return fail(x, err.message);
        size_t cells;
        x->points += number_points(x, &r, &cells);
        x->triangles += 2 * cells;
        if (tp_interrupted())
            return tp_cli_interrupted();
        step_done(x);
    }
    return TP_EXIT_OK;
}

/* Pass 2: piece p as tp_mesh_write_pieces asks for it. */
static tp_status make_piece(void* user, size_t p, tp_mesh* m, tp_error* err)
{
    full_export* x = user;
    if (tp_interrupted())
        return tp_error_set(err, TP_ERR_IO, "%s: interrupted", x->r->out);
    piece_rect r = rect_of(x, p);
    tp_status st = read_block(x, r.x0, r.y0, r.w, r.h, err);
    if (st != TP_OK)
        return st;
    size_t cells;
    size_t points = number_points(x, &r, &cells);
    const tp_georef* gr = georef_of(x);
    size_t at = 0;
    for (int j = 0; j < r.h; j++)
        for (int i = 0; i < r.w; i++) {
            size_t k = (size_t)j * r.w + i;
            if (x->index[k] < 0)
                continue;
            double e, nn;
            tp_georef_grid_to_proj(gr, r.x0 + i, r.y0 + j, &e, &nn);
            x->xyz[3 * at + 0] = e - x->origin[0];
            x->xyz[3 * at + 1] = nn - x->origin[1];
            x->xyz[3 * at + 2] = x->z[k] - x->origin[2];
            x->elev[at] = x->z[k];
            x->vf[at] = x->filled[k];
            at++;
        }
    /* the strips' split (tp_core.h): diagonal from (c+1, r) to (c, r+1); corners in the order
     * of the DEM path's mesh: counter-clockwise seen from above in (east, north) for a
     * north-up grid, reversed for any other */
    size_t t = 0;
    for (int j = 0; j + 1 < r.h; j++)
        for (int i = 0; i + 1 < r.w; i++) {
            if (!full_cell(x->z, r.w, i, j))
                continue;
            size_t k = (size_t)j * r.w + i;
            uint64_t a = (uint64_t)x->index[k], b = (uint64_t)x->index[k + 1],
                     c = (uint64_t)x->index[k + r.w], d = (uint64_t)x->index[k + r.w + 1];
            uint64_t tri[6] = {a, c, b, b, c, d};
            if (!x->north_up) {
                tri[1] = b, tri[2] = c;
                tri[4] = d, tri[5] = c;
            }
            memcpy(x->tri + 3 * t, tri, sizeof tri);
            int cx = r.x0 + i, cy = r.y0 + j;
            int32_t id = x->have_store ? (int32_t)tp_tree_node_id(x->g, 0, cx >> x->patch_shift,
                                                                  cy >> x->patch_shift)
                                       : (int32_t)((int64_t)(cy >> x->patch_shift) * x->patch_cols +
                                                   (cx >> x->patch_shift));
            for (int q = 0; q < 2; q++, t++) {
                x->patch[t] = id;
                x->lodv[t] = (uint8_t)x->lod;
                x->err[t] = 0;
            }
        }
    m->point_count = points;
    m->xyz = x->xyz;
    m->elevation_m = x->elev;
    m->void_filled = x->vf;
    m->triangle_count = t;
    m->triangles = x->tri;
    m->patch_id = x->patch;
    m->lod = x->lodv;
    m->max_error_m = x->err;
    step_done(x);
    return TP_OK;
}

/* ---- the plan ---- */

/* The samples a piece may hold: TP_FULL_EXPORT_PIECE_SAMPLES, fewer when the memory left
 * (TP_MEMORY_LIMIT, ulimit -v, the cgroup, MemAvailable) is smaller; 0 after one line when
 * not even a small piece fits. */
static size_t piece_budget(full_export* x)
{
    size_t want = x->r->piece_samples ? x->r->piece_samples : TP_FULL_EXPORT_PIECE_SAMPLES;
    tp_memory_room room;
    tp_memory_room_now(&room);
    if (room.bytes == UINT64_MAX)
        return want;
    uint64_t spare = room.bytes > FULL_EXPORT_BASE_BYTES ? room.bytes - FULL_EXPORT_BASE_BYTES : 0;
    uint64_t fit = spare / BYTES_PER_PIECE_SAMPLE;
    if (fit < MIN_PIECE_SAMPLES) {
        tp_cli_error("%s: export --full needs about %.0f MiB, %.0f MiB available (%s)", x->r->path,
                     (FULL_EXPORT_BASE_BYTES + (double)MIN_PIECE_SAMPLES * BYTES_PER_PIECE_SAMPLE) /
                         1048576.0,
                     room.bytes / 1048576.0, room.bound);
        return 0;
    }
    return fit < want ? (size_t)fit : want;
}

/* Pieces of about budget samples: bands of whole rows for a DEM (the mosaic reads rows), blocks
 * of whole leaves for a store (each leaf read once a pass). */
static void plan_pieces(full_export* x, size_t budget)
{
    int cw = x->width - 1, ch = x->height - 1; /* cells */
    if (x->have_store) {
        int leaf = 1 << x->g->n;
        int side = (int)(sqrt((double)budget) / leaf);
        side = side < 1 ? 1 : side;
        x->piece_cw = x->piece_ch = side * leaf;
    } else {
        x->piece_cw = cw;
        size_t rows = budget / (size_t)x->width;
        x->piece_ch = (int)(rows < 1 ? 1 : rows > (size_t)ch ? (size_t)ch : rows);
    }
    x->pieces_x = (cw + x->piece_cw - 1) / x->piece_cw;
    x->pieces_y = (ch + x->piece_ch - 1) / x->piece_ch;
}

static int allocate(full_export* x)
{
    size_t s = (size_t)(x->piece_cw + 1) * (size_t)(x->piece_ch + 1);
    size_t tris = 2 * (size_t)x->piece_cw * x->piece_ch;
    x->z = malloc(s * sizeof *x->z);
    x->filled = malloc(s);
    x->index = malloc(s * sizeof *x->index);
    x->xyz = malloc(3 * s * sizeof *x->xyz);
    x->elev = malloc(s * sizeof *x->elev);
    x->vf = malloc(s);
    x->tri = malloc(3 * tris * sizeof *x->tri);
    x->patch = malloc(tris * sizeof *x->patch);
    x->lodv = malloc(tris);
    x->err = malloc(tris * sizeof *x->err);
    return x->z && x->filled && x->index && x->xyz && x->elev && x->vf && x->tri && x->patch &&
           x->lodv && x->err;
}

static void release(full_export* x)
{
    free(x->z);
    free(x->filled);
    free(x->index);
    free(x->xyz);
    free(x->elev);
    free(x->vf);
    free(x->tri);
    free(x->patch);
    free(x->lodv);
    free(x->err);
    free(x->block);
    tp_mosaic_close(x->mosaic);
    tp_georef_destroy(x->georef);
    if (x->have_store)
        tp_store_scene_close(&x->sc);
}

int tp_export_full_streamed(const tp_full_export_request* r)
{
    full_export x;
    memset(&x, 0, sizeof x);
    x.r = r;
    double t0 = tp_clock_s();
    int code = r->is_store ? open_store(&x) : open_dem(&x);
    if (code != TP_EXIT_OK)
        goto done;
    if (x.width < 2 || x.height < 2) {
        code = fail(&x, "nothing to export (a grid under 2 x 2 samples has no cell)");
        goto done;
    }
    x.north_up = x.gt[1] * x.gt[5] < 0;
    if (r->origin_local) {
        double e, nn;
        tp_georef_grid_to_proj(georef_of(&x), 0, 0, &e, &nn);
        x.origin[0] = floor(e / 1000) * 1000;
        x.origin[1] = floor(nn / 1000) * 1000;
    }
    size_t budget = piece_budget(&x);
    if (!budget) {
        code = TP_EXIT_FAILURE;
        goto done;
    }
    plan_pieces(&x, budget);
    if (!allocate(&x)) {
        code = fail(&x, "out of memory for one piece of the mesh");
        goto done;
    }
    size_t pieces = (size_t)x.pieces_x * x.pieces_y;
    x.steps = pieces;
    /* one line a tenth, or a bar on a terminal, a stage a pass: only when there is more than
     * one piece */
    tp_progress_start(&x.progress, pieces > 1, "export", "counting");
    if ((code = count_all(&x)) != TP_EXIT_OK)
        goto done;
    x.steps_done = 0;
    tp_progress_start(&x.progress, pieces > 1, "export", "writing");
    if (x.triangles == 0) {
        code = fail(&x, "nothing to export (no cell has four drawn samples)");
        goto done;
    }
    char zone[TP_ZONE_TEXT_SIZE];
    tp_export_zone_of_crs(x.crs_wkt, &x.epsg, zone);
    tp_mesh fields = {
        .crs_wkt = x.crs_wkt,
        .epsg = x.epsg,
        .utm_zone = zone,
        .source_file = r->path,
        .camera = "",
        .lod_params = "mode=full",
        .program_version = "terrapatch " TP_VERSION,
        .origin = {x.origin[0], x.origin[1], x.origin[2]},
        .void_filled_note = x.have_store ? "from the store's filled bits: 1 where the build "
                                           "filled an interior void"
                                         : NULL,
    };
    tp_error err;
    if (tp_mesh_write_pieces(r->out, &fields, x.triangles, pieces, make_piece, &x, &err) != TP_OK) {
        if (tp_interrupted())
            code = tp_cli_interrupted();
        else
            code = fail(&x, err.message);
        goto done;
    }
    printf("wrote %s: %zu points, %zu triangles (100.00%% of the %zu of the full mesh), "
           "measured error (against the grid's own samples) max 0.000 m, RMS 0.000 m; %zu "
           "piece%s of at most %dx%d cells (points where pieces meet repeated), %.1f s, peak "
           "%.0f MiB\n",
           r->out, x.points, x.triangles, x.triangles, pieces, pieces == 1 ? "" : "s", x.piece_cw,
           x.piece_ch, tp_clock_s() - t0, tp_memory_peak_rss() / 1048576.0);
done:
    release(&x);
    return code;
}
