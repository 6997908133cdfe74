/*
 * navigate.h - moving the viewer's camera: flying (W/S/A/D/Q/E, drag to look), orbiting around
 * a ground point (O), and the home view (Home). Pure C over the core's camera: no window, so
 * tests drive it with made-up controls.
 */
#ifndef TP_APP_NAVIGATE_H
#define TP_APP_NAVIGATE_H

#include "tp_core.h"

/* What the user asks for during one frame. */
typedef struct tp_nav_controls {
    double forward, right, up; /* -1, 0 or 1 each (W/S, D/A, E/Q) */
    double look_dx, look_dy;   /* cursor drag in pixels with the left button down */
    double zoom_steps;         /* mouse wheel steps (orbit: toward the target) */
    double speed_factor;       /* Shift 5, Ctrl 0.2; 0 means 1 */
} tp_nav_controls;

typedef struct tp_nav {
    double yaw_deg, pitch_deg;
    int orbit;                  /* orbit mode: around target instead of flying */
    double target[3];           /* orbit centre (world, drawn heights) */
    double distance_m;          /* eye to target in orbit mode */
    double extent_m;            /* the terrain's larger horizontal extent */
    double speed_mps;           /* the last flight speed (for the HUD) */
    tp_camera home;             /* the view Home returns to */
} tp_nav;

/* Starts navigation from cam, which also becomes the home view. extent_m is the terrain's
 * larger horizontal extent (bounds the flight speed). */
void tp_nav_init(tp_nav* nav, const tp_camera* cam, double extent_m);

/* Flight speed (m/s) at a height above the drawn ground: half the height per second, at least
 * 5 m/s and at most a twentieth of the terrain's extent per second (so that the default view,
 * kilometres up, does not leave the DEM in a second); NaN height (off the terrain) counts as
 * 1000 m. */
double tp_nav_fly_speed(double height_above_ground_m, double extent_m);

/* Back to the home view: flying, the home camera (viewport kept from cam). */
void tp_nav_home(tp_nav* nav, tp_camera* cam);

/* Orbit mode on around ground point g (world, drawn heights), or off if it was on. */
void tp_nav_toggle_orbit(tp_nav* nav, const tp_camera* cam, const double g[3]);

/* One frame: dt seconds of the controls. ground_z is the drawn surface's height under the eye
 * (NaN off the terrain); the caller keeps the new eye above the ground (tp_selection_keep_above).
 * Writes the new camera (viewport and field of view kept). */
void tp_nav_step(tp_nav* nav, const tp_nav_controls* c, double dt, double ground_z,
                 tp_camera* cam);

#endif
