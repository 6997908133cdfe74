/*
 * stitch_add_error.h - the measured error of the `--stitch add` geometry (stitch_add_error.c):
 * what `bench` reports for vertex adding and what the viewer's HUD measures.
 */
#ifndef TP_APP_STITCH_ADD_ERROR_H
#define TP_APP_STITCH_ADD_ERROR_H

#include "tp_core.h"

/* The exact vertical error (metres) of the `--stitch add` geometry of the
 * visible patches of sel (tp_patch_triangles_add with the selection's neighbour levels; an
 * incomplete patch's unmoved level-n triangles) against every drawn sample under it, each
 * counted once, as tp_selection_measure_error measures the vertex-moving geometry; with cam
 * (else NULL) also the screen error (px) of the same samples by tp_selection_measure_screen_error's
 * definition (in view, in front of the near plane; occlusion ignored): *max_px and *rms_px.
 * TP_ERR_OUT_OF_MEMORY (*out untouched) or TP_OK. */
tp_status tp_stitch_add_error(const tp_terrain* t, const tp_selection* sel, const tp_camera* cam,
                              tp_error_measure* out, double* max_px, double* rms_px);

#endif /* TP_APP_STITCH_ADD_ERROR_H */
