/* drape.c - features laid on the ground (drape.h). */
#include "drape.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct builder {
    tp_drape d;
    size_t vcap, pcap;
    int failed;
} builder;

static void add_vertex(builder* b, double e, double n, double h)
{
    if (b->d.vertex_count == b->vcap) {
        size_t cap = b->vcap ? 2 * b->vcap : 1024;
        double* p = realloc(b->d.enh, 3 * cap * sizeof *p);
        if (!p) {
            b->failed = 1;
            return;
        }
        b->d.enh = p;
        b->vcap = cap;
    }
    double* v = b->d.enh + 3 * b->d.vertex_count++;
    v[0] = e, v[1] = n, v[2] = h;
}

/* Ends the run that started at vertex first (kept when it has two vertices or more). */
static void end_part(builder* b, size_t first, double value, int index)
{
    size_t count = b->d.vertex_count - first;
    if (count < 2) {
        b->d.vertex_count = first;
        return;
    }
    if (b->d.part_count == b->pcap) {
        size_t cap = b->pcap ? 2 * b->pcap : 64;
        tp_drape_part* p = realloc(b->d.parts, cap * sizeof *p);
        if (!p) {
            b->failed = 1;
            return;
        }
        b->d.parts = p;
        b->pcap = cap;
    }
    b->d.parts[b->d.part_count++] = (tp_drape_part){first, count, value, index};
}

/* The ground height at render (e, n): NaN off the DEM or in a void; 0 after an error. */
static int ground_at(tp_ground* g, double e, double n, double* h, tp_error* err)
{
    double x, y;
    tp_tree_world_to_grid(tp_ground_scene(g)->tree, e, n, &x, &y);
    const tp_tree_geometry* geom = &tp_ground_scene(g)->info.header.geometry;
    if (!(x >= 0 && y >= 0 && x <= geom->src_width - 1 && y <= geom->src_height - 1)) {
        *h = NAN;
        return 1;
    }
    return tp_ground_height(g, x, y, h, err) == TP_OK;
}

int tp_drape_build(tp_drape* d, const tp_features* f, tp_ground* g, int contours, tp_error* err)
{
    builder b;
    memset(&b, 0, sizeof b);
    const double* gt = tp_ground_scene(g)->info.header.geotransform;
    const double step = fmin(fabs(gt[1]), fabs(gt[5]));
    size_t name_bytes = 0, points = 0;
    for (size_t i = 0; i < f->count; i++) {
        name_bytes += f->items[i].name ? strlen(f->items[i].name) + 1 : 0;
        points += f->items[i].kind == TP_FEATURE_POINT;
    }
    b.d.points = calloc(points ? points : 1, sizeof *b.d.points);
    b.d.names = malloc(name_bytes ? name_bytes : 1);
    b.failed = !b.d.points || !b.d.names;
    size_t name_at = 0;
    for (size_t i = 0; i < f->count && !b.failed; i++) {
        const tp_feature* ft = &f->items[i];
        const double* xy = f->xy + 2 * ft->first;
        if (ft->kind == TP_FEATURE_POINT) {
            double h;
            if (!ground_at(g, xy[0], xy[1], &h, err)) {
                b.failed = 2;
                break;
            }
            if (h != h) {
                b.d.dropped++;
                continue;
            }
            tp_drape_point* p = &b.d.points[b.d.point_count++];
            p->enh[0] = xy[0], p->enh[1] = xy[1], p->enh[2] = h;
            if (ft->name) {
                p->name = b.d.names + name_at;
                strcpy(b.d.names + name_at, ft->name);
                name_at += strlen(ft->name) + 1;
            }
            continue;
        }
        /* a line, or a ring closed by its first vertex again */
        const size_t n = ft->count + (ft->kind == TP_FEATURE_RING ? 1 : 0);
        size_t first = b.d.vertex_count;
        for (size_t k = 0; k < n && !b.failed; k++) {
            const double* p = xy + 2 * (k % ft->count);
            if (contours) {
                add_vertex(&b, p[0], p[1], ft->value);
                continue;
            }
            /* the segment from the previous vertex, every post spacing */
            const double* q = k ? xy + 2 * ((k - 1) % ft->count) : p;
            const double len = hypot(p[0] - q[0], p[1] - q[1]);
            const int pieces = k ? (int)fmin(ceil(len / step), 1e5) : 0;
            for (int s = pieces ? 1 : 0; s <= pieces && !b.failed; s++) {
                const double t = pieces ? (double)s / pieces : 1.0;
                const double e = q[0] + t * (p[0] - q[0]), nn = q[1] + t * (p[1] - q[1]);
                double h;
                if (!ground_at(g, e, nn, &h, err)) {
                    b.failed = 2;
                    break;
                }
                if (h != h) { /* a void or off the DEM: the run ends here */
                    b.d.dropped++;
                    end_part(&b, first, ft->value, ft->index);
                    first = b.d.vertex_count;
                    continue;
                }
                add_vertex(&b, e, nn, h);
            }
        }
        end_part(&b, first, ft->value, ft->index);
    }
    if (b.failed) {
        if (b.failed != 2) /* 2: the ground's reason is in err */
            tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory draping %zu features", f->count);
        tp_drape_free(&b.d);
        return 0;
    }
    *d = b.d;
    return 1;
}

void tp_drape_free(tp_drape* d)
{
    free(d->enh);
    free(d->parts);
    free(d->points);
    free(d->names);
    memset(d, 0, sizeof *d);
}
