/*
 * view_layers.c - the planner's layers on the viewer's scene (view.h): --overlay files draped on
 * the store's full-resolution ground, and contours around the point the camera looks at.
 */
#include "view.h"

#include "cli.h"
#include "layers.h"
#include "pick.h"

/* --overlay files read and draped, on the full-resolution ground of the store (o->ground,
 * o->layers set). TP_EXIT_OK, or one line naming the file and TP_EXIT_FAILURE. */
int tp_view_load_layers(tp_view_scene* v, view_options* o, tp_view_layers* layers)
{
    if (!v->store) {
        tp_cli_error("--overlay and --contours need a georeferenced DEM or a "
                     "store (%s is drawn whole: a heightmap image, --fit, --texture or "
                     "--whole)",
                     o->path);
        return TP_EXIT_FAILURE;
    }
    tp_error err = {{0}};
    if (!o->ground && tp_ground_create(v->store, NULL, &o->ground, &err) != TP_OK) {
        tp_cli_error("%s: %s", o->path, err.message);
        return TP_EXIT_FAILURE;
    }
    o->layers = layers;
    for (int i = 0; i < o->overlay_count; i++) {
        if (!tp_view_layers_add_overlay(layers, o->ground, o->overlays[i], &err)) {
            tp_cli_error("--overlay %s", err.message);
            return TP_EXIT_FAILURE;
        }
    }
    return TP_EXIT_OK;
}

/* Contours around the point the camera looks at (else the DEM's centre), for --contours at the
 * first frame. */
void tp_view_contours_at_centre(tp_view_scene* v, const tp_camera* cam, view_options* o,
                                double interval_m, char* line, size_t cap)
{
    double p[3];
    if (!tp_view_pick_centre(v, cam, p)) {
        p[0] = v->gt[0] + 0.5 * v->src_width * v->gt[1];
        p[1] = v->gt[3] + 0.5 * v->src_height * v->gt[5];
    }
    tp_view_layers_contours_at(o->layers, o->ground, p[0], p[1], interval_m, line, cap);
}
