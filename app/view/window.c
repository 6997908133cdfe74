/* window.c - the interactive viewer's frame loop (see view.h): input events, navigation,
 * picking and measuring, export and screenshots, the overlay. */
#include "view.h"

#include "camera_pose.h"
#include "cli.h"
#include "hud.h"
#include "hud_text.h"
#include "input.h"
#include "los_pick.h"
#include "viewshed_pick.h"
#include "mesh_export.h"
#include "navigate.h"
#include "layers.h"
#include "overlay.h"
#include "pick.h"
#include "point_readout.h"
#include "store_cache.h"
#include "tp_geo.h"
#include "view_bookmarks.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

static const char* help_text =
    "W/S forward/back   A/D left/right   Q/E down/up   left drag: look   Shift faster   Ctrl "
    "slower\n"
    "Home (or 0) home view   O orbit mode (drag rotates, wheel or W/S zoom, A/D/Q/E pan)\n"
    "L colour by level   T wireframe   F freeze LoD and culling   M LoD mode\n"
    "+/- tau (or maxdist)   [ ] mindist   , . exp   X/Z exaggeration   V filled-void tint\n"
    "J/K sun azimuth   U/N sun elevation   PgUp/PgDn the sun's time +/-15 min (Shift: 1 h)\n"
    "G grid (1, 10 or 100 km by the scale)   P screenshot   Y export mesh   F3 imagery on/off\n"
    "C print camera   H hide HUD   F4 details (fps, CPU, triangles, levels, error bound)\n"
    "right-click twice: measure   I or middle-click: what is here\n"
    "R line-of-sight mode (right-click observer, then target: green seen, red hidden)\n"
    "B viewshed from the ground under the cursor, 10 km (red: not seen; B again: off)\n"
    "F2 contours within 10 km of the point looked at (F2 again: off)\n"
    "Ctrl+1..9 save the view as bookmark \"view N\"   1..9 back to it   Tab/Shift+Tab every "
    "bookmark\n"
    "? this help   Esc quit";

typedef struct window_state {
    tp_view_scene* v;
    tp_camera* cam;
    view_options* o;
    tp_nav nav;
    tp_lod_params lod;
    int frozen, shots, exports, show_help, show_hud, show_details, quit, want_shot;
    double picks[2][3];
    int picked;
    char measure_line[512];
    tp_ground* ground; /* the point readout's full-resolution queries; made on first use */
    int has_mark;      /* the last point readout's ground point, marked on screen */
    double mark[3];
    int los_mode;      /* R: right clicks pick a line of sight instead of measuring */
    tp_view_los los;
    tp_view_viewshed viewshed; /* B */
    int bookmark;      /* place in the bookmarks file of the last one shown (-1: none) */
} window_state;

static const char* lod_name(tp_lod_mode m)
{
    return m == TP_LOD_DISTANCE ? "distance"
         : m == TP_LOD_FULL       ? "full"
         : m == TP_LOD_MAX_ERROR  ? "max-error"
                                  : "error";
}

/* Scales tau (error mode) or maxdist (distance mode) by f, defaults made explicit. */
static void scale_lod(window_state* s, double f)
{
    tp_lod_params full;
    if (!s->v->dem) { /* a store: the cut resolves its own defaults */
        if (s->lod.mode == TP_LOD_DISTANCE && s->lod.maxdist_m > 0)
            s->lod.maxdist_m *= f;
        else if (s->lod.mode != TP_LOD_DISTANCE)
            s->lod.tau_px = (s->lod.tau_px > 0 ? s->lod.tau_px : 1) * f;
        return;
    }
    if (tp_lod_params_resolve(s->v->dem->terrain, &s->lod, &full, NULL) != TP_OK)
        return;
    s->lod.tau_px = full.tau_px * (s->lod.mode == TP_LOD_ERROR ? f : 1);
    s->lod.mindist_m = full.mindist_m;
    s->lod.maxdist_m =
        fmax(full.mindist_m, full.maxdist_m * (s->lod.mode == TP_LOD_DISTANCE ? f : 1));
}

static void scale_mindist(window_state* s, double f)
{
    tp_lod_params full;
    if (!s->v->dem) {
        if (s->lod.mindist_m > 0)
            s->lod.mindist_m *= f;
        return;
    }
    if (tp_lod_params_resolve(s->v->dem->terrain, &s->lod, &full, NULL) != TP_OK)
        return;
    s->lod.mindist_m = fmin(full.mindist_m * f, full.maxdist_m);
    s->lod.maxdist_m = full.maxdist_m;
}

static void export_view(window_state* s)
{
    char name[64], cam_text[256], lod_text[96];
    if (!s->v->dem) {
        tp_cli_error("Y: exporting the view's mesh is not available on a store yet");
        return;
    }
    snprintf(name, sizeof name, "terrapatch-view-%03d.vtp", s->exports++);
    tp_camera_text_georef(s->v->georef, s->cam, cam_text, sizeof cam_text);
    snprintf(lod_text, sizeof lod_text, "mode=%s tau_px=%g", lod_name(s->lod.mode),
             s->lod.tau_px > 0 ? s->lod.tau_px : 1);
    tp_export_options eo = {.camera_text = cam_text, .lod_text = lod_text};
    tp_export_result er;
    tp_error err;
    if (tp_export_selection(s->v->dem, s->v->sel, &eo, name, &er, &err) == TP_OK) {
        printf("exported %s: %zu triangles, measured error max %.2f m\n", name, er.triangles,
               er.max_error_m);
        fflush(stdout);
    } else if (!tp_interrupted()) { /* else main says "interrupted" */
        tp_cli_error("%s", err.message);
    }
}

static void print_camera(const window_state* s)
{
    double lat, lon, yaw, pitch;
    const tp_camera* cam = s->cam;
    tp_camera_get_pose(cam, &yaw, &pitch);
    if (tp_georef_proj_to_geo(s->v->georef, cam->position[0], cam->position[1], &lat, &lon,
                              NULL) == TP_OK)
        printf("--camera-geo %.9f,%.9f,%.2f,%.2f,%.2f\n", lat, lon, cam->position[2], yaw, pitch);
    printf("--camera %.3f,%.3f,%.2f,%.2f,%.2f\n", cam->position[0], cam->position[1],
           cam->position[2], yaw, pitch);
    if (s->o->render.exaggeration != 1) /* the heights above are in the exaggerated space */
        printf("--exaggeration %.17g\n", s->o->render.exaggeration);
    fflush(stdout);
}

/* Picks the ground at window coordinates (x, y) (screen coordinates, as GLFW gives the cursor)
 * into p (render CRS E, N and height); 0 where no ground is under them. */
static int pick_window(window_state* s, GLFWwindow* win, double x, double y, double p[3])
{
    int ww, wh;
    glfwGetWindowSize(win, &ww, &wh);
    double px = x * s->cam->viewport_w_px / fmax(ww, 1), py = y * s->cam->viewport_h_px / fmax(wh, 1);
    return tp_view_pick(s->v, s->cam, px, py, p);
}

/* The ground under window coordinates (x, y) for a field tool (the point readout, line of
 * sight, the viewshed), with s->ground made on first use: 1 with p as pick_window's; else 0
 * with "TOOL: why" on the HUD's line (no store, no ground under the cursor, the ground's
 * error). */
static int ground_under(window_state* s, GLFWwindow* win, double x, double y, const char* tool,
                        double p[3])
{
    if (!s->v->store) {
        snprintf(s->measure_line, sizeof s->measure_line,
                 "%s: only on a georeferenced DEM or a store", tool);
        return 0;
    }
    if (!pick_window(s, win, x, y, p)) {
        snprintf(s->measure_line, sizeof s->measure_line, "%s: no ground under the cursor", tool);
        return 0;
    }
    tp_error err = {{0}};
    if (!s->ground && tp_ground_create(s->v->store, NULL, &s->ground, &err) != TP_OK) {
        snprintf(s->measure_line, sizeof s->measure_line, "%s: %.400s", tool, err.message);
        return 0;
    }
    return 1;
}

/* The measuring tool: a right click picks a ground point; every second one measures. */
static void measure_click(window_state* s, GLFWwindow* win, double x, double y)
{
    double* p = s->picks[s->picked % 2];
    if (!pick_window(s, win, x, y, p))
        return;
    s->picked++;
    s->has_mark = 0; /* the measurement replaces the point readout on the HUD */
    if (s->picked % 2 == 0) {
        double e[2] = {s->picks[0][0], s->picks[1][0]}, n[2] = {s->picks[0][1], s->picks[1][1]};
        tp_view_measure_points(s->v, e, n, s->measure_line, sizeof s->measure_line);
        printf("measure: %s\n", s->measure_line);
        fflush(stdout);
    } else {
        snprintf(s->measure_line, sizeof s->measure_line,
                 "first point E %.1f N %.1f (%.1f m); right-click the second", p[0], p[1], p[2]);
    }
}

/* The point readout ("what is here?", I or a middle click): the ground under the cursor,
 * printed to stdout as `terrapatch point` prints it and shown on the HUD where the measuring
 * tool's line goes. */
static void point_click(window_state* s, GLFWwindow* win, double x, double y)
{
    double p[3];
    if (!ground_under(s, win, x, y, "point readout", p))
        return;
    tp_point_readout r;
    tp_error err = {{0}};
    const char* source = s->v->path ? s->v->path : s->v->store->path;
    if (!tp_point_readout_at_world(s->ground, source, p[0], p[1], 5, &r, &err)) {
        snprintf(s->measure_line, sizeof s->measure_line, "point readout: %.400s", err.message);
        printf("point: %s\n", err.message);
    } else {
        char text[2048];
        tp_point_readout_text(&r, text, sizeof text);
        printf("point:\n%s", text);
        tp_point_readout_hud(&r, s->measure_line, sizeof s->measure_line);
        s->has_mark = 1;
        s->mark[0] = p[0];
        s->mark[1] = p[1];
        s->mark[2] = r.ground.height_m;
    }
    fflush(stdout);
}

/* Line-of-sight mode: a right click picks the observer, the next the target. */
static void los_click(window_state* s, GLFWwindow* win, double x, double y)
{
    double p[3];
    if (!ground_under(s, win, x, y, "line of sight", p))
        return;
    s->has_mark = 0;
    tp_view_los_click(&s->los, s->ground, p[0], p[1], s->measure_line, sizeof s->measure_line);
}

/* F2: contours around the point looked at (--contours' interval, else one for the relief);
 * F2 again: off. */
static void contours_key(window_state* s)
{
    if (s->o->layers && s->o->layers->contours.part_count) {
        tp_drape_free(&s->o->layers->contours);
        snprintf(s->measure_line, sizeof s->measure_line, "contours: off");
        return;
    }
    if (!s->o->layers || !s->o->ground) {
        snprintf(s->measure_line, sizeof s->measure_line,
                 "contours: only on a georeferenced DEM or a store");
        return;
    }
    tp_view_contours_at_centre(s->v, s->cam, s->o, s->o->contours_m, s->measure_line,
                               sizeof s->measure_line);
}

/* B: the viewshed from the ground under the cursor; B again: off. */
static void viewshed_key(window_state* s, GLFWwindow* win)
{
    if (s->viewshed.overlay.count) {
        tp_view_viewshed_free(&s->viewshed);
        snprintf(s->measure_line, sizeof s->measure_line, "viewshed: off");
        return;
    }
    double x, y, p[3];
    glfwGetCursorPos(win, &x, &y);
    if (!ground_under(s, win, x, y, "viewshed", p))
        return;
    s->has_mark = 0;
    tp_view_viewshed_at(&s->viewshed, s->ground, p[0], p[1], TP_VIEW_VIEWSHED_RADIUS_M,
                        s->measure_line, sizeof s->measure_line);
}

static void on_char(window_state* s, int c)
{
    switch (c) {
    case '?': s->show_help = !s->show_help; break;
    case '+': case '=': scale_lod(s, 1.5); break;
    case '-': scale_lod(s, 1 / 1.5); break;
    case ']': scale_mindist(s, 1.25); break;
    case '[': scale_mindist(s, 0.8); break;
    case '.': case ',':
        s->lod.exponent = (s->lod.exponent > 0 ? s->lod.exponent : 1) * (c == '.' ? 1.25 : 0.8);
        break;
    case '0': tp_nav_home(&s->nav, s->cam); break;
    }
}

static void on_key(window_state* s, int key, int mods)
{
    tp_render_settings* rs = &s->o->render;
    switch (key) {
    case GLFW_KEY_ESCAPE: s->quit = 1; break;
    case GLFW_KEY_HOME: tp_nav_home(&s->nav, s->cam); break;
    case GLFW_KEY_O: {
        double g[3];
        int hit = !s->nav.orbit && tp_view_pick_centre(s->v, s->cam, g);
        if (hit)
            g[2] *= tp_view_scene_vertical_scale(s->v);
        tp_nav_toggle_orbit(&s->nav, s->cam, hit ? g : NULL);
        break;
    }
    case GLFW_KEY_L: rs->color_lod = !rs->color_lod; break;
    case GLFW_KEY_T: rs->wireframe = !rs->wireframe; break;
    case GLFW_KEY_F: s->frozen = !s->frozen; break;
    case GLFW_KEY_H: s->show_hud = !s->show_hud; break;
    case GLFW_KEY_F4: /* the engineering lines (hud_lines.h) */
        s->show_details = !s->show_details;
        s->show_hud = 1;
        break;
    case GLFW_KEY_V: rs->hide_filled = !rs->hide_filled; break;
    case GLFW_KEY_G: rs->grid_m = rs->grid_m > 0 ? 0 : 1000; break;
    case GLFW_KEY_PAGE_UP:
    case GLFW_KEY_PAGE_DOWN: /* the sun's time (--sun-date, --sun-time) */
        if (!s->o->sun.on) {
            snprintf(s->measure_line, sizeof s->measure_line, "%s",
                     "sun: give --sun-date and --sun-time to move it with PgUp and PgDn");
            break;
        }
        tp_view_sun_step(&s->o->sun, (key == GLFW_KEY_PAGE_DOWN ? -1 : 1) *
                                         (mods & GLFW_MOD_SHIFT ? 3600 : 900), rs);
        break;
    case GLFW_KEY_J: rs->sun_azimuth_deg = fmod(rs->sun_azimuth_deg + 345, 360); break;
    case GLFW_KEY_K: rs->sun_azimuth_deg = fmod(rs->sun_azimuth_deg + 15, 360); break;
    case GLFW_KEY_U: rs->sun_elevation_deg = fmin(90, rs->sun_elevation_deg + 5); break;
    case GLFW_KEY_N: rs->sun_elevation_deg = fmax(0, rs->sun_elevation_deg - 5); break;
    case GLFW_KEY_X: rs->exaggeration = fmin(rs->exaggeration * 1.25, TP_VERTICAL_SCALE_MAX); break;
    case GLFW_KEY_Z: rs->exaggeration = fmax(rs->exaggeration / 1.25, TP_VERTICAL_SCALE_MIN); break;
    case GLFW_KEY_M: s->lod.mode = s->lod.mode == TP_LOD_ERROR ? TP_LOD_DISTANCE : TP_LOD_ERROR; break;
    case GLFW_KEY_F1: s->show_help = !s->show_help; break;
    case GLFW_KEY_P: s->want_shot = 1; break;
    case GLFW_KEY_Y: export_view(s); break;
    case GLFW_KEY_C: print_camera(s); break;
    case GLFW_KEY_B: viewshed_key(s, glfwGetCurrentContext()); break;
    case GLFW_KEY_F2: contours_key(s); break;
    case GLFW_KEY_F3: /* imagery on or off */
        s->v->imagery_hidden = !s->v->imagery_hidden;
        snprintf(s->measure_line, sizeof s->measure_line, "%s",
                 !s->v->imagery ? "imagery: none (terrapatch imagery STORE IMAGE... makes it)"
                 : s->v->imagery_hidden ? "imagery: off (F3: on)" : "imagery: on (F3: off)");
        break;
    case GLFW_KEY_R:
        s->los_mode = !s->los_mode;
        s->los.picked = 0;
        snprintf(s->measure_line, sizeof s->measure_line, "%s",
                 s->los_mode ? "line of sight: right-click the observer, then the target"
                             : "measure: right-click two points");
        break;
    case GLFW_KEY_I: {
        double mx, my;
        glfwGetCursorPos(glfwGetCurrentContext(), &mx, &my);
        point_click(s, glfwGetCurrentContext(), mx, my);
        break;
    }
    }
}

/* Bookmarks (view_bookmarks.h): Ctrl+1..9 saves the view as "view N", 1..9 goes back to it,
 * Tab / Shift+Tab step through the file. Returns 1 when the key was one of them. */
static int bookmark_key(window_state* s, int key, int mods)
{
    int ok;
    tp_error err = {{0}};
    if (key == GLFW_KEY_TAB) {
        ok =
            tp_view_bookmark_cycle(s->v, s->o, s->cam, &s->bookmark, mods & GLFW_MOD_SHIFT ? -1 : 1,
                                   s->measure_line, sizeof s->measure_line, &err);
    } else if (key >= GLFW_KEY_1 && key <= GLFW_KEY_9) {
        char name[16];
        snprintf(name, sizeof name, "view %d", key - GLFW_KEY_0);
        if (mods & GLFW_MOD_CONTROL) {
            if (!tp_view_bookmark_save(s->v, s->o, s->cam, name, s->measure_line,
                                       sizeof s->measure_line, &err))
                snprintf(s->measure_line, sizeof s->measure_line, "%s", err.message);
            printf("%s\n", s->measure_line);
            fflush(stdout);
            return 1;
        }
        ok = tp_view_bookmark_recall(s->v, s->o, s->cam, name, &s->bookmark, s->measure_line,
                                     sizeof s->measure_line, &err);
    } else {
        return 0;
    }
    if (ok) { /* flying from the bookmark, as from Home */
        s->nav.orbit = 0;
        tp_camera_get_pose(s->cam, &s->nav.yaw_deg, &s->nav.pitch_deg);
        s->has_mark = 0;
    } else {
        snprintf(s->measure_line, sizeof s->measure_line, "%s", err.message);
    }
    printf("%s\n", s->measure_line);
    fflush(stdout);
    return 1;
}

/* The controls held during this frame. */
static tp_nav_controls controls(const tp_input* in, double look_dx, double look_dy)
{
#define HELD(k) tp_input_held(in, GLFW_KEY_##k)
    tp_nav_controls c = {.look_dx = look_dx, .look_dy = look_dy, .zoom_steps = in->scroll_y};
    c.forward = HELD(W) - HELD(S);
    c.right = (HELD(D) || HELD(RIGHT)) - (HELD(A) || HELD(LEFT));
    c.up = (HELD(E) || HELD(UP)) - (HELD(Q) || HELD(DOWN));
    c.speed_factor = HELD(LEFT_SHIFT) || HELD(RIGHT_SHIFT) ? 5
                   : HELD(LEFT_CONTROL) || HELD(RIGHT_CONTROL) ? 0.2 : 1;
#undef HELD
    return c;
}

/* A preview's run ends when the store lands, and the store's run goes on from its state:
 * save (1) the keys' state, the level of detail and the navigation into o, or take (0) them. */
static void window_keep(window_state* s, view_options* o, int save)
{
    if (save) {
        o->window_keep.set = 1;
        o->window_keep.shots = s->shots, o->window_keep.exports = s->exports;
        o->window_keep.frozen = s->frozen, o->window_keep.show_hud = s->show_hud;
        o->window_keep.show_details = s->show_details, o->window_keep.show_help = s->show_help;
        o->window_keep.nav = s->nav;
        o->vs.lod = s->lod;
        return;
    }
    s->shots = o->window_keep.shots, s->exports = o->window_keep.exports;
    s->frozen = o->window_keep.frozen, s->show_hud = o->window_keep.show_hud;
    s->show_details = o->window_keep.show_details, s->show_help = o->window_keep.show_help;
    s->nav = o->window_keep.nav;
}

/* The window's title: frame rate, triangles, mode, and what a preview is. */
static void window_title(const window_state* s, double fps, size_t triangles, char* out,
                         size_t cap)
{
    char preview[96] = ""; /* what is drawn until the store lands */
    if (s->o->preview)
        snprintf(preview, sizeof preview, " - a preview of every %d%s post: building the store",
                 s->o->first.coarsen, s->o->first.coarsen == 2 ? "nd" : "th");
    snprintf(out, cap, "terrapatch - %.1f fps, %zu triangles, %s mode%s%s", fps, triangles,
             s->nav.orbit ? "orbit" : "fly", s->frozen ? " (LoD frozen)" : "", preview);
}

int tp_view_window_run(tp_view_scene* v, tp_gl_context* ctx, tp_renderer* r, tp_camera* cam,
                       view_options* o)
{
    GLFWwindow* win = tp_gl_context_window(ctx);
    static tp_input in; /* the callbacks' user pointer: must outlive event processing */
    tp_input_attach(&in, win);
    window_state s = {.v = v,
                      .cam = cam,
                      .o = o,
                      .lod = o->vs.lod,
                      .show_hud = !o->no_hud,
                      .show_details = o->hud_details,
                      .bookmark = -1,
                      .ground = o->ground};
    const double* gt = v->gt;
    tp_nav_init(&s.nav, cam, fmax(v->src_width * fabs(gt[1]), v->src_height * fabs(gt[5])));
    if (o->window_keep.set) /* the store after its preview: the keys' state goes on */
        window_keep(&s, o, 0);
    tp_hud* hud = tp_hud_create();
    tp_measured_error me = {0};
    double measured_at = -1e9, fps = 0, last = glfwGetTime(), mx0 = 0, my0 = 0;
    int dragging = 0, frames = 0, idle = 0;
    /* Ctrl-C kills the window at once, except during a screenshot or an export (Y): then the
     * writer cleans up, and the loop ends here (main exits with 130/143). */
    while (!glfwWindowShouldClose(win) && !s.quit && !v->store_changed && !tp_interrupted()) {
        if (o->preview && tp_store_cache_job_done(o->job)) { /* the store landed: go on there */
            o->refine = 1;
            o->resume_cam = *cam;
            window_keep(&s, o, 1);
            break;
        }
        tp_input_begin_frame(&in);
        /* over a preview, a still view is drawn 10 times a second: the store's build on the
         * other thread gets the cores that llvmpipe would take */
        if (idle)
            glfwWaitEventsTimeout(0.1);
        else
            glfwPollEvents();
        const tp_camera before = *cam;
        int events = 0;
        double now = glfwGetTime(), dt = now - last;
        last = now;
        tp_input_event ev;
        while (tp_input_next(&in, &ev)) {
            events++;
            if (ev.kind == TP_INPUT_KEY && bookmark_key(&s, ev.key, ev.mods))
                continue;
            if (ev.kind == TP_INPUT_KEY)
                on_key(&s, ev.key, ev.mods);
            else if (ev.kind == TP_INPUT_CHAR)
                on_char(&s, ev.key);
            else if (ev.kind == TP_INPUT_CLICK && ev.key == GLFW_MOUSE_BUTTON_RIGHT && s.los_mode)
                los_click(&s, win, ev.x, ev.y);
            else if (ev.kind == TP_INPUT_CLICK && ev.key == GLFW_MOUSE_BUTTON_RIGHT)
                measure_click(&s, win, ev.x, ev.y);
            else if (ev.kind == TP_INPUT_CLICK && ev.key == GLFW_MOUSE_BUTTON_MIDDLE)
                point_click(&s, win, ev.x, ev.y);
        }
        double mx, my, look_dx = 0, look_dy = 0;
        glfwGetCursorPos(win, &mx, &my);
        int left = glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
        if (left && dragging)
            look_dx = mx - mx0, look_dy = my - my0;
        dragging = left;
        mx0 = mx, my0 = my;

        /* navigation in drawn space (heights times the exaggeration), then terrain following */
        double zs = o->render.exaggeration, x, y;
        tp_view_scene_set_vertical_scale(v, zs);
        tp_view_scene_world_to_grid(v, cam->position[0], cam->position[1], &x, &y);
        double ground = tp_view_scene_ground_height(v, x, y) * zs;
        tp_nav_controls c = controls(&in, look_dx, look_dy);
        tp_nav_step(&s.nav, &c, dt, ground, cam);
        tp_view_scene_keep_above(v, cam->position, 2.0);
        if (s.nav.orbit) { /* the target follows the ground as it pans */
            tp_view_scene_world_to_grid(v, s.nav.target[0], s.nav.target[1], &x, &y);
            double tz = tp_view_scene_ground_height(v, x, y);
            if (!isnan(tz))
                s.nav.target[2] = tz * zs;
        }
        idle = o->preview && !events && !left && !memcmp(&before, cam, sizeof before);
        int w, h;
        glfwGetFramebufferSize(win, &w, &h);
        cam->viewport_w_px = w > 0 ? w : 1;
        cam->viewport_h_px = h > 0 ? h : 1;

        tp_gl_context_begin_frame(ctx);
        frame_result fr = {0}; /* the paths set only what they draw */
        tp_render_settings rs = o->render; /* the grid's spacing follows the scale */
        rs.grid_m = tp_view_grid_spacing(v, cam, o->render.grid_m);
        tp_view_frame(v, r, cam, &rs, &s.lod, s.frozen, &fr);
        fr.msaa = tp_gl_context_msaa(ctx);
        /* the first dt only spans the set-up before the first poll */
        if (frames++ > 0)
            fps = fps > 0 ? 0.9 * fps + 0.1 / fmax(dt, 1e-6) : 1 / fmax(dt, 1e-6);
        char text[4096];
        tp_overlay ov = {.grid_m = rs.grid_m,
                         .measure_line = s.measure_line,
                         .has_mark = s.has_mark,
                         .near_m = fr.render.near_m,
                         .far_m = fr.render.far_m};
        memcpy(ov.mark_enh, s.mark, sizeof ov.mark_enh);
        if (s.los.count > 1)
            ov.los = &s.los.overlay;
        if (s.viewshed.overlay.count)
            ov.viewshed = &s.viewshed.overlay;
        if (o->layers)
            ov.drape_count = tp_view_layers_drawn(o->layers, &ov.drapes);
        if (s.show_hud) {
            if (s.show_details && now - measured_at > 1.0) { /* once a second */
                tp_view_measure_now(v, cam, &me);
                measured_at = now;
            }
            char legend[512] = "";
            if (o->layers)
                tp_view_layers_legend(o->layers, legend, sizeof legend);
            char sun[160];
            tp_view_sun_text(&o->sun, sun, sizeof sun);
            tp_hud_state hs = {.fps = fps,
                               .frozen = s.frozen,
                               .orbit = s.nav.orbit,
                               .speed_mps = s.nav.speed_mps,
                               .exaggeration = zs,
                               .layers = legend,
                               .sun = sun,
                               .grid_m = rs.grid_m,
                               .details = s.show_details};
            tp_view_hud_text(v, cam, &s.lod, &fr, &me, &hs, text, sizeof text);
            ov.hud_text = text;
            ov.help_text = s.show_help ? help_text : NULL;
        }
        tp_view_overlay_draw(hud, v, cam, &ov);
        if (s.want_shot) {
            char name[64];
            snprintf(name, sizeof name, "terrapatch-%03d.png", s.shots++);
            if (tp_view_screenshot(ctx, name))
                printf("screenshot: %s\n", name);
            fflush(stdout);
            s.want_shot = 0;
        }
        tp_gl_context_end_frame(ctx);
        tp_store_cache_job_start(o->job); /* a preview drawn: the store's build goes on */
        char title[256];
        window_title(&s, fps, fr.core.triangles, title, sizeof title);
        glfwSetWindowTitle(win, title);
    }
    tp_hud_destroy(hud);
    tp_view_los_free(&s.los);
    tp_view_viewshed_free(&s.viewshed);
    if (s.ground != o->ground) /* the layers' ground is run_view's */
        tp_ground_destroy(s.ground);
    return v->store_changed ? TP_EXIT_FAILURE : TP_EXIT_OK;
}
