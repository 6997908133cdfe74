/* test_cut.c - the cut over a tree (cut_select.c, cut_stitch.c) on real relief: watertight
 * for random views and for adversarial hand-made cuts, the error bound on screen, substitution
 * of nodes that are not resident, and a cost that does not grow with the map.
 */
#include "tp_test.h"

#include <stdint.h>

/* ---- data ---- */

#include "tp_test_hgt.h"

/* Fills voids with the last height before them in the row (or after, at the row's start), for
 * tests that compare covered areas. */
static void fill_voids(float* hts, int w, int h)
{
    for (int y = 0; y < h; y++) {
        float* row = hts + (size_t)y * w;
        float last = NAN;
        for (int x = 0; x < w; x++)
            if (isnan(row[x]))
                row[x] = last;
            else
                last = row[x];
        for (int x = w - 1; x >= 0; x--)
            if (isnan(row[x]))
                row[x] = last;
            else
                last = row[x];
    }
}

#define LOAD_OR_SKIP(var, x0, y0, w, h)                                                            \
    float* var = load_hgt(x0, y0, w, h);                                                           \
    if (!var)                                                                                      \
    SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)")

static const double GT[6] = {400000, 90, 0, 4800000, 0, -90}; /* SRTM3 at about 90 m */

static tp_tree* make_tree(const float* hts, int w, int h, int patch_size)
{
    tp_tree* t = NULL;
    tp_error e = {{0}};
    tp_status st = tp_tree_create_from_grid(hts, (size_t)w * h, w, h, GT, patch_size, 0, &t, &e);
    if (st != TP_OK)
        fprintf(stderr, "tree: %s\n", e.message);
    ASSERT_OK(st);
    return t;
}

static uint64_t rng_state = 88172645463325252ull;
static double rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

static void grid_to_world(double x, double y, double* e, double* n)
{
    *e = GT[0] + (x + 0.5) * GT[1];
    *n = GT[3] + (y + 0.5) * GT[5];
}

/* A camera above grid point (x, y) of the tree, `above` metres over the surface. */
static void camera_at(const tp_tree* t, double x, double y, double above, double yaw, double pitch,
                      tp_camera* cam)
{
    double z = tp_tree_sample(t, (int)x, (int)y);
    for (int r = 1; isnan(z) && r < 64; r++) /* over a void: the nearest height along the row */
        z = tp_tree_sample(t, (int)x + r, (int)y);
    double pos[3];
    grid_to_world(x, y, &pos[0], &pos[1]);
    pos[2] = (isnan(z) ? 0 : z) + above;
    tp_camera_from_pose(pos, yaw, pitch, 60, 1280, 720, cam);
}

/* camera_at over the relief drawn at vertical scale zs. */
static void camera_scaled(const tp_tree* t, double x, double y, double above, double yaw,
                          double pitch, double zs, tp_camera* cam)
{
    camera_at(t, x, y, above, yaw, pitch, cam);
    double pos[3] = {cam->position[0], cam->position[1],
                     zs * (cam->position[2] - above) + above};
    tp_camera_from_pose(pos, yaw, pitch, 60, 1280, 720, cam);
}

static void random_camera(const tp_tree* t, tp_camera* cam)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    camera_at(t, rnd() * (g->src_width - 1), rnd() * (g->src_height - 1), 30 + rnd() * 3000,
              rnd() * 360, -5 - rnd() * 80, cam);
}

/* Builds every TIN level the cut's last update asked for. */
static void build_requested(const tp_cut* cut, tp_tin_cache* tins)
{
    size_t nr;
    const tp_cut_tin_request* rq = tp_cut_tin_requests(cut, &nr);
    for (size_t i = 0; i < nr; i++)
        ASSERT_OK(tp_tin_cache_build(tins, rq[i].node, rq[i].level, NULL));
}

/* tp_cut_update, and with a TIN cache, once more after building every level it asked for (so
 * that the cut draws TINs wherever a rung fits). */
static void update_tins(tp_cut* cut, tp_tin_cache* tins, const tp_camera* cam,
                        const tp_lod_params* lp)
{
    ASSERT_OK(tp_cut_update(cut, cam, lp, NULL));
    if (!tins)
        return;
    build_requested(cut, tins);
    ASSERT_OK(tp_cut_update(cut, cam, lp, NULL));
    size_t nr;
    tp_cut_tin_requests(cut, &nr);
    EXPECT_EQ_INT(0, (int)nr);
}

/* ---- the watertight check ---- */

typedef struct seg {
    int32_t a[2], b[2]; /* a < b */
    float za, zb;
} seg;

typedef struct node_geom {
    int64_t x0, y0, x1, y1;
    int complete;
    int mask_rule;   /* incomplete, drawn by its cell mask */
    int64_t cell;    /* its cell size (grid samples) */
    seg* segs; /* triangle edges on the node's border */
    size_t seg_count;
} node_geom;

static int seg_cmp(const void* p, const void* q)
{
    const seg *a = p, *b = q;
    for (int i = 0; i < 2; i++) {
        if (a->a[i] != b->a[i])
            return a->a[i] < b->a[i] ? -1 : 1;
        if (a->b[i] != b->b[i])
            return a->b[i] < b->b[i] ? -1 : 1;
    }
    return 0;
}

static int seg_match(const seg* a, const seg* b)
{
    return seg_cmp(a, b) == 0 && memcmp(&a->za, &b->za, sizeof(float)) == 0 &&
           memcmp(&a->zb, &b->zb, sizeof(float)) == 0;
}

static int on_border(const node_geom* ng, const int32_t p[2], const int32_t q[2])
{
    return (p[0] == q[0] && (p[0] == ng->x0 || p[0] == ng->x1)) ||
           (p[1] == q[1] && (p[1] == ng->y0 || p[1] == ng->y1));
}

typedef struct cover {
    uint8_t* bits;
    int w;
} cover;

typedef struct void_probe {
    const tp_tree* t;
    int voids;
} void_probe;

static void count_void(int x, int y, double z, void* user)
{
    (void)z;
    void_probe* p = user;
    p->voids += isnan(tp_tree_sample(p->t, x, y));
}

static void mark(int x, int y, double z, void* user)
{
    (void)z;
    cover* c = user;
    c->bits[(size_t)y * c->w + x] = 1;
}

/* --stitch add: drawn node i's triangles when a side takes vertices (tp_cut_node.add), as
 * tp_cut_triangles gives them (index triples into v, degenerate ones left out), with v its
 * level-m lattice (tp_cut_vertices_at_level, m the finest of its and the add levels); SIZE_MAX
 * when no side takes vertices. */
static size_t add_triangles(const tp_cut* cut, int n, size_t i, tp_vertex* v, uint32_t* tri,
                            size_t cap)
{
    size_t count;
    const tp_cut_node* o = &tp_cut_nodes(cut, &count)[i];
    int add[4], m = o->level, any = 0;
    for (int s = 0; s < 4; s++) {
        add[s] = o->add[s];
        any |= add[s] != TP_NO_NEIGHBOR;
        if (add[s] != TP_NO_NEIGHBOR && add[s] > m)
            m = add[s];
    }
    if (!any)
        return SIZE_MAX;
    size_t side = ((size_t)1 << n) + 1, ms = ((size_t)1 << m) + 1;
    tp_cut_vertices_at_level(cut, i, m, v, ms * ms);
    size_t nt = tp_patch_triangles_add(n, o->level, add, tri, cap / 3);
    ASSERT_TRUE(3 * nt <= cap);
    size_t kept = 0;
    for (size_t t = 0; t < nt; t++) {
        uint32_t at[3];
        for (int a = 0; a < 3; a++) {
            size_t row = tri[3 * t + a] / side, col = tri[3 * t + a] % side;
            at[a] = (uint32_t)((row >> (n - m)) * ms + (col >> (n - m)));
        }
        const tp_vertex *a = &v[at[0]], *b = &v[at[1]], *c = &v[at[2]];
        int64_t area = ((int64_t)b->x - a->x) * ((int64_t)c->y - a->y) -
                       ((int64_t)b->y - a->y) * ((int64_t)c->x - a->x);
        if (area != 0)
            memcpy(&tri[3 * kept++], at, sizeof at);
    }
    return kept;
}

/* Checks the drawn cut: shared edges identical from both sides, no fold-over, and every
 * sample of every drawn complete node's area covered. Fills *covered (grid-sized, 0/1) when
 * not NULL. Returns the number of failures (also reported). */
static size_t last_triangles; /* drawn triangles counted by the last check_watertight */

static int check_watertight(const tp_tree* t, const tp_cut* cut, uint8_t* covered)
{
    last_triangles = 0;
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    size_t count;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    size_t vmax = ((size_t)1 << g->n) + 1;
    tp_vertex* v = malloc(vmax * vmax * sizeof *v);
    uint32_t* tri = malloc(6 * (vmax - 1) * (vmax - 1) * sizeof *tri);
    node_geom* ng = calloc(count ? count : 1, sizeof *ng);
    cover cov = {calloc((size_t)g->width * g->height, 1), g->width};
    int failures = 0, sign = 0;
    for (size_t i = 0; i < count; i++) {
        int s, c, r;
        tp_tree_node_locate(g, nodes[i].node, &s, &c, &r);
        int64_t span = (int64_t)1 << (g->n + s);
        ng[i].x0 = c * span, ng[i].x1 = (c + 1) * span;
        ng[i].y0 = r * span, ng[i].y1 = (r + 1) * span;
        ng[i].complete = tp_tree_meta(t, nodes[i].node)->flags & TP_NODE_COMPLETE;
        int k = nodes[i].level, vs = (1 << k) + 1;
        size_t nt = add_triangles(cut, g->n, i, v, tri, 6 * (vmax - 1) * (vmax - 1));
        if (nt == SIZE_MAX) { /* no side takes vertices */
            tp_cut_vertices(cut, i, v, (size_t)vs * vs);
            nt = tp_cut_triangles(cut, i, v, tri, 2 * (size_t)(vs - 1) * (vs - 1));
        }
        last_triangles += nt;
        /* An incomplete node below a leaf's level n: no triangle covers an undrawn sample. */
        ng[i].mask_rule = !ng[i].complete && !(s == 0 && k == g->n);
        /* its cell, or where a coarser neighbour moves its border vertices, the neighbour's
         * (a stitched triangle over a partly undrawn stretch of border is not drawn) */
        int kmin = k;
        for (int side = 0; side < 4; side++)
            if (nodes[i].nb[side] >= 0 && nodes[i].nb[side] < kmin)
                kmin = nodes[i].nb[side];
        ng[i].cell = (int64_t)1 << (g->n - kmin + s);
        for (size_t j = 0; ng[i].mask_rule && j < nt; j++) {
            const tp_vertex* p[3] = {&v[tri[3 * j]], &v[tri[3 * j + 1]], &v[tri[3 * j + 2]]};
            int32_t pa[2] = {p[0]->x, p[0]->y}, pb[2] = {p[1]->x, p[1]->y},
                    pc[2] = {p[2]->x, p[2]->y};
            void_probe vp = {t, 0};
            tp_triangle_rasterize(pa, pb, pc, 0, 0, 0, count_void, &vp);
            if (vp.voids && failures++ < 5)
                fprintf(stderr, "node %lld (incomplete, level %d): a triangle covers %d undrawn "
                        "samples\n", (long long)nodes[i].node, k, vp.voids);
        }
        ng[i].segs = malloc(3 * nt * sizeof(seg) + 1);
        for (size_t j = 0; j < nt; j++) {
            const tp_vertex* p[3] = {&v[tri[3 * j]], &v[tri[3 * j + 1]], &v[tri[3 * j + 2]]};
            int64_t area = ((int64_t)p[1]->x - p[0]->x) * ((int64_t)p[2]->y - p[0]->y) -
                           ((int64_t)p[1]->y - p[0]->y) * ((int64_t)p[2]->x - p[0]->x);
            int sg = area > 0 ? 1 : -1;
            if (!sign)
                sign = sg;
            if (sg != sign && failures++ < 5)
                fprintf(stderr, "fold-over: node %lld triangle %zu\n", (long long)nodes[i].node, j);
            int32_t pa[2] = {p[0]->x, p[0]->y}, pb[2] = {p[1]->x, p[1]->y},
                    pc[2] = {p[2]->x, p[2]->y};
            tp_triangle_rasterize(pa, pb, pc, 0, 0, 0, mark, &cov);
            for (int e = 0; e < 3; e++) {
                const tp_vertex *u = p[e], *w = p[(e + 1) % 3];
                int32_t a[2] = {u->x, u->y}, b[2] = {w->x, w->y};
                if (!on_border(&ng[i], a, b))
                    continue;
                seg sgm;
                int swap = a[0] > b[0] || (a[0] == b[0] && a[1] > b[1]);
                memcpy(sgm.a, swap ? b : a, sizeof sgm.a);
                memcpy(sgm.b, swap ? a : b, sizeof sgm.b);
                sgm.za = swap ? w->z_m : u->z_m;
                sgm.zb = swap ? u->z_m : w->z_m;
                ng[i].segs[ng[i].seg_count++] = sgm;
            }
        }
        qsort(ng[i].segs, ng[i].seg_count, sizeof(seg), seg_cmp);
    }
    /* Every pair of drawn nodes sharing part of an edge: the same segments on the overlap. */
    seg* sa = malloc(4 * vmax * sizeof *sa * 4);
    seg* sb = malloc(4 * vmax * sizeof *sb * 4);
    for (size_t i = 0; i < count; i++)
        for (size_t j = i + 1; j < count; j++) {
            node_geom *A = &ng[i], *B = &ng[j];
            int vertical = A->x1 == B->x0 || B->x1 == A->x0; /* shared line x = const */
            int horizontal = A->y1 == B->y0 || B->y1 == A->y0;
            int64_t lo, hi, line;
            if (vertical) {
                lo = A->y0 > B->y0 ? A->y0 : B->y0, hi = A->y1 < B->y1 ? A->y1 : B->y1;
                line = A->x1 == B->x0 ? A->x1 : A->x0;
            } else if (horizontal) {
                lo = A->x0 > B->x0 ? A->x0 : B->x0, hi = A->x1 < B->x1 ? A->x1 : B->x1;
                line = A->y1 == B->y0 ? A->y1 : A->y0;
            } else
                continue;
            if (hi <= lo)
                continue;
            size_t na = 0, nb = 0;
            for (int side = 0; side < 2; side++) {
                node_geom* N = side ? B : A;
                seg* out = side ? sb : sa;
                size_t* no = side ? &nb : &na;
                for (size_t k = 0; k < N->seg_count; k++) {
                    seg* q = &N->segs[k];
                    int along = vertical ? 1 : 0, across = 1 - along;
                    if (q->a[across] != line || q->b[across] != line)
                        continue;
                    if (q->a[along] < lo || q->b[along] > hi)
                        continue;
                    out[(*no)++] = *q;
                }
            }
            /* Complete nodes: the same segments. Next to undrawn samples a side may lack a
             * triangle: then each segment of one side is either the other side's too or meets
             * none of the other's (a T-junction overlaps without matching). */
            int same = 1;
            if (A->complete && B->complete) {
                same = na == nb;
                for (size_t k = 0; same && k < na; k++)
                    same = seg_match(&sa[k], &sb[k]);
            } else {
                int along = vertical ? 1 : 0;
                for (int side = 0; side < 2 && same; side++) {
                    seg *x = side ? sb : sa, *y = side ? sa : sb;
                    size_t nx = side ? nb : na, ny = side ? na : nb;
                    for (size_t k = 0; k < nx && same; k++) {
                        int found = 0, overlaps = 0;
                        for (size_t l = 0; l < ny; l++) {
                            found |= seg_match(&x[k], &y[l]);
                            overlaps |=
                                x[k].a[along] < y[l].b[along] && y[l].a[along] < x[k].b[along];
                        }
                        same = found || !overlaps;
                    }
                }
            }
            if (!same && failures++ < 5) {
                fprintf(stderr,
                        "crack between nodes %lld (level %d nb %d %d %d %d) and %lld (level %d nb "
                        "%d %d %d %d): %zu vs %zu segments\n",
                        (long long)nodes[i].node, nodes[i].level, nodes[i].nb[0], nodes[i].nb[1],
                        nodes[i].nb[2], nodes[i].nb[3], (long long)nodes[j].node, nodes[j].level,
                        nodes[j].nb[0], nodes[j].nb[1], nodes[j].nb[2], nodes[j].nb[3], na, nb);
            }
        }
    /* Holes: a drawn sample of an incomplete node drawn by its mask that no triangle covers
     * lies within one of its cells (2^(n-k+s) samples; a coarser neighbour's along a stitched
     * side) of an undrawn sample. */
    for (size_t i = 0; i < count; i++) {
        if (!ng[i].mask_rule)
            continue;
        int64_t far = 0, d = ng[i].cell;
        for (int64_t y = ng[i].y0; y <= ng[i].y1; y++)
            for (int64_t x = ng[i].x0; x <= ng[i].x1; x++) {
                if (cov.bits[(size_t)y * g->width + (size_t)x] ||
                    isnan(tp_tree_sample(t, (int)x, (int)y)))
                    continue;
                int near = 0;
                for (int64_t yy = y - d; yy <= y + d && !near; yy++)
                    for (int64_t xx = x - d; xx <= x + d && !near; xx++)
                        near = xx < 0 || yy < 0 || xx >= g->width || yy >= g->height ||
                               isnan(tp_tree_sample(t, (int)xx, (int)yy));
                far += !near;
            }
        if (far && failures++ < 5)
            fprintf(stderr, "hole: %lld drawn samples of node %lld (level %d) not covered and "
                    "farther than %lld from a void\n", (long long)far,
                    (long long)nodes[i].node, nodes[i].level, (long long)d);
    }
    /* No gap: every sample of a complete drawn node's area under a triangle. */
    for (size_t i = 0; i < count; i++) {
        if (!ng[i].complete)
            continue;
        int64_t missing = 0;
        for (int64_t y = ng[i].y0; y <= ng[i].y1; y++)
            for (int64_t x = ng[i].x0; x <= ng[i].x1; x++)
                missing += !cov.bits[(size_t)y * g->width + (size_t)x];
        if (missing && failures++ < 5)
            fprintf(stderr, "gap: %lld samples of node %lld not covered\n", (long long)missing,
                    (long long)nodes[i].node);
    }
    if (covered)
        memcpy(covered, cov.bits, (size_t)g->width * g->height);
    for (size_t i = 0; i < count; i++)
        free(ng[i].segs);
    free(ng);
    free(sa);
    free(sb);
    free(v);
    free(tri);
    free(cov.bits);
    return failures;
}

/* ---- tests ---- */

/* --stitch add's bound for drawn node i as its definition states it (tp_cut_add_bound_m),
 * computed here from the node's samples: its level's delta plus the largest offset of a side
 * sample at an added level's stride from the level-k edge through that side's vertices. */
static double direct_add_bound_m(const tp_tree* t, const tp_cut_node* o)
{
    tp_tree_info info;
    tp_tree_get_info(t, &info);
    const int n = tp_tree_get_geometry(t)->n, k = o->level, side = (1 << n) + 1;
    const uint16_t* q = tp_tree_samples(t, o->node);
    const tp_node_meta* m = tp_tree_meta(t, o->node);
    double worst = 0;
    for (int sd = 0; sd < 4; sd++) {
        if (o->add[sd] == TP_NO_NEIGHBOR || o->add[sd] <= k)
            continue;
        int stride = 1 << (n - (o->add[sd] > n ? n : o->add[sd])), seg = 1 << (n - k);
        for (int u = 0; u < side; u += stride) {
            int lo = u / seg * seg, hi = lo + seg < side ? lo + seg : lo;
            /* position u along the side: TOP row 0, RIGHT column 2^n, BOTTOM row 2^n, LEFT 0 */
            int at[3];
            const int pos[3] = {u, lo, hi};
            for (int j = 0; j < 3; j++)
                at[j] = sd == TP_SIDE_TOP      ? pos[j]
                        : sd == TP_SIDE_RIGHT  ? pos[j] * side + side - 1
                        : sd == TP_SIDE_BOTTOM ? (side - 1) * side + pos[j]
                                               : pos[j] * side;
            double za = q[at[1]], zb = q[at[2]];
            double line = hi > lo ? za + (zb - za) * (u - lo) / (hi - lo) : za;
            worst = fmax(worst, fabs(q[at[0]] - line));
        }
    }
    return tp_node_error_bound(m, n, k, NULL, info.height_step_m, info.err_unit_steps) +
           worst * info.height_step_m;
}

/* Random views with vertex moving, or with --stitch add (add: tp_cut_set_stitch_add). */
static void random_views(int add, int with_tins)
{
    /* 700 x 420: not 2^n k + 1, so padded, and a forest of roots of different scales. */
    LOAD_OR_SKIP(h, 250, 300, 700, 420);
    long add_sides = 0, moved_sides = 0, tin_nodes = 0;
    for (int ps = 17; ps <= 33; ps += 16) { /* n = 4 and 5 */
        tp_tree* t = make_tree(h, 700, 420, ps);
        tp_cut* cut;
        ASSERT_OK(tp_cut_create(t, &cut, NULL));
        tp_cut_set_stitch_add(cut, add);
        tp_tin_cache* tins = NULL;
        if (with_tins) {
            ASSERT_OK(tp_tin_cache_create(t, &tins, NULL));
            tp_cut_set_tins(cut, tins);
        }
        const double taus[] = {0.5, 1, 4, 16};
        size_t total = 0;
        for (int it = 0; it < 40; it++) {
            tp_camera cam;
            random_camera(t, &cam);
            tp_lod_params lp = {0};
            lp.mode = it % 8 == 6 ? TP_LOD_DISTANCE : it % 8 == 7 ? TP_LOD_FULL : TP_LOD_ERROR;
            lp.tau_px = taus[it % 4];
            update_tins(cut, tins, &cam, &lp);
            size_t count;
            tp_cut_nodes(cut, &count);
            total += count;
            int f = check_watertight(t, cut, NULL);
            tp_cut_stats st;
            tp_cut_get_stats(cut, &st);
            EXPECT_EQ_INT((int)last_triangles, (int)st.triangles);
            EXPECT_EQ_INT((int)count, st.drawn);
            add_sides += st.add_sides;
            moved_sides += st.moved_sides;
            tin_nodes += st.tin_nodes;
            if (!tins)
                EXPECT_EQ_INT(0, st.tin_nodes);
            const tp_cut_node* o = tp_cut_nodes(cut, &count);
            for (size_t i = 0; add && i < count; i++) {
                int a[4] = {o[i].add[0], o[i].add[1], o[i].add[2], o[i].add[3]};
                double want = direct_add_bound_m(t, &o[i]);
                /* the cut's table keeps offsets as floats rounded up */
                EXPECT_NEAR(want, tp_cut_add_bound_m(cut, i, a), 1e-6 * (1 + want));
                EXPECT_TRUE(tp_cut_add_bound_m(cut, i, a) >= want - 1e-9);
            }
            if (f)
                fprintf(stderr, "view %d (mode %d, tau %g): %d failures\n", it, (int)lp.mode,
                        lp.tau_px, f);
            EXPECT_EQ_INT(0, f);
        }
        EXPECT_GT((double)total, 40 * 5); /* the views see the terrain */
        tp_cut_destroy(cut);
        tp_tin_cache_destroy(tins);
        tp_tree_destroy(t);
    }
    printf("%s%s: %ld sides take vertices, %ld move; %ld nodes drawn as TINs\n",
           add ? "--stitch add" : "vertex moving", with_tins ? ", TIN nodes" : "", add_sides,
           moved_sides, tin_nodes);
    if (with_tins) /* TINs drawn, and stitched against */
        EXPECT_GT((double)tin_nodes, 1000);
    if (add) /* both kinds of seam are there, or the views prove little */
        EXPECT_GT((double)add_sides, 100);
    else
        EXPECT_EQ_INT(0, (int)add_sides);
    EXPECT_GT((double)moved_sides, 100);
    free(h);
}

TEST(watertight_for_random_views)
{
    random_views(0, 0);
}

TEST(watertight_for_random_views_with_tin_nodes)
{
    random_views(0, 1);
}

/* --stitch add: same-size neighbours add vertices, different sizes still move them. */
TEST(watertight_for_random_views_stitch_add)
{
    random_views(1, 0);
}

/* A cut selected for one camera and drawn from another (a cut selected on another thread for
 * the predicted camera): whenever tp_cut_holds_for accepts it, the measured screen error from
 * the new camera stays within tau, and every pixel where the new camera's own cut shows ground
 * shows ground in the reused cut too (the grid position the fresh cut's ray hits has a drawn
 * height in the old cut). Small moves are mostly accepted; jumps are refused. */
TEST(a_cut_drawn_from_a_moved_camera_keeps_tau_and_coverage)
{
    LOAD_OR_SKIP(h, 250, 300, 700, 420);
    tp_tree* t = make_tree(h, 700, 420, 33);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_cut *cut, *fresh;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    ASSERT_OK(tp_cut_create(t, &fresh, NULL));
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    int small_held = 0, small = 0, jumps_held = 0, covered = 0;
    for (int it = 0; it < 80; it++) {
        double x = rnd() * (g->src_width - 1), y = rnd() * (g->src_height - 1);
        double above = 30 + rnd() * 2000, yaw = rnd() * 360, pitch = -5 - rnd() * 60;
        tp_camera a, b;
        camera_at(t, x, y, above, yaw, pitch, &a);
        int jump = it % 4 == 3;
        if (jump) /* as Home: somewhere else entirely */
            camera_at(t, fmod(x + 350, g->src_width - 1), y, above, yaw + 120, pitch, &b);
        else { /* one frame of a flight: up to 10 m and 1.5 degrees */
            b = a;
            double step = rnd() * 10, turn = (rnd() - 0.5) * 3, dir = yaw * 3.14159265358979 / 180;
            double pos[3] = {a.position[0] + step * sin(dir), a.position[1] + step * cos(dir),
                             a.position[2] + (rnd() - 0.5) * step * 0.2};
            tp_camera_from_pose(pos, yaw + turn, pitch + turn / 3, 60, 1280, 720, &b);
        }
        ASSERT_OK(tp_cut_update(cut, &a, &lp, NULL));
        double bound_b;
        int holds = tp_cut_holds_for(cut, &b, &bound_b, NULL);
        small += !jump, small_held += !jump && holds, jumps_held += jump && holds;
        if (!holds)
            continue;
        EXPECT_TRUE(bound_b <= 1 + 1e-9);
        double max_px;
        size_t samples;
        ASSERT_OK(tp_cut_measure_screen_error(cut, &b, &max_px, NULL, &samples, NULL));
        EXPECT_TRUE(samples > 0);
        EXPECT_TRUE(max_px <= 1 + 1e-9);
        ASSERT_OK(tp_cut_update(fresh, &b, &lp, NULL));
        for (int py = 4; py < 720; py += 24)
            for (int px = 4; px < 1280; px += 24) {
                double dir[3];
                tp_ray_hit hit;
                tp_camera_pixel_ray(&b, px, py, dir);
                ASSERT_OK(tp_cut_ray_cast(fresh, b.position, dir, &hit));
                if (!hit.hit)
                    continue;
                double gx, gy;
                tp_tree_world_to_grid(t, hit.position[0], hit.position[1], &gx, &gy);
                EXPECT_FALSE(isnan(tp_cut_drawn_height_at(cut, gx, gy)));
                covered++;
            }
    }
    printf("small moves: %d of %d reusable; jumps: %d of 20 reusable; %d pixels checked\n",
           small_held, small, jumps_held, covered);
    EXPECT_GT(small_held, small / 2); /* the test proves little if it refuses everything */
    EXPECT_EQ_INT(0, jumps_held);
    EXPECT_GT(covered, 1000);
    tp_cut_destroy(cut);
    tp_cut_destroy(fresh);
    tp_tree_destroy(t);
    free(h);
}

/* Whether cut a draws the nodes saved (node, level, neighbour levels), in order. */
static int cut_equal(const tp_cut* a, const tp_cut_node* saved, size_t saved_count)
{
    size_t n;
    const tp_cut_node* x = tp_cut_nodes(a, &n);
    if (n != saved_count)
        return 0;
    for (size_t i = 0; i < n; i++)
        if (x[i].node != saved[i].node || x[i].level != saved[i].level ||
            memcmp(x[i].nb, saved[i].nb, 4) != 0)
            return 0;
    return 1;
}

/* A cut carried to another camera (tp_cut_repair, the cut worker's frames between selections):
 * for random frames of a flight (moves of up to 40 m, turns of up to 10 degrees), some with
 * leaves missing when the cut was selected and half of those arriving before it is carried,
 * every carried cut asks only for nodes still missing; once everything is resident (the checks
 * read the samples) it holds from scratch for the new camera and is watertight; without
 * substituted nodes (which may exceed tau and leave holes, as in a selection) it measures
 * within tau, draws no more than a quarter more triangles than the selection from the roots,
 * and shows ground wherever that selection does. Carried to its own camera it is the same cut;
 * a jump is mostly refused (and holds when it is not); a requests-only cut is refused. */
TEST(a_carried_cut_holds_is_watertight_and_near_the_selection)
{
    LOAD_OR_SKIP(h, 250, 300, 700, 420);
    tp_tree* t = make_tree(h, 700, 420, 33);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int64_t first = g->first_node[0], leaves = (int64_t)g->node_cols[0] * g->node_rows[0];
    const uint16_t** gone = calloc((size_t)leaves, sizeof *gone);
    ASSERT_TRUE(gone != NULL);
    tp_cut *cut, *carried, *fresh;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    ASSERT_OK(tp_cut_create(t, &carried, NULL));
    ASSERT_OK(tp_cut_create(t, &fresh, NULL));
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    int tries = 0, done = 0, arrivals = 0, covered = 0, whole = 0, jumps = 0;
    int subst_carried = 0, subst_fresh = 0;
    double worst_ratio = 0;
    for (int it = 0; it < 60; it++) {
        double x = rnd() * (g->src_width - 1), y = rnd() * (g->src_height - 1);
        double above = 30 + rnd() * 1500, yaw = rnd() * 360, pitch = -5 - rnd() * 50;
        tp_camera a, b;
        camera_at(t, x, y, above, yaw, pitch, &a);
        double step = rnd() * 40, turn = (rnd() - 0.5) * 20, dir = yaw * 3.14159265358979 / 180;
        double pos[3] = {a.position[0] + step * sin(dir), a.position[1] + step * cos(dir),
                         a.position[2] + (rnd() - 0.5) * step * 0.2};
        tp_camera_from_pose(pos, yaw + turn, pitch + turn / 3, 60, 1280, 720, &b);
        int missing = it % 3 == 1; /* a third of the leaves missing at the selection */
        for (int64_t i = 0; missing && i < leaves; i++)
            if (rnd() < 0.33)
                gone[i] = tp_tree_samples(t, first + i), tp_tree_detach(t, first + i);
        lp.tau_px = it % 4 == 3 ? 3 : 1;
        ASSERT_OK(tp_cut_update(cut, &a, &lp, NULL));
        for (int64_t i = 0; missing && i < leaves; i++) /* half of them arrive */
            if (gone[i] && rnd() < 0.5)
                tp_tree_attach(t, first + i, gone[i]), gone[i] = NULL, arrivals++;
        tries++;
        int ok = tp_cut_repair(carried, cut, &b);
        if (ok) {
            size_t wanted;
            const int64_t* want = tp_cut_requests(carried, &wanted);
            for (size_t k = 0; k < wanted; k++)
                EXPECT_TRUE(tp_tree_samples(t, want[k]) == NULL);
            /* what arrived is drawn: no more substitution than a selection now makes */
            tp_cut_stats sc, sf;
            ASSERT_OK(tp_cut_update(fresh, &b, &lp, NULL));
            tp_cut_get_stats(carried, &sc);
            tp_cut_get_stats(fresh, &sf);
            subst_carried += sc.substituted, subst_fresh += sf.substituted;
        }
        for (int64_t i = 0; i < leaves; i++) /* the rest arrive */
            if (gone[i])
                tp_tree_attach(t, first + i, gone[i]), gone[i] = NULL;
        if (ok) {
            done++;
            double bound_px, max_px;
            size_t samples;
            EXPECT_TRUE(tp_cut_holds_for(carried, &b, &bound_px, NULL));
            EXPECT_EQ_INT(0, check_watertight(t, carried, NULL));
            tp_cut_stats sc, sf;
            tp_cut_get_stats(carried, &sc);
            ASSERT_OK(tp_cut_update(fresh, &b, &lp, NULL));
            tp_cut_get_stats(fresh, &sf);
            if (sc.substituted == 0) {
                whole++;
                EXPECT_TRUE(bound_px <= lp.tau_px + 1e-9);
                ASSERT_OK(tp_cut_measure_screen_error(carried, &b, &max_px, NULL, &samples, NULL));
                EXPECT_TRUE(max_px <= lp.tau_px + 1e-9);
                double ratio = (double)sc.triangles / (double)(sf.triangles + 1);
                worst_ratio = ratio > worst_ratio ? ratio : worst_ratio;
                EXPECT_TRUE(ratio <= 1.25);
            }
            for (int py = 4; py < 720 && sc.substituted == 0; py += 48)
                for (int px = 4; px < 1280; px += 48) {
                    double d[3], gx, gy;
                    tp_ray_hit hit;
                    tp_camera_pixel_ray(&b, px, py, d);
                    ASSERT_OK(tp_cut_ray_cast(fresh, b.position, d, &hit));
                    if (!hit.hit)
                        continue;
                    tp_tree_world_to_grid(t, hit.position[0], hit.position[1], &gx, &gy);
                    EXPECT_FALSE(isnan(tp_cut_drawn_height_at(carried, gx, gy)));
                    covered++;
                }
        }
        /* carried to its own camera, nothing changed: the same cut */
        ASSERT_OK(tp_cut_update(cut, &a, &lp, NULL));
        size_t count;
        const tp_cut_node* o = tp_cut_nodes(cut, &count);
        tp_cut_node* saved = malloc((count + 1) * sizeof *saved);
        ASSERT_TRUE(saved != NULL);
        memcpy(saved, o, count * sizeof *saved);
        EXPECT_TRUE(tp_cut_repair(carried, cut, &a));
        EXPECT_TRUE(cut_equal(carried, saved, count));
        free(saved);
        /* a jump (as Home): mostly a selection from the roots; when carried, it holds */
        tp_camera jump;
        camera_at(t, fmod(x + 350, g->src_width - 1), y, 1000, yaw + 120, -30, &jump);
        if (tp_cut_repair(carried, cut, &jump))
            EXPECT_TRUE(tp_cut_holds_for(carried, &jump, NULL, NULL));
        else
            jumps++;
        /* a cut selected for its requests only is not stitched: never carried */
        ASSERT_OK(tp_cut_update_requests(cut, &a, &lp, NULL));
        EXPECT_FALSE(tp_cut_repair(carried, cut, &a));
    }
    printf("carried %d of %d frames (%d leaves arrived between: %d nodes substituted, %d in "
           "the selections; %d without substituted nodes: triangles at most %.3f times the "
           "selection's, %d pixels checked); %d jumps refused\n",
           done, tries, arrivals, subst_carried, subst_fresh, whole, worst_ratio, covered, jumps);
    EXPECT_GT(subst_fresh, 0);
    EXPECT_TRUE(subst_carried <= subst_fresh + subst_fresh / 10);
    EXPECT_GT(done, tries * 2 / 3); /* the test proves little if it refuses everything */
    EXPECT_GT(jumps, tries * 3 / 4);
    EXPECT_GT(whole, 20);
    EXPECT_GT(arrivals, 100);
    EXPECT_GT(covered, 1000);
    free(gone);
    tp_cut_destroy(cut);
    tp_cut_destroy(carried);
    tp_cut_destroy(fresh);
    tp_tree_destroy(t);
    free(h);
}

/* ---- carried cuts, tried to break (tp_cut_repair) ---- */

/* The checks a carried cut (everything resident again) must pass for cam, as an update's:
 * it holds from scratch, it is watertight, and without substituted nodes it measures within
 * tau and shows ground wherever fresh (the selection from the roots for cam) does. Returns
 * the pixels checked. */
static int carried_holds(const tp_tree* t, const tp_cut* carried, tp_cut* fresh,
                         const tp_camera* cam, const tp_lod_params* lp, const char* what)
{
    double bound_px, max_px;
    size_t samples;
    int covered = 0, holes = 0;
    int holds = tp_cut_holds_for(carried, cam, &bound_px, NULL);
    int cracks = check_watertight(t, carried, NULL);
    tp_cut_stats sc;
    tp_cut_get_stats(carried, &sc);
    ASSERT_OK(tp_cut_update(fresh, cam, lp, NULL));
    if (sc.substituted == 0) {
        ASSERT_OK(tp_cut_measure_screen_error(carried, cam, &max_px, NULL, &samples, NULL));
        for (int py = 4; py < 720; py += 48)
            for (int px = 4; px < 1280; px += 48) {
                double d[3], gx, gy;
                tp_ray_hit hit;
                tp_camera_pixel_ray(cam, px, py, d);
                ASSERT_OK(tp_cut_ray_cast(fresh, cam->position, d, &hit));
                if (!hit.hit)
                    continue;
                tp_tree_world_to_grid(t, hit.position[0], hit.position[1], &gx, &gy);
                holes += isnan(tp_cut_drawn_height_at(carried, gx, gy));
                covered++;
            }
    } else
        bound_px = max_px = 0;
    if (!holds || cracks || bound_px > lp->tau_px + 1e-9 || max_px > lp->tau_px + 1e-9 || holes)
        fprintf(stderr, "%s: holds %d, %d cracks, bound %.3f px, measured %.3f px (tau %g), "
                "%d of %d pixels without ground\n", what, holds, cracks, bound_px, max_px,
                lp->tau_px, holes, covered);
    EXPECT_TRUE(holds);
    EXPECT_EQ_INT(0, cracks);
    EXPECT_TRUE(bound_px <= lp->tau_px + 1e-9);
    EXPECT_TRUE(max_px <= lp->tau_px + 1e-9);
    EXPECT_EQ_INT(0, holes);
    return covered;
}

/* The cut worker's way: a cut carried from the cut carried before, 16 times in a row, along
 * flights (low and 3 m over the ground: the near plane; fast turns; vertical scale 1 and 2.5;
 * hole_px 1 over voids; tau 1 and 3), a fifth of the leaves the cut does not draw detached
 * every second frame and attached again after it is carried, as the stream does. Every
 * carried cut asks only for what is missing, and once everything is resident holds as an
 * update's does (carried_holds); the cut before, where tp_cut_holds_for says it holds for the
 * new camera, is within tau too. Measured (printed): triangles against the selection's along
 * the chains, and the carried requests the selection would not make. (It found leaves at level
 * n whose sides moved onto a coarser neighbour carried above tau: cut_repair.c's
 * seams_again.) */
TEST(a_cut_carried_again_and_again_holds_along_a_flight)
{
    LOAD_OR_SKIP(h, 250, 300, 700, 420);
    tp_tree* t = make_tree(h, 700, 420, 33);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int64_t first = g->first_node[0], leaves = (int64_t)g->node_cols[0] * g->node_rows[0];
    const uint16_t** gone = calloc((size_t)leaves, sizeof *gone);
    ASSERT_TRUE(gone != NULL);
    tp_cut *cut[2], *fresh;
    ASSERT_OK(tp_cut_create(t, &cut[0], NULL));
    ASSERT_OK(tp_cut_create(t, &cut[1], NULL));
    ASSERT_OK(tp_cut_create(t, &fresh, NULL));
    int carries = 0, refused = 0, longest = 0, covered = 0, unwanted = 0, requests = 0;
    int fresh_requests = 0;
    double worst[3] = {0, 0, 0}, sum[3] = {0, 0, 0};
    int n_band[3] = {0, 0, 0};
    for (int flight = 0; flight < 8; flight++) {
        tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = flight % 3 == 2 ? 3 : 1,
                            .hole_px = flight % 4 == 1 ? 1 : 0};
        double zs = flight % 2 ? 2.5 : 1;
        ASSERT_OK(tp_cut_set_vertical_scale(cut[0], zs));
        ASSERT_OK(tp_cut_set_vertical_scale(cut[1], zs));
        ASSERT_OK(tp_cut_set_vertical_scale(fresh, zs));
        double x = 100 + rnd() * 500, y = 80 + rnd() * 260, yaw = rnd() * 360;
        double above = flight % 4 == 3 ? 3 : 20 + rnd() * 400, pitch = -3 - rnd() * 30;
        int front = 0, chain = 0;
        tp_camera cam;
        camera_scaled(t, x, y, above, yaw, pitch, zs, &cam);
        ASSERT_OK(tp_cut_update(cut[front], &cam, &lp, NULL));
        for (int f = 0; f < 40; f++) {
            double speed = 0.5 + rnd() * 3; /* grid samples: up to 315 m */
            yaw += f % 10 < 3 ? 6 : (rnd() - 0.5) * 2;
            x += speed * sin(yaw * 3.14159265358979 / 180);
            y -= speed * cos(yaw * 3.14159265358979 / 180);
            x = fmin(fmax(x, 5), 690), y = fmin(fmax(y, 5), 410);
            camera_scaled(t, x, y, above, yaw, pitch, zs, &cam);
            size_t nd; /* the stream drops some leaves the cut does not draw (a drawn one
                          detached: refused) */
            const tp_cut_node* drawn = tp_cut_nodes(cut[front], &nd);
            for (int64_t i = 0; f % 2 == 1 && i < leaves; i++)
                gone[i] = (const uint16_t*)(uintptr_t)(rnd() < 0.2);
            for (size_t k = 0; f % 2 == 1 && k < nd; k++)
                if (drawn[k].node >= first && drawn[k].node < first + leaves)
                    gone[drawn[k].node - first] = NULL;
            for (int64_t i = 0; f % 2 == 1 && i < leaves; i++)
                if (gone[i])
                    gone[i] = tp_tree_samples(t, first + i), tp_tree_detach(t, first + i);
            int ok = chain < 16 && tp_cut_repair(cut[!front], cut[front], &cam);
            if (!ok) {
                refused++, chain = 0;
                ASSERT_OK(tp_cut_update(cut[!front], &cam, &lp, NULL));
            } else {
                chain++, carries++;
                longest = chain > longest ? chain : longest;
                size_t wanted;
                const int64_t* want = tp_cut_requests(cut[!front], &wanted);
                for (size_t k = 0; k < wanted; k++)
                    EXPECT_TRUE(tp_tree_samples(t, want[k]) == NULL);
                size_t nf; /* measured: requests the selection would not make */
                ASSERT_OK(tp_cut_update(fresh, &cam, &lp, NULL));
                const int64_t* rf = tp_cut_requests(fresh, &nf);
                for (size_t k = 0; k < wanted; k++) {
                    int also = 0;
                    for (size_t l = 0; l < nf && !also; l++)
                        also = want[k] == rf[l];
                    unwanted += !also;
                }
                requests += (int)wanted, fresh_requests += (int)nf;
            }
            front = !front;
            for (int64_t i = 0; i < leaves; i++) /* they arrive again */
                if (gone[i])
                    tp_tree_attach(t, first + i, gone[i]), gone[i] = NULL;
            if (ok) {
                char what[96];
                snprintf(what, sizeof what, "flight %d frame %d (carry %d)", flight, f, chain);
                covered += carried_holds(t, cut[front], fresh, &cam, &lp, what);
                /* the cut before, kept instead (tp_cut_holds_for): within tau when it holds */
                double kept_px;
                tp_cut_stats sk;
                tp_cut_get_stats(cut[!front], &sk);
                if (tp_cut_holds_for(cut[!front], &cam, &kept_px, NULL) && sk.substituted == 0) {
                    if (kept_px > lp.tau_px + 1e-9)
                        fprintf(stderr, "%s: the cut before holds, its bound %.3f px (tau %g)\n",
                                what, kept_px, lp.tau_px);
                    EXPECT_TRUE(kept_px <= lp.tau_px + 1e-9);
                }
                /* measured, not asserted: how much finer than the selection a chain draws,
                   and how many of its requests the selection would not make */
                tp_cut_stats sc, sf;
                tp_cut_get_stats(cut[front], &sc);
                tp_cut_get_stats(fresh, &sf);
                double ratio = (double)sc.triangles / (double)(sf.triangles + 1);
                int band = chain <= 5 ? 0 : chain <= 10 ? 1 : 2;
                worst[band] = ratio > worst[band] ? ratio : worst[band];
                sum[band] += ratio, n_band[band]++;
            }
        }
    }
    printf("%d carries, %d refused, longest chain %d, %d pixels checked; triangles / the "
           "selection's after 1-5 carries: mean %.3f worst %.3f, 6-10: %.3f %.3f, 11-16: %.3f "
           "%.3f; %d of %d requests not the selection's (which made %d)\n", carries, refused,
           longest, covered, sum[0] / (n_band[0] + 1e-9), worst[0], sum[1] / (n_band[1] + 1e-9),
           worst[1], sum[2] / (n_band[2] + 1e-9), worst[2], unwanted, requests, fresh_requests);
    EXPECT_GT(carries, 100); /* the test proves little if it refuses everything */
    EXPECT_EQ_INT(16, longest);
    EXPECT_GT(covered, 1000);
    free(gone);
    tp_cut_destroy(cut[0]);
    tp_cut_destroy(cut[1]);
    tp_cut_destroy(fresh);
    tp_tree_destroy(t);
    free(h);
}

/* Roots missing at the selection (as when the viewer starts: the stream loads them first):
 * carried once they have arrived, the cut draws them (or is refused); a root out of view and
 * missing at the selection, in view and missing when carried, is asked for (or refused). */
TEST(a_carried_cut_takes_in_the_roots_that_arrived)
{
    LOAD_OR_SKIP(h, 250, 300, 700, 420);
    tp_tree* t = make_tree(h, 700, 420, 33);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int64_t* roots = malloc((size_t)g->root_count * sizeof *roots);
    const uint16_t** saved = calloc((size_t)g->root_count, sizeof *saved);
    ASSERT_TRUE(roots && saved);
    tp_tree_roots(g, roots, (size_t)g->root_count);
    ASSERT_GT((double)g->root_count, 1);
    tp_cut *cut, *carried, *fresh;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    ASSERT_OK(tp_cut_create(t, &carried, NULL));
    ASSERT_OK(tp_cut_create(t, &fresh, NULL));
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    tp_camera a, sky;
    camera_at(t, 350, 410, 3000, 0, -40, &a); /* the whole map ahead */
    /* every second root arrives after the selection */
    for (int64_t i = 0; i < g->root_count; i += 2)
        saved[i] = tp_tree_samples(t, roots[i]), tp_tree_detach(t, roots[i]);
    ASSERT_OK(tp_cut_update(cut, &a, &lp, NULL));
    for (int64_t i = 0; i < g->root_count; i++)
        if (saved[i])
            tp_tree_attach(t, roots[i], saved[i]), saved[i] = NULL;
    if (tp_cut_repair(carried, cut, &a))
        carried_holds(t, carried, fresh, &a, &lp, "roots arrived");
    /* all missing, the selection looking at the sky; carried to a view of the map */
    camera_at(t, 350, 410, 3000, 0, 30, &sky);
    for (int64_t i = 0; i < g->root_count; i++)
        saved[i] = tp_tree_samples(t, roots[i]), tp_tree_detach(t, roots[i]);
    ASSERT_OK(tp_cut_update(cut, &sky, &lp, NULL));
    size_t nreq, nfresh;
    tp_cut_requests(cut, &nreq);
    EXPECT_EQ_INT(0, (int)nreq);
    /* nothing arrived, nothing drawn: no reason to refuse (else the test proves nothing) */
    int carried_to_map = tp_cut_repair(carried, cut, &a);
    EXPECT_TRUE(carried_to_map);
    if (carried_to_map) {
        ASSERT_OK(tp_cut_update(fresh, &a, &lp, NULL));
        const int64_t* want = tp_cut_requests(carried, &nreq);
        const int64_t* need = tp_cut_requests(fresh, &nfresh);
        EXPECT_GT((double)nfresh, 0);
        int missed = 0;
        for (size_t k = 0; k < nfresh; k++) {
            int listed = 0;
            for (size_t l = 0; l < nreq; l++)
                listed |= want[l] == need[k];
            missed += !listed;
        }
        if (missed)
            fprintf(stderr, "carried to a view of the map: %d of the %zu roots in view and "
                    "missing not asked for\n", missed, nfresh);
        EXPECT_EQ_INT(0, missed);
    }
    for (int64_t i = 0; i < g->root_count; i++)
        tp_tree_attach(t, roots[i], saved[i]);
    free(roots);
    free(saved);
    tp_cut_destroy(cut);
    tp_cut_destroy(carried);
    tp_cut_destroy(fresh);
    tp_tree_destroy(t);
    free(h);
}

/* What is not an update's cut is not carried as one: a requests-only update (no stitching,
 * no output) and a cut whose vertical scale changed after its update are refused, or carried
 * to a cut that holds (carried_holds at the scale the carried cut has). */
TEST(a_carried_cut_is_carried_only_from_an_update)
{
    LOAD_OR_SKIP(h, 250, 300, 700, 420);
    tp_tree* t = make_tree(h, 700, 420, 33);
    tp_cut *cut, *carried, *fresh;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    ASSERT_OK(tp_cut_create(t, &carried, NULL));
    ASSERT_OK(tp_cut_create(t, &fresh, NULL));
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    tp_camera a;
    camera_at(t, 300, 300, 400, 20, -25, &a);
    int carried_ro = 0;
    for (int it = 0; it < 10; it++) {
        tp_camera r, b;
        random_camera(t, &r);
        b = r; /* a third nearer the ground it looks at */
        tp_ray_hit hit;
        ASSERT_OK(tp_cut_update(fresh, &r, &lp, NULL));
        ASSERT_OK(tp_cut_ray_cast(fresh, r.position, r.forward, &hit));
        if (!hit.hit)
            continue;
        for (int k = 0; k < 3; k++)
            b.position[k] += (hit.position[k] - r.position[k]) / 3;
        ASSERT_OK(tp_cut_update_requests(cut, &r, &lp, NULL));
        if (tp_cut_repair(carried, cut, &b)) {
            carried_ro++;
            carried_holds(t, carried, fresh, &b, &lp, "from a requests-only update");
        }
        ASSERT_OK(tp_cut_update(cut, &r, &lp, NULL)); /* the same from an update: it holds */
        if (tp_cut_repair(carried, cut, &b))
            carried_holds(t, carried, fresh, &b, &lp, "from an update");
    }
    printf("requests-only: carried %d of 10\n", carried_ro);
    ASSERT_OK(tp_cut_update(cut, &a, &lp, NULL));
    ASSERT_OK(tp_cut_set_vertical_scale(cut, 4));
    if (tp_cut_repair(carried, cut, &a)) {
        ASSERT_OK(tp_cut_set_vertical_scale(fresh, tp_cut_vertical_scale(carried)));
        carried_holds(t, carried, fresh, &a, &lp, "vertical scale changed after the update");
    }
    tp_cut_destroy(cut);
    tp_cut_destroy(carried);
    tp_cut_destroy(fresh);
    tp_tree_destroy(t);
    free(h);
}

/* Forests of roots of different scales (sizes not 2^n k + 1, small nodes): carried over random
 * moves of up to 200 m and 30 degrees from random views, each carried cut holds as an update's
 * (carried_holds). */
TEST(a_carried_cut_holds_over_forests_of_odd_sizes)
{
    const int sizes[][3] = {{18, 17, 17}, {49, 40, 17}, {70, 33, 17}, {131, 97, 33}, {300, 170, 17}};
    int carries = 0;
    for (int i = 0; i < 5; i++) {
        int w = sizes[i][0], hh = sizes[i][1];
        LOAD_OR_SKIP(h, 380, 380, w, hh);
        tp_tree* t = make_tree(h, w, hh, sizes[i][2]);
        tp_cut *cut, *carried, *fresh;
        ASSERT_OK(tp_cut_create(t, &cut, NULL));
        ASSERT_OK(tp_cut_create(t, &carried, NULL));
        ASSERT_OK(tp_cut_create(t, &fresh, NULL));
        for (int it = 0; it < 30; it++) {
            tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = it % 3 ? 0.5 : 2};
            double x = rnd() * (w - 1), y = rnd() * (hh - 1), yaw = rnd() * 360;
            double above = 5 + rnd() * 600, pitch = -5 - rnd() * 70;
            tp_camera a, b;
            camera_at(t, x, y, above, yaw, pitch, &a);
            double step = rnd() * 200, turn = (rnd() - 0.5) * 30, d = yaw * 3.14159265358979 / 180;
            double pos[3] = {a.position[0] + step * sin(d), a.position[1] + step * cos(d),
                             a.position[2]};
            tp_camera_from_pose(pos, yaw + turn, pitch, 60, 1280, 720, &b);
            ASSERT_OK(tp_cut_update(cut, &a, &lp, NULL));
            if (!tp_cut_repair(carried, cut, &b))
                continue;
            carries++;
            char what[64];
            snprintf(what, sizeof what, "%dx%d view %d", w, hh, it);
            carried_holds(t, carried, fresh, &b, &lp, what);
        }
        tp_cut_destroy(cut);
        tp_cut_destroy(carried);
        tp_cut_destroy(fresh);
        tp_tree_destroy(t);
        free(h);
    }
    printf("%d carried\n", carries);
    EXPECT_GT(carries, 40);
}

/* An island of real relief in a sea of voids, smaller than a coarse node's sample stride (the
 * coarse nodes over it have no own drawn samples: the selection culls such a node for having
 * no box when it does not refine it), hole_px 1000 (so that far away the selection leaves the
 * island out). Descending towards it from 60 km, each cut carried from the cut before, and the
 * cut before where tp_cut_holds_for says it holds, shows ground wherever the selection from
 * the roots does once the camera is below 1500 m: there every cell of a leaf drawn below level
 * n (1440 m) would leave a hole above 1000 px, and a node over the island kept unrefined holes
 * far wider. (Higher up, a leaf carried at level 0, which draws nothing of the island, holds
 * for tau and hole_px where the selection draws level n: both allowed.) */
TEST(a_carried_cut_finds_an_island_smaller_than_a_coarse_stride)
{
    LOAD_OR_SKIP(h, 300, 300, 257, 257);
    for (int y = 0; y < 257; y++) /* real heights on x, y in 97..103 (7 x 7); voids elsewhere */
        for (int x = 0; x < 257; x++)
            if (x < 97 || x > 103 || y < 97 || y > 103)
                h[(size_t)y * 257 + x] = NAN;
    tp_tree* t = make_tree(h, 257, 257, 17);
    tp_cut *cut[2], *fresh;
    ASSERT_OK(tp_cut_create(t, &cut[0], NULL));
    ASSERT_OK(tp_cut_create(t, &cut[1], NULL));
    ASSERT_OK(tp_cut_create(t, &fresh, NULL));
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1, .hole_px = 1000};
    int front = 0, carries = 0, kept = 0, checked = 0;
    tp_camera cam;
    camera_at(t, 100, 100, 60000, 0, -89, &cam);
    ASSERT_OK(tp_cut_update(cut[front], &cam, &lp, NULL));
    for (double above = 60000; above > 100; above *= 0.8) {
        camera_at(t, 100, 100, above, 0, -89, &cam);
        ASSERT_OK(tp_cut_update(fresh, &cam, &lp, NULL));
        int ok = tp_cut_repair(cut[!front], cut[front], &cam);
        if (!ok)
            ASSERT_OK(tp_cut_update(cut[!front], &cam, &lp, NULL));
        int holds = tp_cut_holds_for(cut[front], &cam, NULL, NULL); /* the cut before, kept */
        front = !front, carries += ok, kept += holds;
        for (int py = 300; py < 420 && above < 1500; py += 4)
            for (int px = 580; px < 700; px += 4) {
                double d[3], gx, gy;
                tp_ray_hit hit;
                tp_camera_pixel_ray(&cam, px, py, d);
                ASSERT_OK(tp_cut_ray_cast(fresh, cam.position, d, &hit));
                if (!hit.hit)
                    continue;
                checked++;
                tp_tree_world_to_grid(t, hit.position[0], hit.position[1], &gx, &gy);
                if (ok && isnan(tp_cut_drawn_height_at(cut[front], gx, gy))) {
                    fprintf(stderr, "%.0f m above: the carried cut shows no ground at (%.1f, "
                            "%.1f)\n", above, gx, gy);
                    EXPECT_TRUE(0);
                    py = px = 10000;
                }
                if (holds && isnan(tp_cut_drawn_height_at(cut[!front], gx, gy))) {
                    fprintf(stderr, "%.0f m above: the cut before holds but shows no ground at "
                            "(%.1f, %.1f)\n", above, gx, gy);
                    EXPECT_TRUE(0);
                    py = px = 10000;
                }
            }
    }
    printf("%d carried, %d kept, %d pixels on the island checked\n", carries, kept, checked);
    EXPECT_GT(checked, 100);
    tp_cut_destroy(cut[0]);
    tp_cut_destroy(cut[1]);
    tp_cut_destroy(fresh);
    tp_tree_destroy(t);
    free(h);
}

/* Random hand-made cuts: from the roots, split at random (deep on one side, shallow on the
 * other, so neighbours differ by up to the tree's depth in scale), random levels. */
static void random_cut(const tp_tree_geometry* g, int64_t node, double p_split, int64_t* nodes,
                       int* levels, size_t* count)
{
    int s, c, r;
    tp_tree_node_locate(g, node, &s, &c, &r);
    if (s > 0 && rnd() < p_split) {
        for (int q = 0; q < 4; q++)
            random_cut(g, tp_tree_node_child(g, node, q), q == 0 ? 0.9 : p_split * 0.6, nodes,
                       levels, count);
        return;
    }
    nodes[*count] = node;
    levels[*count] = (int)(rnd() * (g->n + 1));
    (*count)++;
}

/* tp_cut_set_nodes, and with a TIN cache, once more after building every level it asked for
 * (an installed cut draws each level's coarsest rung that stitches). */
static void set_nodes_tins(tp_cut* cut, tp_tin_cache* tins, const int64_t* nodes,
                           const int* levels, size_t count)
{
    ASSERT_OK(tp_cut_set_nodes(cut, nodes, levels, count, NULL));
    if (!tins)
        return;
    build_requested(cut, tins);
    ASSERT_OK(tp_cut_set_nodes(cut, nodes, levels, count, NULL));
}

static void adversarial_cuts(int add, int with_tins)
{
    /* 1025 x 1025 with n = 4: 64 x 64 leaves under one root of scale 6, so neighbours can
     * differ by more than n scales (split or collapse). */
    LOAD_OR_SKIP(h, 100, 100, 1025, 1025);
    fill_voids(h, 1025, 1025);
    tp_tree* t = make_tree(h, 1025, 1025, 17);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    tp_cut_set_stitch_add(cut, add);
    tp_tin_cache* tins = NULL;
    long tin_nodes = 0;
    if (with_tins) {
        ASSERT_OK(tp_tin_cache_create(t, &tins, NULL));
        tp_cut_set_tins(cut, tins);
    }
    long add_sides = 0;
    int64_t* nodes = malloc((size_t)g->node_count * sizeof *nodes);
    int* levels = malloc((size_t)g->node_count * sizeof *levels);
    int64_t roots[64];
    tp_tree_roots(g, roots, 64);
    uint8_t* covered = malloc((size_t)g->width * g->height);
    uint8_t* keep = malloc((size_t)g->node_count);
    const uint16_t** saved = calloc((size_t)g->node_count, sizeof *saved);
    int collapses = 0;
    for (int it = 0; it < 80; it++) {
        size_t count = 0;
        for (int64_t ri = 0; ri < g->root_count; ri++)
            random_cut(g, roots[ri], 0.95, nodes, levels, &count);
        if (it % 2) {
            /* Detach a third of the nodes neither drawn nor above a drawn one, so that splits
             * fail and the stitching pass collapses instead (onto resident ancestors). */
            memset(keep, 0, (size_t)g->node_count);
            for (size_t i = 0; i < count; i++)
                for (int64_t p = tp_tree_node_parent(g, nodes[i]); p >= 0;
                     p = tp_tree_node_parent(g, p))
                    keep[p] = 1; /* above a drawn node */
            for (size_t i = 0; i < count; i++)
                keep[nodes[i]] = 2;
            for (int64_t id = 0; id < g->node_count; id++)
                if (!keep[id] && rnd() < 0.33) {
                    saved[id] = tp_tree_samples(t, id);
                    tp_tree_detach(t, id);
                }
        }
        set_nodes_tins(cut, tins, nodes, levels, count);
        size_t drawn;
        const tp_cut_node* out = tp_cut_nodes(cut, &drawn);
        ASSERT_GT((double)drawn, 0);
        for (size_t i = 0; it % 2 && i < drawn; i++) {
            collapses += keep[out[i].node] == 1; /* drawn above installed nodes */
            EXPECT_TRUE(tp_tree_samples(t, out[i].node) != NULL);
        }
        /* Levels only go up. */
        for (size_t i = 0; i < drawn; i++)
            for (size_t j = 0; j < count; j++)
                if (nodes[j] == out[i].node)
                    EXPECT_GE_INT(out[i].level, levels[j]);
        int f = check_watertight(t, cut, covered);
        EXPECT_EQ_INT(0, f);
        /* The stats' triangles (a table by level and neighbour levels) are the drawn ones. */
        tp_cut_stats st;
        tp_cut_get_stats(cut, &st);
        EXPECT_EQ_INT((int)last_triangles, (int)st.triangles);
        add_sides += st.add_sides;
        tin_nodes += st.tin_nodes;
        /* The whole map stays covered (the crop has no voids). */
        size_t gaps = 0;
        for (int y = 0; y < 1025; y++)
            for (int x = 0; x < 1025; x++)
                gaps += !covered[(size_t)y * g->width + x];
        EXPECT_EQ_INT(0, (int)gaps);
        for (int64_t id = 0; id < g->node_count; id++)
            if (saved[id]) {
                tp_tree_attach(t, id, saved[id]);
                saved[id] = NULL;
            }
    }
    printf("random cuts: %d nodes collapsed onto\n", collapses);
    EXPECT_GT(collapses, 0);
    free(keep);
    free(saved);
    /* Every configuration of one node of scale 1 against its 4 neighbours: each neighbour
     * region drawn as one node of scale 1 at level 0 or n, or as scale-0 nodes, plus a
     * scale-5 neighbour next to a leaf (n + 1 apart). */
    int64_t center = tp_tree_node_id(g, 1, 10, 10);
    for (int conf = 0; conf < 81; conf++) {
        size_t count = 0;
        int code = conf;
        uint8_t taken[4] = {0};
        for (int side = 0; side < 4; side++, code /= 3) {
            static const int dc[4] = {0, 1, 0, -1}, dr[4] = {-1, 0, 1, 0};
            int64_t nbn = tp_tree_node_id(g, 1, 10 + dc[side], 10 + dr[side]);
            if (code % 3 < 2) {
                nodes[count] = nbn;
                levels[count++] = code % 3 ? g->n : 0;
            } else
                for (int q = 0; q < 4; q++) {
                    nodes[count] = tp_tree_node_child(g, nbn, q);
                    levels[count++] = q;
                }
            taken[side] = 1;
        }
        (void)taken;
        for (int lv = 0; lv <= g->n; lv++) {
            size_t c2 = count;
            nodes[c2] = center;
            levels[c2++] = lv;
            set_nodes_tins(cut, tins, nodes, levels, c2);
            EXPECT_EQ_INT(0, check_watertight(t, cut, NULL));
            tp_cut_stats st;
            tp_cut_get_stats(cut, &st);
            EXPECT_EQ_INT((int)last_triangles, (int)st.triangles);
            add_sides += st.add_sides;
            tin_nodes += st.tin_nodes;
        }
    }
    {
        /* A leaf (scale 0) next to a scale-5 node at level 0: split, or collapse. */
        size_t count = 0;
        int64_t big = tp_tree_node_id(g, 5, 1, 0);
        nodes[count] = big, levels[count++] = 0;
        nodes[count] = tp_tree_node_id(g, 5, 0, 1), levels[count++] = 0;
        nodes[count] = tp_tree_node_id(g, 5, 1, 1), levels[count++] = 0;
        int64_t q = tp_tree_node_id(g, 5, 0, 0);
        for (int s = 5; s > 0; s--) { /* down to the leaf in the top-right corner */
            for (int k = 0; k < 4; k++)
                if (k != 1)
                    nodes[count] = tp_tree_node_child(g, q, k), levels[count++] = 0;
            q = tp_tree_node_child(g, q, 1);
        }
        nodes[count] = q, levels[count++] = g->n;
        for (int resident = 1; resident >= 0; resident--) {
            /* Without the big node's children the leaf's ancestor of scale 5 - n is drawn. */
            const uint16_t* kept[4];
            for (int k = 0; k < 4; k++) {
                int64_t ch = tp_tree_node_child(g, big, k);
                kept[k] = tp_tree_samples(t, ch);
                if (!resident)
                    tp_tree_detach(t, ch);
            }
            ASSERT_OK(tp_cut_set_nodes(cut, nodes, levels, count, NULL));
            EXPECT_EQ_INT(0, check_watertight(t, cut, covered));
            size_t gaps = 0;
            for (int y = 0; y < 1025; y++)
                for (int x = 0; x < 1025; x++)
                    gaps += !covered[(size_t)y * g->width + x];
            EXPECT_EQ_INT(0, (int)gaps);
            size_t drawn;
            const tp_cut_node* out = tp_cut_nodes(cut, &drawn);
            int has_big = 0, has_collapsed = 0;
            for (size_t i = 0; i < drawn; i++) {
                has_big |= out[i].node == big;
                has_collapsed |=
                    out[i].node == tp_tree_node_id(g, 5 - g->n, (32 >> (5 - g->n)) - 1, 0);
            }
            EXPECT_EQ_INT(!resident, has_big);
            EXPECT_EQ_INT(!resident, has_collapsed);
            for (int k = 0; k < 4; k++)
                tp_tree_attach(t, tp_tree_node_child(g, big, k), kept[k]);
        }
    }
    free(covered);
    free(nodes);
    free(levels);
    tp_cut_destroy(cut);
    tp_tin_cache_destroy(tins);
    tp_tree_destroy(t);
    free(h);
    printf("%s%s: %ld sides took vertices, %ld nodes drawn as TINs\n",
           add ? "--stitch add" : "vertex moving", with_tins ? ", TIN nodes" : "", add_sides,
           tin_nodes);
    if (add)
        EXPECT_GT((double)add_sides, 1000);
    if (with_tins)
        EXPECT_GT((double)tin_nodes, 10000);
}

TEST(watertight_for_adversarial_cuts)
{
    adversarial_cuts(0, 0);
}

/* The same with TIN nodes: each drawn level's coarsest rung that stitches, against lattice
 * and TIN neighbours of any size and level. */
TEST(watertight_for_adversarial_cuts_with_tin_nodes)
{
    adversarial_cuts(0, 1);
}

/* The same cuts and configurations with --stitch add: same-size neighbours, several levels
 * apart, next to larger nodes that still move the smaller ones' vertices. */
TEST(watertight_for_adversarial_cuts_stitch_add)
{
    adversarial_cuts(1, 0);
}

/* Error mode holds tau on the measured screen error (tp_cut_measure_screen_error: the
 * triangles drawn, added vertices included with --stitch add). */
static void screen_error(int add, int with_tins)
{
    LOAD_OR_SKIP(h, 300, 200, 800, 700);
    tp_tree* t = make_tree(h, 800, 700, 17);
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    tp_cut_set_stitch_add(cut, add);
    tp_tin_cache* tins = NULL;
    long tin_nodes = 0;
    size_t tris_lattice = 0, tris_tin = 0;
    if (with_tins) {
        ASSERT_OK(tp_tin_cache_create(t, &tins, NULL));
        tp_cut_set_tins(cut, tins);
    }
    const double taus[] = {0.5, 1, 4};
    double worst_ratio = 0;
    size_t total = 0;
    long adds = 0;
    for (int it = 0; it < 30; it++) {
        tp_camera cam;
        random_camera(t, &cam);
        tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = taus[it % 3]};
        if (tins) { /* the same view as lattices: what the TINs save */
            tp_cut_set_tins(cut, NULL);
            ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
            tp_cut_stats ls;
            tp_cut_get_stats(cut, &ls);
            tris_lattice += ls.triangles;
            tp_cut_set_tins(cut, tins);
        }
        update_tins(cut, tins, &cam, &lp);
        double max_px = -1, rms_px;
        size_t samples, skipped;
        ASSERT_OK(tp_cut_measure_screen_error(cut, &cam, &max_px, &rms_px, &samples, &skipped));
        EXPECT_EQ_INT(0, (int)skipped);
        EXPECT_LE(max_px, lp.tau_px + 1e-6);
        tp_cut_stats st;
        tp_cut_get_stats(cut, &st);
        EXPECT_EQ_INT(0, st.substituted);
        EXPECT_LE(st.max_bound_px, lp.tau_px + 1e-6);
        adds += st.add_sides;
        tin_nodes += st.tin_nodes;
        tris_tin += st.triangles;
        worst_ratio = fmax(worst_ratio, max_px / lp.tau_px);
        total += samples;
    }
    EXPECT_GT((double)total, 1e5); /* the views see the terrain */
    printf("worst measured / tau: %.3f over %zu samples\n", worst_ratio, total);
    if (tins) {
        printf("TIN nodes: %ld drawn; %zu triangles against %zu as lattices (%.1f%%)\n",
               tin_nodes, tris_tin, tris_lattice, 100.0 * tris_tin / tris_lattice);
        EXPECT_GT((double)tin_nodes, 300);
        EXPECT_LT((double)tris_tin, 0.8 * (double)tris_lattice);
        tp_cut_set_tins(cut, NULL); /* the exaggerated views below: lattices */
    }
    /* Exaggerated 3x: tau still holds on screen. */
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_cut_set_vertical_scale(cut, 0));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_cut_set_vertical_scale(cut, NAN));
    ASSERT_OK(tp_cut_set_vertical_scale(cut, 3));
    int too_coarse = 0;
    for (int it = 0; it < 10; it++) {
        tp_camera cam;
        random_camera(t, &cam);
        cam.position[2] *= 3; /* above the exaggerated surface */
        tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
        /* The cut of the plain surface, measured exaggerated (the scale takes effect at the
         * next update), shows what the scale changes; the exaggerated cut holds tau. */
        ASSERT_OK(tp_cut_set_vertical_scale(cut, 1));
        ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
        ASSERT_OK(tp_cut_set_vertical_scale(cut, 3));
        double plain_px = -1, max_px = -1;
        ASSERT_OK(tp_cut_measure_screen_error(cut, &cam, &plain_px, NULL, NULL, NULL));
        too_coarse += plain_px > lp.tau_px;
        ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
        tp_cut_stats st;
        tp_cut_get_stats(cut, &st);
        ASSERT_OK(tp_cut_measure_screen_error(cut, &cam, &max_px, NULL, NULL, NULL));
        EXPECT_LE(max_px, lp.tau_px + 1e-6);
        EXPECT_LE(st.max_bound_px, lp.tau_px + 1e-6);
        /* Heights stay true. */
        size_t count;
        const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
        if (count) {
            tp_vertex v[17 * 17];
            tp_cut_vertices(cut, 0, v, 17 * 17);
            if (!isnan(v[0].z_m))
                EXPECT_EQ_DBL(v[0].z_m, tp_tree_sample(t, v[0].x, v[0].y));
            (void)nodes;
        }
    }
    EXPECT_GT(too_coarse, 0); /* some plain cuts are too coarse for 3x the relief */
    printf("%s: %ld sides took vertices\n", add ? "--stitch add" : "vertex moving", adds);
    if (add)
        EXPECT_GT((double)adds, 30);
    tp_cut_destroy(cut);
    tp_tin_cache_destroy(tins);
    tp_tree_destroy(t);
    free(h);
}

TEST(screen_error_within_tau)
{
    screen_error(0, 0);
}

TEST(screen_error_within_tau_with_tin_nodes)
{
    screen_error(0, 1);
}

TEST(screen_error_within_tau_stitch_add)
{
    screen_error(1, 0);
}

/* Drawn nodes of the last update that are incomplete, and of those, how many lie above the
 * leaves (scale >= 1) or below their finest level. */
static void count_incomplete(const tp_tree* t, const tp_cut* cut, int* incomplete, int* collapsed)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    size_t count;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    *incomplete = *collapsed = 0;
    for (size_t i = 0; i < count; i++) {
        if (tp_tree_meta(t, nodes[i].node)->flags & TP_NODE_COMPLETE)
            continue;
        int s, c, r;
        tp_tree_node_locate(g, nodes[i].node, &s, &c, &r);
        (*incomplete)++;
        *collapsed += s > 0 || nodes[i].level < g->n;
    }
}

/* The whole SRTM tile with its voids (some hundreds of samples wide in the high Pyrenees),
 * seen from far: nodes over a void's edge collapse like the others instead of staying leaves
 * at full resolution, tau still holds, no crack, and holes stay within a cell. With holes
 * forbidden (what the export asks), every incomplete node drawn is a leaf at level n. */
TEST(incomplete_nodes_collapse_far_away)
{
    LOAD_OR_SKIP(h, 0, 0, 1201, 1201);
    size_t voids = 0;
    for (size_t i = 0; i < (size_t)1201 * 1201; i++)
        voids += isnan(h[i]);
    ASSERT_TRUE(voids > 1000); /* the raw tile has its voids */
    tp_tree* t = make_tree(h, 1201, 1201, 17);
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    const double heights[] = {8000, 30000, 80000};
    int collapsed_total = 0;
    for (int v = 0; v < 3; v++) {
        tp_camera cam; /* from the south-west corner, looking north-east over the tile */
        camera_at(t, 100, 1100, heights[v], 45, -35, &cam);
        tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
        for (int hp = 1; getenv("TP_HOLE_SWEEP") && hp <= 16; hp *= 2) {
            lp.hole_px = hp;
            ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
            int i2, c2;
            count_incomplete(t, cut, &i2, &c2);
            tp_cut_stats s2;
            tp_cut_get_stats(cut, &s2);
            printf("hole %2d px: %d nodes (%d incomplete, %d collapsed), %zu triangles\n", hp,
                   s2.drawn, i2, c2, s2.triangles);
        }
        lp.hole_px = 0;
        ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
        int inc, col;
        count_incomplete(t, cut, &inc, &col);
        tp_cut_stats st;
        tp_cut_get_stats(cut, &st);
        double max_px = -1;
        ASSERT_OK(tp_cut_measure_screen_error(cut, &cam, &max_px, NULL, NULL, NULL));
        EXPECT_LE(max_px, lp.tau_px + 1e-6);
        EXPECT_EQ_INT(0, check_watertight(t, cut, NULL));
        /* holes forbidden: the old cut, every incomplete node a leaf at level n */
        lp.hole_px = 1e-300;
        ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
        int inc_exact, col_exact;
        count_incomplete(t, cut, &inc_exact, &col_exact);
        tp_cut_stats ex;
        tp_cut_get_stats(cut, &ex);
        EXPECT_EQ_INT(0, col_exact);
        EXPECT_GE(inc_exact, inc);
        EXPECT_GE(ex.drawn, st.drawn);
        EXPECT_EQ_INT(0, check_watertight(t, cut, NULL));
        printf("%6.0f m up: %d nodes drawn (%d incomplete, %d of them collapsed), %zu "
               "triangles; holes forbidden: %d nodes (%d incomplete), %zu triangles; "
               "measured %.3f px\n",
               heights[v], st.drawn, inc, col, st.triangles, ex.drawn, inc_exact, ex.triangles,
               max_px);
        collapsed_total += col;
    }
    EXPECT_GT(collapsed_total, 0);
    tp_lod_params bad = {.mode = TP_LOD_ERROR, .hole_px = -1};
    tp_camera cam;
    camera_at(t, 100, 1100, 8000, 45, -35, &cam);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_cut_update(cut, &cam, &bad, NULL));
    bad.hole_px = NAN;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_cut_update(cut, &cam, &bad, NULL));
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
    free(h);
}

TEST(substitution_keeps_the_surface_whole)
{
    LOAD_OR_SKIP(h, 0, 0, 1201, 1201);
    fill_voids(h, 1201, 1201);
    tp_tree* t = make_tree(h, 1201, 1201, 17);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    size_t cells = (size_t)g->width * g->height;
    uint8_t* full_cov = malloc(cells);
    uint8_t* sub_cov = malloc(cells);
    const uint16_t** saved = calloc((size_t)g->node_count, sizeof *saved);
    for (int it = 0; it < 6; it++) {
        /* High above the middle, looking down: the whole tile in view. */
        tp_camera cam;
        camera_at(t, 600, 600, 110000 + 20000 * it, 0, -90, &cam);
        tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 0.5};
        ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
        size_t full_count;
        const tp_cut_node* fn = tp_cut_nodes(cut, &full_count);
        tp_cut_node* full = malloc(full_count * sizeof *full);
        memcpy(full, fn, full_count * sizeof *full);
        ASSERT_EQ_INT(0, check_watertight(t, cut, full_cov));
        tp_cut_stats st;
        tp_cut_get_stats(cut, &st);
        ASSERT_EQ_INT(0, st.culled);
        /* Detach a random third of the non-root nodes. */
        int detached = 0;
        for (int64_t id = 0; id < g->node_count; id++)
            if (tp_tree_node_parent(g, id) >= 0 && rnd() < 0.33) {
                saved[id] = tp_tree_samples(t, id);
                tp_tree_detach(t, id);
                detached++;
            }
        ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
        EXPECT_EQ_INT(0, check_watertight(t, cut, sub_cov));
        EXPECT_EQ_INT(0, memcmp(full_cov, sub_cov, cells));
        tp_cut_get_stats(cut, &st);
        EXPECT_GT(st.substituted, 0);
        size_t measured, skipped;
        ASSERT_OK(tp_cut_measure_screen_error(cut, &cam, NULL, NULL, &measured, &skipped));
        EXPECT_GT((double)skipped, 0); /* detached leaves cannot be measured */
        EXPECT_GT((double)measured, 0);
        size_t count, nreq;
        const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
        const int64_t* req = tp_cut_requests(cut, &nreq);
        EXPECT_EQ_INT(st.requests, (int)nreq);
        for (size_t i = 0; i < count; i++) {
            EXPECT_TRUE(tp_tree_samples(t, nodes[i].node) != NULL);
            if (!nodes[i].substituted)
                continue;
            int s, c, r;
            tp_tree_node_locate(g, nodes[i].node, &s, &c, &r);
            ASSERT_GT(s, 0);
            int missing = 0;
            for (int q = 0; q < 4; q++) {
                int64_t ch = tp_tree_node_child(g, nodes[i].node, q);
                if (tp_tree_samples(t, ch))
                    continue;
                missing++;
                int listed = 0;
                for (size_t k = 0; k < nreq; k++)
                    listed |= req[k] == ch;
                EXPECT_TRUE(listed);
            }
            EXPECT_GT(missing, 0);
        }
        for (size_t k = 0; k < nreq; k++)
            EXPECT_TRUE(tp_tree_samples(t, req[k]) == NULL);
        /* Re-attach: the full cut again, nothing requested. */
        for (int64_t id = 0; id < g->node_count; id++)
            if (saved[id]) {
                tp_tree_attach(t, id, saved[id]);
                saved[id] = NULL;
            }
        ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
        EXPECT_TRUE(cut_equal(cut, full, full_count));
        tp_cut_requests(cut, &nreq);
        EXPECT_EQ_INT(0, (int)nreq);
        if (it == 0)
            printf("substitution: %d detached, %d drawn -> %d drawn, %d substituted, %d "
                   "requests\n",
                   detached, (int)full_count, st.drawn, st.substituted, st.requests);
        free(full);
    }
    free(saved);
    free(full_cov);
    free(sub_cov);
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
    free(h);
}

static double now_s(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Update time (ms, best of a few) and stats of one view. */
static double time_view(tp_cut* cut, const tp_camera* cam, const tp_lod_params* lp,
                        tp_cut_stats* st)
{
    double best = INFINITY;
    for (int i = 0; i < 5; i++) {
        double t0 = now_s();
        ASSERT_OK(tp_cut_update(cut, cam, lp, NULL));
        best = fmin(best, now_s() - t0);
    }
    tp_cut_get_stats(cut, st);
    return best * 1e3;
}

TEST(cost_does_not_grow_with_the_map)
{
    LOAD_OR_SKIP(h, 0, 0, 1201, 1201);
    /* Voids filled: an incomplete node is refined down to its leaves at any distance (only
     * complete nodes are drawn coarse), so the tile's ~7600 void samples, mirrored 16 times,
     * would put leaves all over the far terrain. */
    fill_voids(h, 1201, 1201);
    /* 4801 x 4801: the tile mirrored 4 x 4 (continuous across the seams), tile (0, 0) as is. */
    const int W = 4801;
    float* big = malloc((size_t)W * W * sizeof *big);
    for (int y = 0; y < W; y++) {
        int ty = y % 2400, sy = ty <= 1200 ? ty : 2400 - ty;
        for (int x = 0; x < W; x++) {
            int tx = x % 2400, sx = tx <= 1200 ? tx : 2400 - tx;
            big[(size_t)y * W + x] = h[(size_t)sy * 1201 + sx];
        }
    }
    tp_tree* small_t = make_tree(h, 1201, 1201, 17);
    tp_tree* big_t = make_tree(big, W, W, 17);
    free(big);
    tp_cut *cs, *cb;
    ASSERT_OK(tp_cut_create(small_t, &cs, NULL));
    ASSERT_OK(tp_cut_create(big_t, &cb, NULL));
    /* Hovering 500 m above sample (600, 600), looking at the horizon in 4 directions; 3 setups:
     * error mode with a 40 km far plane (both maps show the same terrain: the big one's tile
     * (0, 0) is the small one), distance mode without a far plane (the big map shows 8x deeper
     * terrain), and error mode without a far plane (reported only: see below). */
    const double yaws[] = {45, 135, 225, 315};
    for (int m = 0; m < 3; m++)
        for (int i = 0; i < 4; i++) {
            tp_camera cam_s, cam_b;
            camera_at(small_t, 600, 600, 500, yaws[i], -2, &cam_s);
            camera_at(big_t, 600, 600, 500, yaws[i], -2, &cam_b);
            if (m == 0)
                cam_s.far_m = cam_b.far_m = 40000;
            tp_lod_params lp = {.mode = m == 1 ? TP_LOD_DISTANCE : TP_LOD_ERROR, .tau_px = 1};
            tp_cut_stats ss, sb;
            double ms_s = time_view(cs, &cam_s, &lp, &ss);
            double ms_b = time_view(cb, &cam_b, &lp, &sb);
            printf("%-14s yaw %3.0f: 1201^2: visited %5d drawn %5d %7.3f ms | 4801^2: visited "
                   "%5d drawn %5d %7.3f ms\n",
                   m == 0   ? "error far40km"
                   : m == 1 ? "distance"
                            : "error",
                   yaws[i], ss.visited, ss.drawn, ms_s, sb.visited, sb.drawn, ms_b);
            /* Nearly the same terrain in view: the big map adds the 2 scales of nodes above
             * the small map's root, and what the frustum's far corners (40 km away, +-46
             * degrees) reach past the small tile's edges (54 km from the eye): a fixed part
             * of the view, so a fixed number of nodes whatever the map's size. Measured: +8
             * (looking off both maps) to +100 (looking across the tile's corner). */
            if (m == 0)
                EXPECT_LE(sb.visited, ss.visited + 250);
            /* Distance mode: beyond maxdist the stride doubles with the distance, so each
             * doubling of the view's depth adds one ring of nodes of a fixed count (their
             * size grows with the distance as the ring does); the big map is 8x deeper
             * here: 3 rings, plus the 2 extra scales of roots. */
            if (m == 1)
                EXPECT_LE(sb.visited, ss.visited + 150);
            /* Error mode without a far plane has no such bound: the Pyrenees' relief 400 km
             * away still projects above 1 px for nodes of 1-3 km, so the cut grows with the
             * visible terrain (not with the map: yaw 315 looks off both maps and is equal). */
            EXPECT_GT(sb.visited, 0);
        }
    printf("leaves: %d x %d vs %d x %d\n", tp_tree_get_geometry(small_t)->cols,
           tp_tree_get_geometry(small_t)->rows, tp_tree_get_geometry(big_t)->cols,
           tp_tree_get_geometry(big_t)->rows);
    tp_cut_destroy(cs);
    tp_cut_destroy(cb);
    tp_tree_destroy(small_t);
    tp_tree_destroy(big_t);
    free(h);
}

typedef struct height_probe {
    const tp_cut* cut;
    size_t count;
    double max_diff;
} height_probe;

static void probe(int x, int y, double z, void* user)
{
    height_probe* hp = user;
    double d = fabs(tp_cut_drawn_height_at(hp->cut, x, y) - z);
    hp->max_diff = isnan(d) ? INFINITY : fmax(hp->max_diff, d);
    hp->count++;
}

static height_probe probe_cut(const tp_cut* cut)
{
    height_probe hp = {cut, 0, 0};
    size_t count;
    tp_cut_nodes(cut, &count);
    tp_vertex v[17 * 17];
    uint32_t tri[2 * 16 * 16 * 3];
    for (size_t i = 0; i < count; i++) {
        tp_cut_vertices(cut, i, v, 17 * 17);
        size_t nt = tp_cut_triangles(cut, i, v, tri, 2 * 16 * 16);
        for (size_t j = 0; j < nt; j++) {
            const tp_vertex *a = &v[tri[3 * j]], *b = &v[tri[3 * j + 1]], *c = &v[tri[3 * j + 2]];
            int32_t pa[2] = {a->x, a->y}, pb[2] = {b->x, b->y}, pc[2] = {c->x, c->y};
            tp_triangle_rasterize(pa, pb, pc, a->z_m, b->z_m, c->z_m, probe, &hp);
        }
    }
    return hp;
}

TEST(drawn_height_follows_the_triangles)
{
    LOAD_OR_SKIP(h, 500, 500, 300, 300);
    tp_tree* t = make_tree(h, 300, 300, 17);
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    tp_camera cam;
    camera_at(t, 20, 20, 200, 135, -20, &cam);
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 2};
    ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
    size_t count;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    ASSERT_GT((double)count, 0);
    /* Every vertex of every drawn node: the drawn height there is the vertex's height. */
    size_t checked = 0;
    tp_vertex v[17 * 17];
    for (size_t i = 0; i < count; i++) {
        int vs = (1 << nodes[i].level) + 1;
        tp_cut_vertices(cut, i, v, 17 * 17);
        for (int j = 0; j < vs * vs; j++) {
            if (isnan(v[j].z_m) || v[j].cls != TP_SAMPLE_VALID)
                continue;
            double z = tp_cut_drawn_height_at(cut, v[j].x, v[j].y);
            EXPECT_NEAR(v[j].z_m, z, 1e-3);
            checked++;
        }
    }
    EXPECT_GT((double)checked, 100);
    /* Every sample under every drawn triangle: the drawn height is the triangle's. */
    height_probe hp = probe_cut(cut);
    EXPECT_GT((double)hp.count, 10000);
    EXPECT_LE(hp.max_diff, 1e-3);
    int stitched = 0; /* the view has moved vertices: the border strips are searched */
    for (size_t i = 0; i < count; i++)
        for (int side = 0; side < 4; side++)
            stitched += nodes[i].nb[side] >= 0;
    EXPECT_GT(stitched, 0);
    EXPECT_LE(hp.max_diff, 1e-3);
    /* A leaf at level n between neighbours at level 0 (vertices moved by up to 8 cells) and
     * a node of scale 1 at level 1 below it. */
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int64_t hand[5] = {tp_tree_node_id(g, 0, 1, 1), tp_tree_node_id(g, 0, 0, 1),
                       tp_tree_node_id(g, 0, 2, 1), tp_tree_node_id(g, 0, 1, 0),
                       tp_tree_node_id(g, 1, 0, 1)};
    int hand_levels[5] = {g->n, 0, 0, 0, 1};
    ASSERT_OK(tp_cut_set_nodes(cut, hand, hand_levels, 4, NULL));
    hp = probe_cut(cut);
    EXPECT_GT((double)hp.count, 300);
    EXPECT_LE(hp.max_diff, 1e-3);
    hand[0] = tp_tree_node_id(g, 0, 1, 0), hand[1] = tp_tree_node_id(g, 0, 0, 0);
    hand[2] = tp_tree_node_id(g, 0, 2, 0), hand[3] = tp_tree_node_id(g, 0, 3, 0);
    hand[4] = tp_tree_node_id(g, 1, 0, 1);
    int hl2[5] = {g->n, 0, 0, 2, 0};
    ASSERT_OK(tp_cut_set_nodes(cut, hand, hl2, 5, NULL));
    hp = probe_cut(cut);
    EXPECT_GT((double)hp.count, 300);
    EXPECT_LE(hp.max_diff, 1e-3);
    EXPECT_NAN(tp_cut_drawn_height_at(cut, -1, 5));
    EXPECT_NAN(tp_cut_drawn_height_at(cut, 100, 100)); /* not in the hand-made cut */
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
    free(h);
}

/* The distance mode as tp_cut_update documents it: log2 of the stride asked for at d. */
static int asked_stride_log(int n, double d, double mindist, double maxdist)
{
    if (d > maxdist)
        return n + (int)floor(log2(d / maxdist));
    int k;
    ASSERT_OK(tp_lod_level_distance(n, d, mindist, maxdist, 1, &k, NULL));
    return n - k;
}

TEST(distance_mode_never_coarser_than_asked)
{
    LOAD_OR_SKIP(h, 0, 0, 1201, 1201);
    fill_voids(h, 1201, 1201); /* incomplete nodes are refined whatever the distance */
    tp_tree* t = make_tree(h, 1201, 1201, 17);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    const double leaf_m = 16 * 90.0;
    int coarse = 0, levels_below_n = 0;
    for (int it = 0; it < 20; it++) {
        tp_camera cam;
        random_camera(t, &cam);
        tp_lod_params lp = {.mode = TP_LOD_DISTANCE};
        if (it % 2) /* explicit, short distances: far terrain in big nodes */
            lp.mindist_m = 500, lp.maxdist_m = 4000;
        double mind = it % 2 ? 500 : leaf_m, maxd = it % 2 ? 4000 : 24 * leaf_m;
        ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
        size_t count;
        const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
        for (size_t i = 0; i < count; i++) {
            int sc, c, r;
            tp_tree_node_locate(g, nodes[i].node, &sc, &c, &r);
            const tp_node_meta* m = tp_tree_meta(t, nodes[i].node);
            double span = (double)(1 << (g->n + sc)), bmin[3], bmax[3];
            grid_to_world(c * span, (r + 1) * span, &bmin[0], &bmin[1]);
            grid_to_world((c + 1) * span, r * span, &bmax[0], &bmax[1]);
            bmin[2] = m->area_qmin, bmax[2] = m->area_qmax; /* 1 m steps (integral heights) */
            double d2 = 0;
            for (int a = 0; a < 3; a++) {
                double e = cam.position[a] < bmin[a]   ? bmin[a] - cam.position[a]
                           : cam.position[a] > bmax[a] ? cam.position[a] - bmax[a]
                                                       : 0;
                d2 += e * e;
            }
            int stride_log = sc + g->n - nodes[i].level;
            int asked = asked_stride_log(g->n, sqrt(d2), mind, maxd);
            EXPECT_LE_INT(stride_log, asked);
            coarse += sc >= 2;
            levels_below_n += nodes[i].level < g->n;
        }
    }
    EXPECT_GT(coarse, 0); /* the views reach far terrain */
    EXPECT_GT(levels_below_n, 0);
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
    free(h);
}

TEST(tiny_grids)
{
    /* 1x1 (one sample: nothing to draw), 2x2, 18x17 (two leaf roots), 49x40 (padded forest). */
    const int sizes[][2] = {{1, 1}, {2, 2}, {18, 17}, {49, 40}};
    for (int i = 0; i < 4; i++) {
        int w = sizes[i][0], hh = sizes[i][1];
        LOAD_OR_SKIP(h, 400, 400, w, hh);
        tp_tree* t = make_tree(h, w, hh, 17);
        tp_cut* cut;
        ASSERT_OK(tp_cut_create(t, &cut, NULL));
        tp_camera cam;
        camera_at(t, 0, 0, 300, 135, -45, &cam);
        for (int m = 0; m < 3; m++) {
            tp_lod_params lp = {.mode = m == 0   ? TP_LOD_ERROR
                                        : m == 1 ? TP_LOD_DISTANCE
                                                 : TP_LOD_FULL};
            ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
            size_t count;
            const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
            EXPECT_EQ_INT(0, check_watertight(t, cut, NULL));
            for (size_t k = 0; k < count; k++)
                if (!(tp_tree_meta(t, nodes[k].node)->flags & TP_NODE_COMPLETE))
                    EXPECT_EQ_INT(tp_tree_get_geometry(t)->n, nodes[k].level);
            if (w == 1)
                EXPECT_EQ_INT(0, (int)last_triangles);
            else
                EXPECT_GT((double)last_triangles, 0);
            double mx = -1;
            ASSERT_OK(tp_cut_measure_screen_error(cut, &cam, &mx, NULL, NULL, NULL));
            if (m == 2)
                EXPECT_EQ_DBL(0, mx); /* leaves at level n draw the samples themselves */
        }
        tp_cut_destroy(cut);
        tp_tree_destroy(t);
        free(h);
    }
}

TEST(rejects_max_error_mode)
{
    LOAD_OR_SKIP(h, 0, 0, 65, 65);
    tp_tree* t = make_tree(h, 65, 65, 17);
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    tp_camera cam;
    camera_at(t, 10, 10, 100, 0, -30, &cam);
    tp_lod_params lp = {.mode = TP_LOD_MAX_ERROR, .max_error_m = 1};
    tp_error e = {{0}};
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_cut_update(cut, &cam, &lp, &e));
    EXPECT_CONTAINS(e.message, "max-error");
    lp = (tp_lod_params){.mode = TP_LOD_ERROR, .tau_px = -1};
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_cut_update(cut, &cam, &lp, NULL));
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
    free(h);
}

/* tp_cut_update_requests asks for what tp_cut_update asks for (less requests only its stitching
 * pass makes) and draws nothing, over a tree with a third of its nodes below the roots not
 * resident. */
TEST(requests_only_update_asks_as_the_full_update)
{
    LOAD_OR_SKIP(h, 250, 300, 700, 420);
    tp_tree* t = make_tree(h, 700, 420, 17);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    for (int64_t id = 0; id < g->node_count; id++)
        if (tp_tree_node_parent(g, id) >= 0 && rnd() < 0.33)
            tp_tree_detach(t, id);
    tp_cut *full, *req;
    ASSERT_OK(tp_cut_create(t, &full, NULL));
    ASSERT_OK(tp_cut_create(t, &req, NULL));
    size_t asked = 0, same = 0, extra = 0;
    for (int it = 0; it < 40; it++) {
        tp_camera cam;
        random_camera(t, &cam);
        tp_lod_params lp = {.mode = it % 4 == 3 ? TP_LOD_DISTANCE : TP_LOD_ERROR, .tau_px = 1};
        ASSERT_OK(tp_cut_update(full, &cam, &lp, NULL));
        ASSERT_OK(tp_cut_update_requests(req, &cam, &lp, NULL));
        size_t nf, nr, nodes;
        const int64_t* rf = tp_cut_requests(full, &nf);
        const int64_t* rr = tp_cut_requests(req, &nr);
        tp_cut_nodes(req, &nodes);
        EXPECT_EQ_INT(0, (int)nodes);
        asked += nf;
        for (size_t i = 0; i < nr; i++) {
            int found = 0;
            for (size_t j = 0; j < nf && !found; j++)
                found = rr[i] == rf[j];
            same += found;
            extra += !found;
        }
        tp_cut_stats st;
        tp_cut_get_stats(req, &st);
        EXPECT_EQ_INT(0, st.drawn);
        EXPECT_EQ_INT((int)nr, st.requests);
    }
    printf("requests: %zu by the full updates, %zu of them by the requests-only ones\n", asked,
           same);
    EXPECT_EQ_INT(0, (int)extra);
    EXPECT_GT((double)asked, 40);
    EXPECT_GE_INT((int)same, (int)(0.95 * (double)asked));
    tp_cut_destroy(full);
    tp_cut_destroy(req);
    tp_tree_destroy(t);
    free(h);
}

#define TESTS(X)                                                                                   \
    X(watertight_for_random_views)                                                                 \
    X(watertight_for_random_views_with_tin_nodes)                                                  \
    X(screen_error_within_tau_with_tin_nodes)                                                      \
    X(watertight_for_random_views_stitch_add)                                                      \
    X(a_cut_drawn_from_a_moved_camera_keeps_tau_and_coverage)                                      \
    X(a_carried_cut_holds_is_watertight_and_near_the_selection)                                    \
    X(a_cut_carried_again_and_again_holds_along_a_flight)                                          \
    X(a_carried_cut_takes_in_the_roots_that_arrived)                                               \
    X(a_carried_cut_is_carried_only_from_an_update)                                                \
    X(a_carried_cut_holds_over_forests_of_odd_sizes)                                               \
    X(a_carried_cut_finds_an_island_smaller_than_a_coarse_stride)                                  \
    X(watertight_for_adversarial_cuts)                                                             \
    X(watertight_for_adversarial_cuts_with_tin_nodes)                                              \
    X(watertight_for_adversarial_cuts_stitch_add)                                                  \
    X(screen_error_within_tau)                                                                     \
    X(screen_error_within_tau_stitch_add)                                                          \
    X(incomplete_nodes_collapse_far_away)                                                          \
    X(substitution_keeps_the_surface_whole)                                                        \
    X(cost_does_not_grow_with_the_map)                                                             \
    X(drawn_height_follows_the_triangles)                                                          \
    X(distance_mode_never_coarser_than_asked)                                                      \
    X(tiny_grids)                                                                                  \
    X(rejects_max_error_mode)                                                                      \
    X(requests_only_update_asks_as_the_full_update)
TP_TEST_MAIN(TESTS)
