/* camera_int.h - the camera's frame and screen error (camera.c), for everything that projects:
 * lod.c, the selection, the cut, pgm_error.c. */
#ifndef TP_CORE_CAMERA_INT_H
#define TP_CORE_CAMERA_INT_H

#include "internal.h"
#include "tp_camera.h"

/* Camera frame: orthonormal basis and the pixel focal length (camera.c). */
typedef struct tp__view {
    double pos[3], fwd[3], right[3], up[3];
    double f_px;         /* pixels per unit of tan(angle) */
    double tan_x, tan_y; /* half-extents of the view at depth 1 */
    double w_px, h_px, near_m, far_m;
} tp__view;
void tp__view_from_camera(const tp_camera* cam, tp__view* v);

/* Screen error (px) between a sample's true position and the drawn surface's point vertically
 * above or below it (world, drawn space), as the screen-error measures define it: NaN when the
 * true position is outside the view (behind the near plane, past the far plane, outside the
 * frustum's sides), INFINITY when only the drawn point is behind the eye (camera.c). */
double tp__screen_error_px(const tp__view* v, const double truth[3], const double drawn[3]);

#endif
