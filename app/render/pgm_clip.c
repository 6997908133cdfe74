/* pgm_clip.c - Persistent Grid Mapping over a store: the elevation clipmap on the GPU (see
 * pgm_clip.h). */
#define _POSIX_C_SOURCE 200112L
#include "pgm_clip.h"
#include "clock.h"

#include <epoxy/gl.h>

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The synchronous path's buffer: 1 MiB of posts, read and uploaded a band of rows at a time. */
#define FILL_BUFFER_POSTS ((size_t)1 << 18)

typedef struct pgm_job pgm_job;
static void job_free(pgm_job* j);

/* A decoded node in the cache (direct-mapped by id). */
typedef struct cached {
    int64_t node; /* -1: empty */
    float* z;     /* (2^n+1)^2 heights, NaN where not drawn */
} cached;

struct tp_pgm_clipmap {
    const tp_store* store;
    tp_store_info info;
    const tp_tree_geometry* g;
    const tp_node_meta* metas;
    tp_pgm_pyramid shape;
    int w;
    int origin[TP_PGM_MAX_LEVELS][2];
    int filled; /* the windows hold their posts (after the first update) */
    GLuint tex;
    size_t gpu_bytes;
    size_t side, samples; /* 2^n + 1 and its square */
    uint16_t* raw;        /* one node's stored samples */
    cached* cache;
    size_t cache_count;
    char failed[512]; /* the filler's first read failure */
    /* tp_pgm_clipmap_set_async: the loader thread fills one job at a time */
    int async, quit;
    pthread_t thread;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    pgm_job* pending; /* handed to the loader (under mu) */
    pgm_job* ready;   /* filled, to upload (under mu) */
};

/* Clears the GL errors earlier calls left (bounded: a lost context may report one forever), so
 * that glGetError after the calls it checks reports theirs. */
static void drain_gl_errors(void)
{
    for (int k = 0; k < 64 && glGetError() != GL_NO_ERROR; k++)
        ;
}

/* The shape tp_pgm_pyramid_build gives a width x height grid, without heights. */
static void make_shape(tp_pgm_clipmap* c)
{
    tp_pgm_pyramid* p = &c->shape;
    int w = c->g->src_width, h = c->g->src_height, levels = 0;
    for (;;) {
        p->width[levels] = w;
        p->height[levels] = h;
        levels++;
        if ((w <= 2 && h <= 2) || levels == TP_PGM_MAX_LEVELS)
            break;
        w = w / 2 + 1;
        h = h / 2 + 1;
    }
    p->levels = levels;
    memcpy(p->geotransform, c->info.header.geotransform, sizeof p->geotransform);
}

/* The drawn range over the roots' areas (every drawn sample lies in one). 0 if none. */
static int height_range(tp_pgm_clipmap* c)
{
    const tp_tree_geometry* g = c->g;
    int64_t* roots = malloc((size_t)g->root_count * sizeof *roots);
    if (!roots)
        return 0;
    tp_tree_roots(g, roots, (size_t)g->root_count);
    long long lo = 0, hi = 0;
    int any = 0;
    for (int64_t k = 0; k < g->root_count; k++) {
        const tp_node_meta* m = &c->metas[roots[k]];
        if (!(m->flags & TP_NODE_HAS_DRAWN))
            continue;
        lo = any && lo < m->area_qmin ? lo : m->area_qmin;
        hi = any && hi > m->area_qmax ? hi : m->area_qmax;
        any = 1;
    }
    free(roots);
    double step = c->info.header.height_step_m;
    c->shape.min_m = (double)lo * step;
    c->shape.max_m = (double)hi * step;
    return any;
}

tp_pgm_clipmap* tp_pgm_clipmap_create(const tp_store* store, int w, tp_error* err)
{
    if (w == 0)
        w = TP_PGM_CLIP_DEFAULT_WINDOW;
    if (w < 16 || w > 8192 || (w & (w - 1))) {
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "PGM clipmap window %d: expected a power of two, 16 .. 8192", w);
        return NULL;
    }
    tp_pgm_clipmap* c = calloc(1, sizeof *c);
    if (!c) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    c->store = store;
    c->w = w;
    tp_store_get_info(store, &c->info);
    c->g = &c->info.header.geometry;
    size_t count = 0;
    c->metas = tp_store_metas(store, &count);
    make_shape(c);
    int need = tp_pgm_clip_min_window(c->g->src_width, c->g->src_height);
    if (w < need) { /* the coarsest window must hold its level whole (pgm_clip.h) */
        tp_error_set(
            err, TP_ERR_INVALID_ARG,
            "PGM clipmap: the store's %d x %d posts keep %d x %d at the coarsest of its %d "
            "levels, more than a window of %d posts holds: --pgm-window %d or more",
            c->g->src_width, c->g->src_height, c->shape.width[c->shape.levels - 1],
            c->shape.height[c->shape.levels - 1], c->shape.levels, w, need);
        free(c);
        return NULL;
    }
    if (!height_range(c)) {
        tp_error_set(err, TP_ERR_BAD_DATA,
                     "PGM: the store has no drawn height (or memory ran out)");
        free(c);
        return NULL;
    }
    c->side = ((size_t)1 << c->g->n) + 1;
    c->samples = c->side * c->side;
    /* about 16 MiB of decoded nodes, at least 64 of them */
    c->cache_count = ((size_t)16 << 20) / (c->samples * sizeof(float));
    c->cache_count = c->cache_count < 64 ? 64 : c->cache_count;
    c->raw = malloc(c->samples * sizeof *c->raw);
    c->cache = calloc(c->cache_count, sizeof *c->cache);
    if (!c->raw || !c->cache) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        tp_pgm_clipmap_destroy(c);
        return NULL;
    }
    for (size_t k = 0; k < c->cache_count; k++)
        c->cache[k].node = -1;
    GLint max = 0, layers = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max);
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &layers);
    if (w > max || c->shape.levels > layers) {
        tp_error_set(err, TP_ERR_BACKEND,
                     "PGM clipmap: %d levels of %d x %d texels; this GPU allows %d x %d and %d "
                     "layers (a smaller window: --pgm-window)",
                     c->shape.levels, w, w, (int)max, (int)max, (int)layers);
        tp_pgm_clipmap_destroy(c);
        return NULL;
    }
    drain_gl_errors(); /* what another module left would read as this allocation's */
    glGenTextures(1, &c->tex);
    glBindTexture(GL_TEXTURE_2D_ARRAY, c->tex);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_R32F, w, w, c->shape.levels, 0, GL_RED, GL_FLOAT, NULL);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAX_LEVEL, 0);
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        tp_error_set(err, TP_ERR_BACKEND,
                     "PGM clipmap: allocating %d layers of %d x %d R32F failed (GL "
                     "error 0x%x)",
                     c->shape.levels, w, w, (unsigned)e);
        tp_pgm_clipmap_destroy(c);
        return NULL;
    }
    c->gpu_bytes = (size_t)c->shape.levels * (size_t)w * (size_t)w * 4;
    return c;
}

void tp_pgm_clipmap_destroy(tp_pgm_clipmap* c)
{
    if (!c)
        return;
    if (c->async) {
        pthread_mutex_lock(&c->mu);
        c->quit = 1;
        pthread_cond_signal(&c->cv);
        pthread_mutex_unlock(&c->mu);
        pthread_join(c->thread, NULL);
        pthread_cond_destroy(&c->cv);
        pthread_mutex_destroy(&c->mu);
        job_free(c->pending);
        job_free(c->ready);
    }
    if (c->tex)
        glDeleteTextures(1, &c->tex);
    for (size_t k = 0; c->cache && k < c->cache_count; k++)
        free(c->cache[k].z);
    free(c->cache);
    free(c->raw);
    free(c);
}

const tp_pgm_pyramid* tp_pgm_clipmap_shape(const tp_pgm_clipmap* c)
{
    return &c->shape;
}

int tp_pgm_clipmap_window(const tp_pgm_clipmap* c)
{
    return c->w;
}

void tp_pgm_clipmap_origins(const tp_pgm_clipmap* c, int* origin)
{
    for (int l = 0; l < c->shape.levels; l++)
        origin[2 * l] = c->origin[l][0], origin[2 * l + 1] = c->origin[l][1];
}

unsigned tp_pgm_clipmap_texture(const tp_pgm_clipmap* c)
{
    return c->tex;
}

size_t tp_pgm_clipmap_gpu_bytes(const tp_pgm_clipmap* c)
{
    return c->gpu_bytes;
}

const tp_store* tp_pgm_clipmap_store(const tp_pgm_clipmap* c)
{
    return c->store;
}

int tp_pgm_clipmap_filled(const tp_pgm_clipmap* c)
{
    return c->filled;
}

/* The decoded heights of node, read on a miss; NULL when the read fails (c->failed says why,
 * the first time). */
static const float* node_heights(tp_pgm_clipmap* c, int64_t node, tp_pgm_clip_stats* st)
{
    cached* e = &c->cache[(size_t)node % c->cache_count];
    if (e->node == node)
        return e->z;
    if (!e->z && !(e->z = malloc(c->samples * sizeof *e->z)))
        return NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    st->node_reads++;
    if (tp_store_read_node(c->store, node, c->raw, c->samples, &err) != TP_OK) {
        if (!c->failed[0])
            snprintf(c->failed, sizeof c->failed, "%.500s", err.message);
        e->node = -1;
        return NULL;
    }
    double step = c->info.header.height_step_m, qmin = c->metas[node].qmin;
    for (size_t k = 0; k < c->samples; k++)
        e->z[k] = c->raw[k] == TP_TREE_NO_HEIGHT ? NAN : (float)((c->raw[k] + qmin) * step);
    e->node = node;
    return e->z;
}

/* One piece of a job: level l's posts [x0, x1) x [y0, y1), not wrapping (one texel block), at
 * z + at in the job's buffer. */
typedef struct piece {
    int l, x0, y0, x1, y1;
    size_t at;
} piece;

/* The posts the windows gain when they move to target: filled (by the loader thread, or at
 * once), then uploaded together with the new origins (so the windows the shader reads always
 * hold their posts). */
struct pgm_job {
    int target[TP_PGM_MAX_LEVELS][2];
    piece* pieces;
    int count, cap;
    float* z;
    size_t posts;
    double fill_ms;
    size_t node_reads;
    char failed[512];
};

static void job_free(pgm_job* j)
{
    if (!j)
        return;
    free(j->pieces);
    free(j->z);
    free(j);
}

static int job_add(pgm_job* j, int l, int x0, int y0, int x1, int y1)
{
    if (j->count == j->cap) {
        int cap = j->cap ? 2 * j->cap : 16;
        piece* p = realloc(j->pieces, (size_t)cap * sizeof *p);
        if (!p)
            return 0;
        j->pieces = p, j->cap = cap;
    }
    j->pieces[j->count++] = (piece){l, x0, y0, x1, y1, j->posts};
    j->posts += (size_t)(x1 - x0) * (size_t)(y1 - y0);
    return 1;
}

/* The job that moves every window to centre on (x, y), without its buffer; NULL when nothing
 * moves (*oom set when memory ran out). */
static pgm_job* make_job(const tp_pgm_clipmap* c, double x, double y, int* oom)
{
    const int w = c->w;
    *oom = 0;
    pgm_job* j = calloc(1, sizeof *j);
    if (!j) {
        *oom = 1;
        return NULL;
    }
    int moved = 0;
    for (int l = 0; l < c->shape.levels; l++) {
        int pw = c->shape.width[l], ph = c->shape.height[l];
        int ox = tp_pgm_clip_origin(ldexp(x, -l), pw, w);
        int oy = tp_pgm_clip_origin(ldexp(y, -l), ph, w);
        j->target[l][0] = ox, j->target[l][1] = oy;
        tp_pgm_rect r[2];
        int n = tp_pgm_clip_update(w, c->filled, c->origin[l][0], c->origin[l][1], ox, oy, r);
        moved |= n > 0;
        for (int k = 0; k < n; k++) {
            /* only posts on the terrain (a level smaller than the window holds fewer) */
            int x0 = r[k].x0 > 0 ? r[k].x0 : 0, y0 = r[k].y0 > 0 ? r[k].y0 : 0;
            int x1 = r[k].x1 < pw ? r[k].x1 : pw, y1 = r[k].y1 < ph ? r[k].y1 : ph;
            /* split where the texels wrap */
            for (int ya = y0; ya < y1;) {
                int yb = (ya / w + 1) * w;
                yb = yb < y1 ? yb : y1;
                for (int xa = x0; xa < x1;) {
                    int xb = (xa / w + 1) * w;
                    xb = xb < x1 ? xb : x1;
                    if (!job_add(j, l, xa, ya, xb, yb)) {
                        *oom = 1;
                        job_free(j);
                        return NULL;
                    }
                    xa = xb;
                }
                ya = yb;
            }
        }
    }
    if (!moved) {
        job_free(j);
        return NULL;
    }
    return j; /* its buffer, z, is the caller's to make (job_buffer) or not */
}

/* The job's whole buffer (the loader fills it at once); 0 when memory runs out. */
static int job_buffer(pgm_job* j)
{
    return !j->posts || (j->z = malloc(j->posts * sizeof *j->z)) != NULL;
}

/* Reads piece p's posts from the store into out (row-major; the node cache is the filler's:
 * the loader thread's when there is one, else the render thread's). */
static void fill_piece(tp_pgm_clipmap* c, const piece* p, float* out, tp_pgm_clip_stats* st)
{
    const tp_tree_geometry* g = c->g;
    int l = p->l, nx = p->x1 - p->x0;
    int64_t last = -1;
    const float* z = NULL;
    for (int jy = p->y0; jy < p->y1; jy++) {
        long long yl = (long long)jy << l;
        int y = (int)(yl < g->src_height - 1 ? yl : g->src_height - 1);
        float* row = out + (size_t)(jy - p->y0) * nx;
        for (int i = p->x0; i < p->x1; i++) {
            long long xl = (long long)i << l;
            int x = (int)(xl < g->src_width - 1 ? xl : g->src_width - 1);
            size_t sample;
            int64_t node = tp_pgm_store_post(g, l, x, y, &sample);
            if (node != last) {
                z = node_heights(c, node, st);
                last = node;
            }
            float h = z ? z[sample] : NAN;
            row[i - p->x0] = isnan(h) ? TP_PGM_CLIP_VOID : h;
        }
    }
}

/* Reads the job's posts into its buffer (the loader thread). */
static void fill_job(tp_pgm_clipmap* c, pgm_job* j)
{
    double t0 = tp_clock_ms();
    tp_pgm_clip_stats st;
    memset(&st, 0, sizeof st);
    c->failed[0] = 0;
    for (int k = 0; k < j->count; k++)
        fill_piece(c, &j->pieces[k], j->z + j->pieces[k].at, &st);
    memcpy(j->failed, c->failed, sizeof j->failed);
    j->node_reads = st.node_reads;
    j->fill_ms = tp_clock_ms() - t0;
}

static void upload_piece(const tp_pgm_clipmap* c, const piece* p, const float* z)
{
    glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, p->x0 & (c->w - 1), p->y0 & (c->w - 1), p->l,
                    p->x1 - p->x0, p->y1 - p->y0, 1, GL_RED, GL_FLOAT, z);
}

/* Uploads a filled job and moves the windows to its targets (render thread). */
static void upload_job(tp_pgm_clipmap* c, const pgm_job* j, tp_pgm_clip_stats* st)
{
    double t0 = tp_clock_ms();
    glBindTexture(GL_TEXTURE_2D_ARRAY, c->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    for (int k = 0; k < j->count; k++)
        upload_piece(c, &j->pieces[k], j->z + j->pieces[k].at);
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
    memcpy(c->origin, j->target, sizeof c->origin);
    c->filled = 1;
    st->upload_ms += tp_clock_ms() - t0;
    st->fill_ms += j->fill_ms;
    st->posts += j->posts;
    st->node_reads += j->node_reads;
    st->buffer_posts = j->posts > st->buffer_posts ? j->posts : st->buffer_posts;
}

/* The job at once on the render thread, a band of rows of a piece at a time through one buffer
 * of at most FILL_BUFFER_POSTS (a first fill or a jump refills every window: levels x w^2
 * posts), then the windows move. 0 when the buffer cannot be had: nothing is written, the
 * windows stay as they were (unfilled before the first fill: nothing is drawn then). */
static int fill_upload_job(tp_pgm_clipmap* c, const pgm_job* j, tp_pgm_clip_stats* st)
{
    size_t cap = j->posts < FILL_BUFFER_POSTS ? j->posts : FILL_BUFFER_POSTS;
    float* z = cap ? malloc(cap * sizeof *z) : NULL;
    if (cap && !z)
        return 0;
    c->failed[0] = 0;
    glBindTexture(GL_TEXTURE_2D_ARRAY, c->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    for (int k = 0; k < j->count; k++) {
        const piece* p = &j->pieces[k];
        size_t nx = (size_t)(p->x1 - p->x0);
        int rows = (int)(cap / nx); /* >= 1: a piece is at most w <= 8192 posts wide */
        for (int y = p->y0; y < p->y1; y += rows) {
            piece band = *p;
            band.y0 = y;
            band.y1 = y + rows < p->y1 ? y + rows : p->y1;
            double t0 = tp_clock_ms();
            fill_piece(c, &band, z, st);
            double t1 = tp_clock_ms();
            upload_piece(c, &band, z);
            st->fill_ms += t1 - t0;
            st->upload_ms += tp_clock_ms() - t1;
        }
    }
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
    free(z);
    memcpy(c->origin, j->target, sizeof c->origin);
    c->filled = 1;
    st->posts += j->posts;
    st->buffer_posts = cap > st->buffer_posts ? cap : st->buffer_posts;
    return 1;
}

static void* loader_main(void* arg)
{
    tp_pgm_clipmap* c = arg;
    pthread_mutex_lock(&c->mu);
    for (;;) {
        while (!c->quit && !c->pending)
            pthread_cond_wait(&c->cv, &c->mu);
        if (c->quit)
            break;
        pgm_job* j = c->pending;
        pthread_mutex_unlock(&c->mu);
        fill_job(c, j);
        pthread_mutex_lock(&c->mu);
        c->pending = NULL;
        c->ready = j;
    }
    pthread_mutex_unlock(&c->mu);
    return NULL;
}

int tp_pgm_clipmap_set_async(tp_pgm_clipmap* c, tp_error* err)
{
    if (c->async)
        return 1;
    if (pthread_mutex_init(&c->mu, NULL) != 0) {
        tp_error_set(err, TP_ERR_BACKEND, "PGM clipmap: cannot create a mutex");
        return 0;
    }
    if (pthread_cond_init(&c->cv, NULL) != 0) {
        pthread_mutex_destroy(&c->mu);
        tp_error_set(err, TP_ERR_BACKEND, "PGM clipmap: cannot create a condition variable");
        return 0;
    }
    if (pthread_create(&c->thread, NULL, loader_main, c) != 0) {
        pthread_cond_destroy(&c->cv);
        pthread_mutex_destroy(&c->mu);
        tp_error_set(err, TP_ERR_BACKEND, "PGM clipmap: cannot start the loader thread");
        return 0;
    }
    c->async = 1;
    return 1;
}

int tp_pgm_clipmap_pending(const tp_pgm_clipmap* c)
{
    if (!c->async)
        return 0;
    tp_pgm_clipmap* m = (tp_pgm_clipmap*)c; /* the mutex only */
    pthread_mutex_lock(&m->mu);
    int busy = m->pending || m->ready;
    pthread_mutex_unlock(&m->mu);
    return busy;
}

int tp_pgm_clipmap_update(tp_pgm_clipmap* c, double x, double y, tp_pgm_clip_stats* stats,
                          tp_error* err)
{
    tp_pgm_clip_stats st;
    memset(&st, 0, sizeof st);
    char failed[512] = "";
    int oom = 0;
    if (!c->async || !c->filled) { /* at once (the first fill always: nothing to draw before) */
        pgm_job* j = make_job(c, x, y, &oom);
        if (j) {
            oom = !fill_upload_job(c, j, &st);
            memcpy(failed, c->failed, sizeof failed);
            job_free(j);
        }
    } else {
        pthread_mutex_lock(&c->mu);
        pgm_job* done = c->ready;
        c->ready = NULL;
        int busy = c->pending != NULL;
        pthread_mutex_unlock(&c->mu);
        if (done) { /* uploaded with its origins: the windows move only now */
            upload_job(c, done, &st);
            memcpy(failed, done->failed, sizeof failed);
            job_free(done);
        }
        if (!busy) { /* the next move, from the windows as they now are */
            pgm_job* j = make_job(c, x, y, &oom);
            if (j && !job_buffer(j)) {
                job_free(j);
                j = NULL;
                oom = 1;
            }
            if (j) {
                pthread_mutex_lock(&c->mu);
                c->pending = j;
                pthread_cond_signal(&c->cv);
                pthread_mutex_unlock(&c->mu);
            }
        }
    }
    if (stats)
        *stats = st;
    if (oom) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "PGM clipmap: out of memory for the posts to load");
        return 0;
    }
    if (failed[0]) {
        tp_error_set(err, TP_ERR_IO, "PGM clipmap: %s", failed);
        return 0;
    }
    return 1;
}
