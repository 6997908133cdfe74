/*
 * hud_text.h - the words of the viewer's overlay: frame statistics, level of detail, error,
 * the camera's and the looked-at point's positions (lat/lon, UTM, MGRS), navigation mode; and
 * wrapping them to the window's width (nothing may be cut at 1024 px).
 */
#ifndef TP_APP_HUD_TEXT_H
#define TP_APP_HUD_TEXT_H

#include "position.h"
#include "view.h"

/* The exact error of the drawn geometry, measured now and then (it costs tens of ms). */
typedef struct tp_measured_error {
    double max_m, rms_m, max_px, rms_px;
    int valid;
    tp_view_measured_how how; /* what was measured (a store's cut: the share of its leaves) */
} tp_measured_error;

void tp_view_measure_now(const tp_view_scene* v, const tp_camera* cam, tp_measured_error* m);

/* What the frame loop knows that the scene does not. */
typedef struct tp_hud_state {
    double fps;
    int frozen;
    int orbit;           /* orbit mode; else flying */
    double speed_mps;    /* flight speed (0: not flying) */
    double exaggeration; /* vertical; 1 none */
    const char* layers;  /* the planning layers' legend (tp_view_layers_legend), or NULL */
    const char* sun;     /* the sun's time and place in the sky (tp_view_sun_text), or NULL */
    double grid_m;       /* the grid spacing drawn (tp_view_grid_spacing; 0: no grid) */
    int details;         /* the engineering lines too (TP_HUD_DETAILS_KEY, --hud-details) */
} tp_hud_state;

/* A position as "45.37312N 121.69512W  UTM 10n 600000 5012000  MGRS 10T FR 00000 12000" (each
 * part reads back as a position: position.h), or
 * "" without a CRS. */
void tp_view_position_text(const tp_georef* g, double e, double n, char* out, size_t cap);

/* Its parts: "45.37312N 121.69512W", "10n 600000 5012000", "10T FR 00000 12000" (each "" where
 * the position has no such form). */
void tp_view_position_parts(const tp_georef* g, double e, double n, char latlon[48], char utm[48],
                            char mgrs[TP_POSITION_MGRS_SPACED_SIZE]);

/* The overlay's text, '\n'-separated lines (unwrapped): the ground lines (hud_lines.h), the
 * legends of what is turned on (filled voids, layers, the sun, shadows), and with st->details
 * the engineering lines. me may be NULL. */
void tp_view_hud_text(tp_view_scene* v, const tp_camera* cam,
                      const tp_lod_params* lod, const frame_result* fr,
                      const tp_measured_error* me, const tp_hud_state* st, char* out,
                      size_t cap);

/* Wraps text so that no line is wider than max_width_px at the HUD font's scale 1: lines
 * break first between fields (runs of 3+ spaces), then between words, and continue indented.
 * Returns the length written (always NUL-terminated, cut to cap). */
size_t tp_hud_wrap(const char* text, float max_width_px, char* out, size_t cap);

#endif
