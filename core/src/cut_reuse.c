/* cut_reuse.c - a cut drawn from another camera than the one it was selected for
 * (tp_cut_holds_for): the test that lets a cut selected on another thread, for the predicted
 * camera, be drawn from the camera the frame really has, without losing tau or coverage.
 */
#include "cut_int.h"

int tp_cut_holds_for(const tp_cut* c, const tp_camera* cam, double* max_bound_px)
{
    assert(c && cam);
    tp__view v;
    tp_frustum f;
    tp__view_from_camera(cam, &v);
    tp_frustum_from_camera(cam, &f);
    const int error = c->have_view && c->lp.mode == TP_LOD_ERROR;
    double worst = 0;
    int holds = 1;
    for (size_t i = 0; i < c->rec_count; i++) {
        const tp__cut_rec* r = &c->rec[i];
        double bmin[3], bmax[3];
        if (r->state == TP__CUT_CULLED) {
            /* classify culled it by its area box (view == 1: not in view) or by its own box */
            if (tp__cut_box(c, (int)i, r->view == 1, bmin, bmax) &&
                tp_frustum_test_aabb(&f, bmin, bmax) != TP_CULL_OUTSIDE)
                holds = 0;
            continue;
        }
        if (r->state != TP__CUT_DRAWN || !error || r->out < 0)
            continue;
        if (!tp__cut_box(c, (int)i, 1, bmin, bmax))
            continue;
        tp__proj_bound pb = tp__proj_bound_box(&v, bmin, bmax);
        int near;
        double px = tp__projected_px_drawn(&v, &pb, r->bound_m, &near);
        worst = px > worst ? px : worst;
        if (px > c->lp.tau_px && !r->substituted && !(r->s == 0 && r->level == c->n))
            holds = 0;
    }
    if (max_bound_px)
        *max_bound_px = worst;
    return holds;
}
