/* test_qm_refine.c - a quantized-mesh tile's refinement (app/export/qm_refine.c) on synthetic
 * ground: every point held within the bound, checked here by a brute-force search of the
 * triangle around each point (not the exporter's point index); the tile's outline untouched; the
 * triangles a partition of the tile (areas summing to it, one orientation, every inner edge
 * shared by two); side vertices splitting the outline where asked. Whole tile sets are checked
 * by tests/qm_check.py (export_qm.*). */
#include "qm_tile.h"
#include "tp_io.h"
#include "tp_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TESTS(X)                                                                                   \
    X(refine_holds_every_point_and_keeps_the_outline)                                              \
    X(side_vertices_split_the_outline)

#define MAXC 32767
#define PER_CELL (MAXC / TP_QM_CELLS)

/* Ridged ground in metres at lattice position (fi, fj), slopes up to ~50 m a cell, on a plane
 * at the tile's outline (the refinement never touches the outline: a side's own posts are
 * qm_sides.c's). */
static double ground(double fi, double fj)
{
    const double pi = 3.14159265358979323846;
    const double inside = sin(pi * fi / TP_QM_CELLS) * sin(pi * fj / TP_QM_CELLS);
    return inside * (300 * sin(fi / 9.0) * cos(fj / 13.0) + 80 * fabs(sin((fi + 2 * fj) / 5.0))) +
           0.3 * fi - 0.2 * fj;
}

static int ground_fn(void* ctx, double fi, double fj, double* h)
{
    (void)ctx;
    *h = ground(fi, fj);
    return 1;
}

/* Two triangles over the tile, corners at the ground's heights (steps of 0.125 m). */
static void two_triangles(qm_work* w, double step)
{
    memset(w, 0, sizeof *w);
    w->nv = w->cap_v = 4;
    w->u = malloc(4 * sizeof *w->u);
    w->v = malloc(4 * sizeof *w->v);
    w->hq = malloc(4 * sizeof *w->hq);
    const uint16_t u[4] = {0, MAXC, 0, MAXC}, v[4] = {0, 0, MAXC, MAXC};
    for (int k = 0; k < 4; k++) {
        w->u[k] = u[k];
        w->v[k] = v[k];
        w->hq[k] = llround(ground(u[k] / (double)PER_CELL, TP_QM_CELLS - v[k] / (double)PER_CELL) / step);
    }
    w->nt = 2;
    w->cap_t = 6;
    w->tris = malloc(6 * sizeof *w->tris);
    const uint32_t t[6] = {0, 1, 3, 0, 3, 2}; /* counter-clockwise in (u, v) */
    memcpy(w->tris, t, sizeof t);
}

static void work_free(qm_work* w)
{
    free(w->u);
    free(w->v);
    free(w->hq);
    free(w->tris);
}

static double cross(const qm_work* w, uint32_t a, uint32_t b, double x, double y)
{
    return ((double)w->u[b] - w->u[a]) * (y - w->v[a]) - ((double)w->v[b] - w->v[a]) * (x - w->u[a]);
}

/* The mesh's height at code position (x, y): every triangle tried, the one holding it. */
static double height_at(const qm_work* w, double x, double y, double step)
{
    for (size_t t = 0; t < w->nt; t++) {
        const uint32_t* v = w->tris + 3 * t;
        const double area = cross(w, v[0], v[1], w->u[v[2]], w->v[v[2]]);
        const double a = cross(w, v[1], v[2], x, y) / area, b = cross(w, v[2], v[0], x, y) / area;
        const double c = 1 - a - b;
        if (a >= -1e-12 && b >= -1e-12 && c >= -1e-12)
            return (a * w->hq[v[0]] + b * w->hq[v[1]] + c * w->hq[v[2]]) * step;
    }
    return NAN;
}

/* The triangles: one orientation, areas summing to the tile, each edge used once (outline) or
 * twice in opposite directions (inside). */
static void check_partition(const qm_work* w)
{
    double sum = 0;
    for (size_t t = 0; t < w->nt; t++) {
        const uint32_t* v = w->tris + 3 * t;
        const double area = cross(w, v[0], v[1], w->u[v[2]], w->v[v[2]]);
        ASSERT_GT(area, 0);
        sum += area / 2;
    }
    ASSERT_NEAR(sum, (double)MAXC * MAXC, 1e-6 * MAXC * MAXC);
    size_t outline = 0;
    for (size_t t = 0; t < w->nt; t++)
        for (int e = 0; e < 3; e++) {
            const uint32_t a = w->tris[3 * t + e], b = w->tris[3 * t + (e + 1) % 3];
            int twin = 0;
            for (size_t o = 0; o < w->nt; o++)
                for (int f = 0; f < 3; f++)
                    twin += w->tris[3 * o + f] == b && w->tris[3 * o + (f + 1) % 3] == a;
            const int on_outline = (w->u[a] == w->u[b] && (w->u[a] == 0 || w->u[a] == MAXC)) ||
                                   (w->v[a] == w->v[b] && (w->v[a] == 0 || w->v[a] == MAXC));
            ASSERT_EQ_INT(on_outline ? 0 : 1, twin);
            outline += on_outline;
        }
    ASSERT_GE_INT((int)outline, 4);
}

/* The mesh as the measure's index sees it (ij in lattice cells, decoded heights). */
typedef struct mesh_buf {
    double *ij, *z;
    qm_mesh m;
} mesh_buf;

static void mesh_of(const qm_work* w, double step, mesh_buf* b)
{
    b->ij = malloc(2 * w->nv * sizeof *b->ij);
    b->z = malloc(w->nv * sizeof *b->z);
    for (size_t k = 0; k < w->nv; k++) {
        b->ij[2 * k] = w->u[k] / (double)PER_CELL;
        b->ij[2 * k + 1] = TP_QM_CELLS - w->v[k] / (double)PER_CELL;
        b->z[k] = w->hq[k] * step;
    }
    b->m = (qm_mesh){TP_QM_CELLS, w->nv, w->nt, b->ij, b->z, w->tris};
}

TEST(refine_holds_every_point_and_keeps_the_outline)
{
    const double step = 0.125, bound = 2.0;
    qm_work w;
    two_triangles(&w, step);
    /* 4000 points at random positions (a fixed generator), on the ground */
    const size_t n = 4000;
    qm_point* p = malloc(n * sizeof *p);
    uint64_t s = 34;
    for (size_t k = 0; k < n; k++) {
        double r[2];
        for (int c = 0; c < 2; c++) {
            s = s * 6364136223846793005ull + 1442695040888963407ull;
            r[c] = (double)(s >> 11) / 9007199254740992.0;
        }
        p[k] = (qm_point){0.01 + 216.98 * r[0], 0.01 + 216.98 * r[1], 0};
        p[k].h = ground(p[k].fi, p[k].fj);
    }
    mesh_buf b;
    mesh_of(&w, step, &b);
    qm_index* ix = NULL;
    size_t added;
    double stuck;
    tp_error err;
    ASSERT_TRUE(tp_qm_refine(&w, &b.m, &ix, p, n, bound, step, ground_fn, NULL, &added, &stuck,
                             &err));
    tp_qm_index_free(ix);
    free(b.ij);
    free(b.z);
    /* the two triangles missed by hundreds of metres: many vertices, far fewer than points */
    ASSERT_GT((double)added, 50);
    ASSERT_LT((double)added, (double)n);
    ASSERT_EQ_INT(4 + (int)added, (int)w.nv);
    ASSERT_EQ_INT(2 + 2 * (int)added, (int)w.nt); /* Euler: each inner vertex two triangles */
    EXPECT_EQ_DBL(0.0, stuck);
    double worst = 0;
    for (size_t k = 0; k < n; k++) {
        const double z = height_at(&w, p[k].fi * PER_CELL, MAXC - p[k].fj * PER_CELL, step);
        ASSERT_FALSE(isnan(z));
        worst = fmax(worst, fabs(z - p[k].h));
    }
    EXPECT_LE(worst, bound);
    EXPECT_GT(worst, 0.25 * bound); /* greedy to the bound, not beyond */
    for (size_t k = 4; k < w.nv; k++) {
        ASSERT_TRUE(w.u[k] > 0 && w.u[k] < MAXC && w.v[k] > 0 && w.v[k] < MAXC);
        /* on the ground at its own code, within half a step */
        const double h = ground(w.u[k] / (double)PER_CELL, TP_QM_CELLS - w.v[k] / (double)PER_CELL);
        ASSERT_NEAR(w.hq[k] * step, h, 0.5 * step + 1e-9);
    }
    check_partition(&w);
    free(p);
    work_free(&w);
}

TEST(side_vertices_split_the_outline)
{
    const double step = 0.125;
    qm_work w;
    two_triangles(&w, step);
    const qm_side_vertex sv[5] = {{0, 10000, 8}, {16000, 0, -8}, {MAXC, 20000, 80},
                                  {5000, MAXC, 3}, {16000, 0, 99}}; /* the last: taken already */
    tp_error err;
    ASSERT_TRUE(tp_qm_insert_sides(&w, sv, 5, &err));
    ASSERT_EQ_INT(8, (int)w.nv);
    ASSERT_EQ_INT(6, (int)w.nt); /* a vertex on the outline adds one triangle */
    for (int k = 0; k < 4; k++) {
        ASSERT_EQ_INT(sv[k].u, w.u[4 + k]);
        ASSERT_EQ_INT(sv[k].v, w.v[4 + k]);
        ASSERT_EQ_INT((int)sv[k].hq, (int)w.hq[4 + k]);
    }
    check_partition(&w);
    work_free(&w);
}

TP_TEST_MAIN(TESTS)
