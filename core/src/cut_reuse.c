/* cut_reuse.c - a cut drawn from another camera than the one it was selected for
 * (tp_cut_holds_for): the test that lets a cut selected on another thread, for the predicted
 * camera, be drawn from the camera the frame really has, without losing tau or coverage.
 *
 * The test from scratch projects every drawn node's box and tests every culled one against
 * the frustum (0.9 ms on the render thread at 65537^2). tp_cut_prepare_reuse, on the thread
 * that selected the cut, keeps per record what the test needs from the selection's own camera
 * P; tp_cut_holds_for then bounds how far a camera R may have moved each figure (below) and
 * tests a node from scratch only where that bound does not settle it. Same answer, a few
 * operations a node.
 *
 * The bounds. Let dc = |pos_R - pos_P|, beta the Frobenius norm of the difference of the two
 * orthonormal frames (right, up, fwd; |B_R w - B_P w| <= beta |w| for any vector w), and for
 * a box rmax the largest distance from pos_P to a corner. For any corner x:
 *   - a frustum plane's signed distance n.(x - pos) + o (unit n = B^T m, o fixed by the
 *     field of view) moves by at most beta rmax + dc: a box outside a plane of P by more than
 *     that is outside the same plane of R;
 *   - its depth fwd.(x - pos) drops by at most beta rmax + dc: zmin_R >= zmin_P - beta rmax - dc;
 *   - the projection bound's numerators (A, B: tp__proj_bound_box) are the first two camera
 *     coordinates of up x (x - pos), which moves by at most dc + beta rmax: each of Amax and
 *     Bmax grows by at most that, and sqrt(Amax^2 + Bmax^2) by at most sqrt(2) times it.
 * tp__projected_px_drawn grows with the numerator and falls with the depth, so putting these
 * bounds in it bounds R's figure from above.
 */
#include "cut_int.h"
#include "lod_int.h"

#include <math.h>

enum { REUSE_NONE = 0, REUSE_CULLED, REUSE_DRAWN, REUSE_SCRATCH /* always tested */ };

/* What tp_cut_holds_for needs of one record, from the update's camera. */
typedef struct tp__cut_reuse {
    double a;     /* culled: how far the box lies outside one frustum plane (m); drawn: its
                     projection numerator sqrt(Amax^2 + Bmax^2) (m) */
    double zmin;  /* drawn: the box's smallest depth (m) */
    double rmax;  /* the eye to the box's farthest corner (m) */
    double hole;  /* drawn, incomplete (it may leave holes): the eye to its area box (m, the
                     hole test's R); else -1 */
    uint8_t kind; /* REUSE_*: what the record is tested for */
} tp__cut_reuse;

/* Relative slack for rounding: a bound this close to its limit is settled from scratch. */
#define SLACK 1e-9

static double far_corner(const double pos[3], const double bmin[3], const double bmax[3])
{
    double d2 = 0;
    for (int a = 0; a < 3; a++) {
        double d = fmax(fabs(bmin[a] - pos[a]), fabs(bmax[a] - pos[a]));
        d2 += d * d;
    }
    return sqrt(d2);
}

/* How far the box lies outside the frustum's planes: the largest -(distance of the corner
 * furthest along the plane's normal), > 0 when tp_frustum_test_aabb says outside. */
static double outside_margin(const tp_frustum* f, const double mn[3], const double mx[3])
{
    double margin = -INFINITY;
    for (int i = 0; i < f->plane_count; i++) {
        const double* pl = f->planes[i];
        double pv = pl[3];
        for (int a = 0; a < 3; a++)
            pv += pl[a] * (pl[a] >= 0 ? mx[a] : mn[a]);
        margin = -pv > margin ? -pv : margin;
    }
    return margin;
}

/* A leaf drawn at level n draws its samples: only quantisation is left, however near it comes
 * (unless it draws a TIN rung, whose bound is its own). */
static int exempt_leaf(const tp_cut* c, const tp__cut_rec* r)
{
    return r->s == 0 && r->level == c->n && !(c->out_tin && c->out_tin[r->out]);
}

/* A drawn record's distance for the hole test (the selection's hole_px, cut_select.c) from the
 * eye at pos to its area box, or -1 when it leaves no holes. */
static double hole_distance(const tp_cut* c, const tp__cut_rec* r, const double pos[3],
                            const double bmin[3], const double bmax[3])
{
    if (tp__cut_whole(tp_tree_meta(c->t, r->node)) || (r->s == 0 && r->level == c->n))
        return -1;
    return tp__cut_box_distance(pos, bmin, bmax);
}

/* Whether a drawn record, its bound d (m) projecting to px from view v, with near set when its
 * box reaches the near plane and hole as hole_distance, keeps the cut: within tau (a box at the
 * near plane only with a zero bound, as the selection asks), and its holes within hole_px. */
static int bound_holds(const tp_cut* c, const tp__cut_rec* r, const tp__view* v, double d,
                       double px, int near, double hole)
{
    return !(px > c->lp.tau_px) && !(near && d > 0) &&
           (hole < 0 || tp__cut_hole_ok(c, v->f_px, r->s, 0, hole, r->level));
}

static int drawn_holds(const tp_cut* c, const tp__cut_rec* r, const tp__view* v, double px,
                       int near, double hole)
{
    return bound_holds(c, r, v, r->bound_m, px, near, hole);
}

static const int no_nb[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};

/* Culled record i, which has no own samples to draw though its area box was in view (an island
 * of data smaller than its sample stride, voids around it): whether it keeps the cut from view
 * v (frustum f). Its area box is outside, or (error mode) drawn at its level it would keep tau
 * and hole_px, so that the selection would not refine it either (into nodes that draw what is
 * in its area); a substituted one stays (its children are not resident). */
static int empty_holds(const tp_cut* c, size_t i, const tp__view* v, const tp_frustum* f)
{
    const tp__cut_rec* r = &c->rec[i];
    double bmin[3], bmax[3];
    if (!tp__cut_box(c, (int)i, 1, bmin, bmax) ||
        tp_frustum_test_aabb(f, bmin, bmax) == TP_CULL_OUTSIDE)
        return 1;
    if (!c->have_view || c->lp.mode != TP_LOD_ERROR || r->substituted)
        return 1;
    tp__proj_bound pb = tp__proj_bound_box(v, bmin, bmax);
    double d = tp__cut_bound_m(c, (int)i, r->level, no_nb);
    int near;
    double px = tp__projected_px_drawn(v, &pb, d, &near);
    return bound_holds(c, r, v, d, px, near, hole_distance(c, r, v->pos, bmin, bmax));
}

/* Whether a drawn record's bound may exceed tau from camera v (the exempt ones are not
 * tested: they could not be finer in this update either). */
static int tested_drawn(const tp_cut* c, const tp__cut_rec* r)
{
    return r->state == TP__CUT_DRAWN && c->have_view && c->lp.mode == TP_LOD_ERROR &&
           r->out >= 0 && !r->substituted && !exempt_leaf(c, r);
}

/* The figures of every record from view v (frustum f), and whether the cut holds for v (as
 * holds_node would say of each record). 0 without memory: nothing kept, *holds unset. */
static int keep_figures(tp_cut* c, const tp__view* v, const tp_frustum* f, int* holds)
{
    c->reuse_gen = 0;
    if (c->rec_count > c->reuse_cap) {
        tp__free(&c->alloc, c->reuse);
        c->reuse_cap = 0;
        c->reuse = tp__alloc(&c->alloc, c->rec_count, sizeof *c->reuse);
        if (!c->reuse)
            return 0;
        c->reuse_cap = c->rec_count;
    }
    int all = 1;
    for (size_t i = 0; i < c->rec_count; i++) {
        const tp__cut_rec* r = &c->rec[i];
        tp__cut_reuse* e = &c->reuse[i];
        double bmin[3], bmax[3];
        e->kind = REUSE_NONE;
        if (r->state == TP__CUT_CULLED) {
            if (!tp__cut_box(c, (int)i, r->view == 1, bmin, bmax)) {
                if (r->view != 1) { /* no own samples: tested from scratch */
                    e->kind = REUSE_SCRATCH;
                    all &= empty_holds(c, i, v, f);
                }
                continue;
            }
            e->kind = REUSE_CULLED;
            e->a = outside_margin(f, bmin, bmax);
            all &= e->a > 0; /* tp_frustum_test_aabb's outside: a corner test per plane */
        } else if (tested_drawn(c, r)) {
            if (!tp__cut_box(c, (int)i, 1, bmin, bmax))
                continue;
            tp__proj_bound pb = tp__proj_bound_box(v, bmin, bmax);
            e->kind = REUSE_DRAWN;
            e->zmin = pb.zmin;
            e->a = isfinite(pb.num) ? pb.num * pb.zmin / v->f_px : INFINITY;
            int near;
            double px = tp__projected_px_drawn(v, &pb, r->bound_m, &near);
            e->hole = hole_distance(c, r, v->pos, bmin, bmax);
            all &= drawn_holds(c, r, v, px, near, e->hole);
        } else
            continue;
        e->rmax = far_corner(v->pos, bmin, bmax);
    }
    c->reuse_v = *v;
    c->reuse_gen = c->gen;
    *holds = all;
    return 1;
}

int tp_cut_prepare_reuse(tp_cut* c)
{
    assert(c);
    c->reuse_gen = 0;
    if (!c->have_view || c->gen == 0)
        return 0;
    int holds;
    return keep_figures(c, &c->v, &c->f, &holds);
}

int tp_cut_keep_for(tp_cut* c, const tp_camera* cam)
{
    assert(c && cam);
    tp__view v;
    tp_frustum f;
    tp__view_from_camera(cam, &v);
    tp_frustum_from_camera(cam, &f);
    int holds;
    if (c->have_view && c->gen != 0 && keep_figures(c, &v, &f, &holds))
        return holds;
    c->reuse_gen = 0;
    return tp_cut_holds_for(c, cam, NULL, NULL);
}

int tp__cut_holds_node(const tp_cut* c, size_t i, const tp__view* v, const tp_frustum* f,
                       double* px, tp__proj_bound* pb_out)
{
    const tp__cut_rec* r = &c->rec[i];
    double bmin[3], bmax[3];
    *px = 0;
    if (pb_out)
        pb_out->num = pb_out->zmin = NAN;
    if (r->state == TP__CUT_CULLED) {
        /* classify culled it by its area box (view == 1: not in view) or by its own box */
        if (tp__cut_box(c, (int)i, r->view == 1, bmin, bmax))
            return tp_frustum_test_aabb(f, bmin, bmax) == TP_CULL_OUTSIDE;
        return r->view == 1 || empty_holds(c, i, v, f); /* nothing in its area, or no own box */
    }
    if (r->state != TP__CUT_DRAWN || !c->have_view || c->lp.mode != TP_LOD_ERROR || r->out < 0 ||
        !tp__cut_box(c, (int)i, 1, bmin, bmax))
        return 1;
    tp__proj_bound pb = tp__proj_bound_box(v, bmin, bmax);
    if (pb_out)
        *pb_out = pb;
    int near;
    *px = tp__projected_px_drawn(v, &pb, r->bound_m, &near);
    return !tested_drawn(c, r) ||
           drawn_holds(c, r, v, *px, near, hole_distance(c, r, v->pos, bmin, bmax));
}

/* Whether v sees through the same lens as the update's view (only the pose may differ). */
static int same_lens(const tp__view* a, const tp__view* b)
{
    return a->f_px == b->f_px && a->tan_x == b->tan_x && a->tan_y == b->tan_y &&
           a->w_px == b->w_px && a->h_px == b->h_px && a->near_m == b->near_m &&
           a->far_m == b->far_m;
}

/* Record e's figures bound from camera v, moved by dc and turned by beta from the update's:
 * whether they settle that it keeps the cut (0: test it from scratch). */
static int settled(const tp_cut* c, const tp__cut_reuse* e, const tp__cut_rec* r,
                   const tp__view* v, double dc, double beta, double ratio)
{
    if (e->kind == REUSE_SCRATCH)
        return 0;
    double move = dc + beta * e->rmax;
    if (e->kind == REUSE_CULLED)
        return e->a > move + SLACK * (e->rmax + 1);
    double z = e->zmin - move;
    if (!(z > v->near_m) || !isfinite(e->a))
        return 0;
    double d = r->bound_m, num = v->f_px * (e->a + 1.4142135623730951 * move) / z;
    double z2 = z - d * fabs(v->fwd[2]);
    double px = d * (num < ratio ? num : ratio) / (z2 > v->near_m ? z2 : v->near_m);
    /* the eye is at most dc nearer the area box than it was */
    if (e->hole >= 0 && !tp__cut_hole_ok(c, v->f_px, r->s, 0, e->hole - dc - SLACK * (e->hole + 1),
                                         r->level))
        return 0;
    return px <= c->lp.tau_px * (1 - SLACK);
}

int tp_cut_holds_for(const tp_cut* c, const tp_camera* cam, double* max_bound_px,
                     size_t* scratch)
{
    assert(c && cam);
    tp__view v;
    tp_frustum f;
    tp__view_from_camera(cam, &v);
    tp_frustum_from_camera(cam, &f);
    double worst = 0, px;
    size_t tested = 0, dummy;
    scratch = scratch ? scratch : &dummy;
    if (!max_bound_px && c->reuse_gen && c->reuse_gen == c->gen && same_lens(&v, &c->reuse_v)) {
        double dc = 0, beta = 0;
        for (int a = 0; a < 3; a++) {
            const tp__view* p = &c->reuse_v; /* the camera the figures are from */
            double dp = v.pos[a] - p->pos[a], dr = v.right[a] - p->right[a];
            double du = v.up[a] - p->up[a], df = v.fwd[a] - p->fwd[a];
            dc += dp * dp, beta += dr * dr + du * du + df * df;
        }
        dc = sqrt(dc), beta = sqrt(beta);
        /* tp__projected_px_drawn's bound from the view's sides (v's own) */
        double ax = fabs(v.right[2]) + v.tan_x * fabs(v.fwd[2]);
        double ay = fabs(v.up[2]) + v.tan_y * fabs(v.fwd[2]);
        double ratio = v.f_px * sqrt(ax * ax + ay * ay);
        for (size_t i = 0; i < c->rec_count; i++) {
            const tp__cut_reuse* e = &c->reuse[i];
            if (e->kind == REUSE_NONE || settled(c, e, &c->rec[i], &v, dc, beta, ratio))
                continue;
            tested++;
            if (!tp__cut_holds_node(c, i, &v, &f, &px, NULL)) {
                *scratch = tested;
                return 0;
            }
        }
        *scratch = tested;
        return 1;
    }
    int holds = 1;
    for (size_t i = 0; i < c->rec_count; i++) {
        holds &= tp__cut_holds_node(c, i, &v, &f, &px, NULL);
        worst = px > worst ? px : worst;
    }
    *scratch = c->rec_count;
    if (max_bound_px)
        *max_bound_px = worst;
    return holds;
}
