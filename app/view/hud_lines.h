/*
 * hud_lines.h - the words of the viewer's HUD from the figures of a frame, with no scene and no
 * GL (hud_text.c gathers the figures; tests/test_hud_lines.c checks the words).
 *
 * By default the HUD says what a user on the ground needs, in three short lines (issue 29,
 * 4.6): where the view's centre is (MGRS, latitude and longitude, elevation), where the eye is
 * and which way it looks (height, height above the ground, heading, pitch), the scale and the
 * grid spacing, and the navigation mode with the keys for more. The engineering figures (frame
 * rate, CPU split, triangles, levels, error bound and measured error, memory) are the details,
 * shown on a key (TP_HUD_DETAILS_KEY) and always written to --stats-json.
 */
#ifndef TP_APP_HUD_LINES_H
#define TP_APP_HUD_LINES_H

#include <stddef.h>

/* The key that shows and hides the details (window.c), as the HUD and the help name it. */
#define TP_HUD_DETAILS_KEY "F4"

/* The default HUD's lines are at most this many characters (they fit a 1024 px window at the
 * overlay's scale 2 without wrapping). */
#define TP_HUD_LINE_MAX 84

typedef struct tp_hud_ground {
    /* the ground point at the centre of the view */
    int centre;                /* 0: sky at the centre */
    const char* centre_mgrs;   /* "10T FR 02244 24440", or "" / NULL without a geographic CRS */
    const char* centre_latlon; /* "45.36602N 121.69439W", or "" / NULL */
    double centre_e, centre_n; /* render CRS (shown without a geographic CRS) */
    double centre_elev_m;      /* true height of the drawn ground there */
    /* the eye */
    double eye_m;   /* height (drawn space: times the exaggeration) */
    double above_m; /* above the drawn ground under it; NaN: off the DEM */
    double heading_deg, pitch_deg;
    double m_per_px;     /* ground metres a pixel at the centre; NaN: none */
    double grid_m;       /* grid spacing drawn; 0: no grid */
    int orbit;           /* else flying */
    double speed_mps;    /* flight speed (0: not flying, headless) */
    int frozen;          /* level selection frozen (F) */
    double exaggeration; /* 1: none */
    int details;         /* the details are shown (the last line says how to hide them) */
} tp_hud_ground;

/* The default HUD, '\n'-separated, 3 lines of at most TP_HUD_LINE_MAX characters (a longer
 * MGRS or position is cut by the wrap, not here). Returns the length (cut to cap). */
size_t tp_hud_ground_text(const tp_hud_ground* g, char* out, size_t cap);

/* The error bound of the frame, one field of the details. */
typedef struct tp_hud_bound {
    int kind;          /* TP_HUD_BOUND_M (a DEM drawn whole), _PX (a store), _NONE (PGM) */
    double max, rms_m; /* metres (max and RMS) or pixels (max) */
    int near_nodes;    /* _PX: drawn nodes whose box reaches the near plane, bounded over
                          what is drawn of them (tp_cut_node.near_plane) */
} tp_hud_bound;

enum { TP_HUD_BOUND_NONE = 0, TP_HUD_BOUND_M, TP_HUD_BOUND_PX };

/* "error bound max 0.97 px"; with nodes at the near plane "error bound max 312 px (3 nodes at
 * the eye: bounded in front of the near plane)"; never "inf" nor "nan" (a bound that is not
 * finite says "unbounded"). */
void tp_hud_bound_text(const tp_hud_bound* b, char* out, size_t cap);

/* A length for the HUD: "850 m", "1 km", "12.5 km". */
void tp_hud_length_text(double m, char* out, size_t cap);

#endif
