/*
 * cmd_view.c - `terrapatch view [options] [DEM]`: the viewer, in a window or headless.
 *
 * Each frame: select levels and cull (core), upload the vertex data that changed and draw
 * (renderer.c). Headless frames are complete and deterministic: everything is loaded before the
 * first frame and there is no multisampling.
 */
#define _POSIX_C_SOURCE 200809L
#include "atomic_file.h"
#include "camera_pose.h"
#include "cli.h"
#include "gl_context.h"
#include "hud.h"
#include "json.h"
#include "measure.h"
#include "mesh_export.h"
#include "renderer.h"
#include "scene.h"
#include "view_options.h"
#include "tp_geo.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define DEG (3.14159265358979323846 / 180.0)
#define TP_SAMPLE_SCENE "data/lf_elev_220_mt_hood_utm.tif"

typedef struct view_options {
    tp_scene_options scene;
    tp_view_setup vs; /* level of detail, camera, field of view, size */
    tp_render_settings render;
    int headless, frames, no_hud, hud;
    const char* screenshot;
    const char* texture;
    int has_measure;
    double measure[4]; /* E1, N1, E2, N2 */
    const char* stats_json;
    const char* path;
} view_options;

enum {
    OPT_HEADLESS = 256,
    OPT_FRAMES,
    OPT_SCREENSHOT,
    OPT_CLEAR,
    OPT_WIREFRAME,
    OPT_COLOR_LOD,
    OPT_STATS,
    OPT_NO_HUD,
    OPT_EXAG,
    OPT_ONE_DRAW,
    OPT_HUD,
    OPT_HIDE_FILLED,
    OPT_TEXTURE,
    OPT_GRID,
    OPT_MEASURE,
    OPT_SUN,
};

static void print_help(void)
{
    fputs("usage: terrapatch view [options] [DEM]\n"
          "\n"
          "Shows DEM (default: the sample " TP_SAMPLE_SCENE ") as shaded terrain, each patch\n"
          "at its own level of detail. In a window when there is a display; --headless renders\n"
          "offscreen (EGL, no display needed) and writes --screenshot.\n"
          "\n"
          "level of detail:\n"
          "  --lod distance|error  distance: Vanek & Jezek's mindist/maxdist/exp rule; error\n"
          "                        (default): the coarsest level whose error stays <= --tau px\n"
          "  --tau PX              screen-space error threshold (default 1)\n"
          "  --mindist M, --maxdist M, --exp E   distance rule (defaults: 1 and 24 patch widths, 1)\n"
          "camera:\n"
          "  --camera E,N,H,YAW,PITCH      position in the render grid's projected CRS (metres),\n"
          "                                height H above the DEM's vertical datum, yaw degrees\n"
          "                                clockwise from grid north, pitch degrees (-90: down)\n"
          "  --camera-geo LAT,LON,H,YAW,PITCH   the same with a WGS84 position\n"
          "  --fov DEG             vertical field of view (default 60)\n"
          "  (default camera: the whole DEM in view, from the south)\n"
          "output:\n"
          "  --size WxH            window or image size (default 1280x720)\n"
          "  --headless            render offscreen through EGL\n"
          "  --frames N            headless: frames to render (default 1); the last is kept\n"
          "  --screenshot FILE     write the last frame (PNG, through OpenImageIO)\n"
          "  --stats-json FILE     write the last frame's statistics\n"
          "  --clear-color R,G,B   background, 0..1 each\n"
          "  --wireframe, --color-lod   draw edges only / colour patches by level\n"
          "  --exaggeration X      vertical exaggeration (default 1)\n"
          "  --sun AZ,EL           hillshade light: azimuth clockwise from grid north and\n"
          "                        elevation, degrees (default 315,45)\n"
          "  --hide-filled         draw filled voids like measured ground (default: tinted)\n"
          "  --measure E1,N1,E2,N2 print the geodesic distance, true and grid bearing and height\n"
          "                        difference between two ground points (render CRS)\n"
          "  --grid M              grid lines every M metres of the render CRS, labelled (for a\n"
          "                        UTM render grid: the UTM/MGRS grid; 1000 = the 1 km grid)\n"
          "  --texture FILE        drape an image: an orthophoto georeferenced through GDAL (warped\n"
          "                        onto the render grid), or any image covering the DEM's extent\n"
          "  --one-draw-per-patch  one draw call per patch instead of multi-draw\n"
          "  --no-hud              no text overlay (frame times, triangles, levels, error,\n"
          "                        camera and centre position as lat/lon, UTM and MGRS)\n"
          "  --hud                 headless frames too get the overlay (off by default there,\n"
          "                        so that a headless image depends on the view alone)\n"
          "DEM:\n",
          stdout);
    tp_scene_options_help(stdout);
    fputs("\nWindow keys: W/S forward/back, A/D left/right, Q/E down/up, drag with the left\n"
          "mouse button to look around, L colour by level, T wireframe, F freeze LoD and\n"
          "culling, M switch LoD mode, +/- tau (or maxdist), [ ] mindist, , . exp, X/Z vertical\n"
          "exaggeration, J/K sun azimuth, U/N sun elevation, V tint\n"
          "of filled voids, G 1 km grid, P screenshot, Y export the view's mesh (.vtp), C print the camera as --camera-geo and --camera\n"
          "options, H hide the HUD, O orbit mode (drag rotates around the point looked at, wheel\n"
          "or W/S zoom, A/D/Q/E pan), right-click twice to measure, ? key help, Esc quit.\n"
          "\nExit status: 0 success, 1 failure, 2 usage error.\n",
          stdout);
}

/* The bundled sample: data/ of the source tree the binary was built in (build/terrapatch ->
 * ../data), else data/ of the working directory. */
static const char* sample_scene(void)
{
    static char path[4096];
    ssize_t n = readlink("/proc/self/exe", path, sizeof path - 64);
    if (n > 0) {
        path[n] = '\0';
        char* slash = strrchr(path, '/');
        if (slash) {
            strcpy(slash, "/../" TP_SAMPLE_SCENE);
            if (access(path, R_OK) == 0)
                return path;
        }
    }
    return TP_SAMPLE_SCENE;
}

static int bad(const char* opt, const char* expected, const char* got)
{
    tp_option_error("view", opt, expected, got);
    return TP_EXIT_USAGE;
}

static int parse_options(int argc, char** argv, view_options* o)
{
    static const struct option longs[] = {
        TP_SCENE_LONG_OPTIONS,
        TP_VIEW_LONG_OPTIONS,
        {"headless", no_argument, NULL, OPT_HEADLESS},
        {"frames", required_argument, NULL, OPT_FRAMES},
        {"screenshot", required_argument, NULL, OPT_SCREENSHOT},
        {"clear-color", required_argument, NULL, OPT_CLEAR},
        {"wireframe", no_argument, NULL, OPT_WIREFRAME},
        {"color-lod", no_argument, NULL, OPT_COLOR_LOD},
        {"stats-json", required_argument, NULL, OPT_STATS},
        {"no-hud", no_argument, NULL, OPT_NO_HUD},
        {"hud", no_argument, NULL, OPT_HUD},
        {"hide-filled", no_argument, NULL, OPT_HIDE_FILLED},
        {"texture", required_argument, NULL, OPT_TEXTURE},
        {"grid", required_argument, NULL, OPT_GRID},
        {"measure", required_argument, NULL, OPT_MEASURE},
        {"sun", required_argument, NULL, OPT_SUN},
        {"exaggeration", required_argument, NULL, OPT_EXAG},
        {"one-draw-per-patch", no_argument, NULL, OPT_ONE_DRAW},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    memset(o, 0, sizeof *o);
    tp_scene_options_default(&o->scene);
    tp_render_settings_default(&o->render);
    tp_view_setup_default(&o->vs);
    o->frames = 1;
    opterr = 0;
    optind = 1;
    int c;
    double v[5];
    char* end;
    while ((c = getopt_long(argc, argv, ":h", longs, NULL)) != -1) {
        int taken = c == '?' || c == ':' ? 0 : tp_scene_option(c, optarg, &o->scene, "view");
        if (!taken && c != '?' && c != ':')
            taken = tp_view_option(c, optarg, &o->vs, "view");
        if (taken < 0)
            return TP_EXIT_USAGE;
        if (taken)
            continue;
        switch (c) {
        case OPT_EXAG:
            if (!tp_parse_numbers(optarg, v, 1) || !(v[0] > 0))
                return bad("--exaggeration", "a number > 0", optarg);
            o->render.exaggeration = v[0];
            break;
        case OPT_HEADLESS: o->headless = 1; break;
        case OPT_FRAMES: {
            long n = strtol(optarg, &end, 10);
            if (*end || n < 1 || n > 1000000)
                return bad("--frames", "a count >= 1", optarg);
            o->frames = (int)n;
            break;
        }
        case OPT_SCREENSHOT: o->screenshot = optarg; break;
        case OPT_STATS: o->stats_json = optarg; break;
        case OPT_CLEAR:
            if (!tp_parse_numbers(optarg, v, 3) || v[0] < 0 || v[0] > 1 || v[1] < 0 || v[1] > 1 ||
                v[2] < 0 || v[2] > 1)
                return bad("--clear-color", "R,G,B in 0..1", optarg);
            for (int i = 0; i < 3; i++)
                o->render.clear_rgb[i] = (float)v[i];
            break;
        case OPT_WIREFRAME: o->render.wireframe = 1; break;
        case OPT_COLOR_LOD: o->render.color_lod = 1; break;
        case OPT_NO_HUD: o->no_hud = 1; break;
        case OPT_HUD: o->hud = 1; break;
        case OPT_HIDE_FILLED: o->render.hide_filled = 1; break;
        case OPT_TEXTURE: o->texture = optarg; break;
        case OPT_SUN:
            if (!tp_parse_numbers(optarg, v, 2) || v[1] < 0 || v[1] > 90)
                return bad("--sun", "AZIMUTH,ELEVATION in degrees (elevation 0..90)", optarg);
            o->render.sun_azimuth_deg = v[0];
            o->render.sun_elevation_deg = v[1];
            break;
        case OPT_MEASURE:
            if (!tp_parse_numbers(optarg, o->measure, 4))
                return bad("--measure", "E1,N1,E2,N2", optarg);
            o->has_measure = 1;
            break;
        case OPT_GRID:
            if (!tp_parse_numbers(optarg, v, 1) || v[0] < 0 || (v[0] > 0 && v[0] < 1))
                return bad("--grid", "a line spacing in metres >= 1 (0: none)", optarg);
            o->render.grid_m = v[0];
            break;
        case OPT_ONE_DRAW: o->render.one_draw_per_patch = 1; break;
        case 'h': print_help(); return tp_cli_finish(TP_EXIT_OK);
        case ':':
            fprintf(stderr, "terrapatch view: missing value for %s\n", argv[optind - 1]);
            return TP_EXIT_USAGE;
        default:
            fprintf(stderr, "terrapatch view: unknown option '%s' (see 'terrapatch view --help')\n",
                    argv[optind - 1]);
            return TP_EXIT_USAGE;
        }
    }
    if (argc - optind > 1) {
        fprintf(stderr, "terrapatch view: expected one DEM, got extra argument '%s'\n",
                argv[optind + 1]);
        return TP_EXIT_USAGE;
    }
    o->path = optind < argc ? argv[optind] : sample_scene();
    if (tp_view_setup_check(&o->vs, "view") < 0)
        return TP_EXIT_USAGE;
    return -1;
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

typedef struct frame_result {
    tp_frame_stats core;
    tp_render_stats render;
    double select_ms;
} frame_result;

static int write_stats(const char* path, const frame_result* f, const tp_error_measure* em,
                       double max_px, double rms_px, int levels)
{
    tp_atomic_file file;
    if (!tp_atomic_open(&file, path))
        return 0;
    FILE* out = file.f;
    tp_json j;
    tp_json_init(&j, out);
    tp_json_object_begin(&j);
#define KEY_NUM(k, v) (tp_json_key(&j, k), tp_json_number(&j, v))
#define KEY_SIZE(k, v) (tp_json_key(&j, k), tp_json_size(&j, v))
    KEY_SIZE("triangles", f->core.triangles);
    KEY_SIZE("draw_calls", (size_t)f->render.draw_calls);
    KEY_SIZE("patches_drawn", (size_t)f->render.patches_drawn);
    KEY_SIZE("patches_culled", (size_t)f->core.culled_patches);
    tp_json_key(&j, "levels");
    tp_json_array_begin(&j);
    for (int k = 0; k < levels; k++)
        tp_json_int(&j, f->core.patches_per_level[k]);
    tp_json_array_end(&j);
    KEY_NUM("cpu_ms", f->select_ms + f->render.upload_ms);
    KEY_NUM("select_ms", f->select_ms);
    KEY_NUM("upload_ms", f->render.upload_ms);
    KEY_NUM("draw_ms", f->render.draw_ms);
    KEY_SIZE("uploads", (size_t)f->render.uploads);
    KEY_SIZE("gpu_bytes", f->render.gpu_bytes);
    KEY_NUM("max_error_m", em->max_error_m);
    KEY_NUM("rms_error_m", em->rms_error_m);
    KEY_NUM("max_error_px", max_px);
    KEY_NUM("rms_error_px", rms_px);
    KEY_NUM("bound_max_error_m", f->core.bound_max_error_m);
#undef KEY_NUM
#undef KEY_SIZE
    tp_json_object_end(&j);
    fputc('\n', out);
    return tp_atomic_commit(&file);
}

static int screenshot(tp_gl_context* ctx, const char* path)
{
    int w, h;
    tp_gl_context_size(ctx, &w, &h);
    uint8_t* px = malloc((size_t)w * h * 4);
    if (!px) {
        fprintf(stderr, "terrapatch: %s: out of memory\n", path);
        return 0;
    }
    tp_gl_context_read_rgba(ctx, px);
    tp_error err;
    tp_status s = tp_image_write_rgba(path, w, h, px, &err);
    free(px);
    if (s != TP_OK) {
        fprintf(stderr, "terrapatch: %s\n", err.message);
        return 0;
    }
    return 1;
}

/* One frame: select (unless frozen), upload, draw. */
static void frame(tp_selection* sel, tp_renderer* r, const tp_camera* cam, const view_options* o,
                  const tp_lod_params* lod, int frozen, frame_result* out)
{
    double t0 = now_ms();
    tp_error err;
    if (!frozen)
        tp_selection_update(sel, cam, lod, &err);
    out->select_ms = now_ms() - t0;
    tp_renderer_draw(r, sel, cam, &o->render, 1, &out->render);
    tp_selection_stats(sel, &out->core);
}

/* A position as latitude/longitude, UTM and MGRS (1 m), or "" without a CRS. */
static void position_text(const tp_scene* sc, double e, double n, char* out, size_t cap)
{
    double lat, lon, ue, un;
    int zone, northp;
    char mgrs[TP_MGRS_SIZE];
    out[0] = '\0';
    if (tp_georef_proj_to_geo(sc->georef, e, n, &lat, &lon, NULL) != TP_OK)
        return;
    if (tp_geo_to_utmups(lat, lon, &zone, &northp, &ue, &un, NULL) != TP_OK ||
        tp_mgrs_forward(zone, northp, ue, un, lat, 5, mgrs, sizeof mgrs, NULL) != TP_OK)
        mgrs[0] = '\0';
    char zname[8];
    if (zone == TP_ZONE_UPS)
        snprintf(zname, sizeof zname, "%s", northp ? "UPS N" : "UPS S");
    else
        snprintf(zname, sizeof zname, "%d%c", zone, northp ? 'N' : 'S');
    snprintf(out, cap, "%.5f%c %.5f%c  UTM %s %.0f %.0f  MGRS %s", fabs(lat), lat >= 0 ? 'N' : 'S',
             fabs(lon), lon >= 0 ? 'E' : 'W', zname, ue, un, mgrs);
}

/* Where the ray from the camera along dir meets the drawn terrain. */
static int ground_along(const tp_scene* sc, const tp_selection* sel, const tp_camera* cam,
                        const double dir[3], double out[3])
{
    double step = fabs(sc->info.geotransform[1]), dist = 0;
    for (int i = 0; i < 4000; i++) {
        dist += step;
        step *= 1.004;
        double p[3] = {cam->position[0] + dist * dir[0], cam->position[1] + dist * dir[1],
                       cam->position[2] + dist * dir[2]};
        double x, y;
        tp_terrain_world_to_grid(sc->terrain, p[0], p[1], &x, &y);
        double g = tp_selection_drawn_height_at(sel, x, y);
        if (!isnan(g) && p[2] <= g) {
            out[0] = p[0], out[1] = p[1], out[2] = g;
            return 1;
        }
    }
    return 0;
}

static int ground_at_centre(const tp_scene* sc, const tp_selection* sel, const tp_camera* cam,
                            double out[3])
{
    double l = sqrt(cam->forward[0] * cam->forward[0] + cam->forward[1] * cam->forward[1] +
                    cam->forward[2] * cam->forward[2]);
    double dir[3] = {cam->forward[0] / l, cam->forward[1] / l, cam->forward[2] / l};
    return ground_along(sc, sel, cam, dir, out);
}

/* The ground point under pixel (sx, sy). */
static int ground_at_pixel(const tp_scene* sc, const tp_selection* sel, const tp_camera* cam,
                           double sx, double sy, double out[3])
{
    const double* f = cam->forward;
    double r[3] = {f[1] * cam->up[2] - f[2] * cam->up[1], f[2] * cam->up[0] - f[0] * cam->up[2],
                   f[0] * cam->up[1] - f[1] * cam->up[0]};
    double lr = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]), lf = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    double fw[3] = {f[0] / lf, f[1] / lf, f[2] / lf};
    for (int i = 0; i < 3; i++)
        r[i] /= lr;
    double u[3] = {r[1] * fw[2] - r[2] * fw[1], r[2] * fw[0] - r[0] * fw[2], r[0] * fw[1] - r[1] * fw[0]};
    double fpx = cam->viewport_h_px / 2.0 / tan(cam->fov_y_rad / 2);
    double a = (sx - cam->viewport_w_px / 2.0) / fpx, b = -(sy - cam->viewport_h_px / 2.0) / fpx;
    double dir[3], l = 0;
    for (int i = 0; i < 3; i++) {
        dir[i] = fw[i] + a * r[i] + b * u[i];
        l += dir[i] * dir[i];
    }
    for (int i = 0; i < 3; i++)
        dir[i] /= sqrt(l);
    return ground_along(sc, sel, cam, dir, out);
}

/* The exact error of the drawn geometry, measured now and then (it costs tens of ms). */
typedef struct measured_error {
    double max_m, rms_m, max_px, rms_px;
    int valid;
} measured_error;

static void measure_now(const tp_selection* sel, const tp_camera* cam, measured_error* m)
{
    tp_error_measure em;
    m->valid = tp_selection_measure_error(sel, &em) == TP_OK &&
               tp_selection_measure_screen_error(sel, cam, &m->max_px, &m->rms_px, NULL) == TP_OK;
    m->max_m = em.max_error_m;
    m->rms_m = em.rms_error_m;
}

static void hud_text(const tp_scene* sc, const tp_selection* sel, const tp_camera* cam,
                     const tp_lod_params* lod, const frame_result* fr, const measured_error* me,
                     double fps, int frozen, char* out, size_t cap)
{
    char measured[160] = "";
    if (me && me->valid)
        snprintf(measured, sizeof measured, "   measured max %.2f m / %.2f px, RMS %.2f m / %.2f px",
                 me->max_m, me->max_px, me->rms_m, me->rms_px);
    char pos[256], ground[640] = "";
    double g[3];
    position_text(sc, cam->position[0], cam->position[1], pos, sizeof pos);
    if (ground_at_centre(sc, sel, cam, g)) {
        char gp[256];
        position_text(sc, g[0], g[1], gp, sizeof gp);
        snprintf(ground, sizeof ground, "centre  %s  elevation %.1f m",
                 gp[0] ? gp : "(no CRS)", g[2]);
    }
    char levels[128] = "";
    size_t at = 0;
    for (int k = 0; k < sc->info.levels && at < sizeof levels; k++)
        at += (size_t)snprintf(levels + at, sizeof levels - at, " %d", fr->core.patches_per_level[k]);
    double x, y;
    tp_terrain_world_to_grid(sc->terrain, cam->position[0], cam->position[1], &x, &y);
    double below = tp_terrain_height_at(sc->terrain, x, y);
    double yaw = fmod(atan2(cam->forward[0], cam->forward[1]) / DEG + 360, 360);
    char agl[64], lod_text[128];
    if (lod->mode == TP_LOD_ERROR)
        snprintf(lod_text, sizeof lod_text, "error, tau %.3g px", lod->tau_px > 0 ? lod->tau_px : 1);
    else if (lod->mode == TP_LOD_DISTANCE)
        snprintf(lod_text, sizeof lod_text, "distance, mindist %.0f m, maxdist %.0f m, exp %.3g",
                 lod->mindist_m, lod->maxdist_m, lod->exponent > 0 ? lod->exponent : 1);
    else
        snprintf(lod_text, sizeof lod_text, "full resolution");
    if (isnan(below))
        snprintf(agl, sizeof agl, "outside the DEM");
    else
        snprintf(agl, sizeof agl, "%.1f m above ground", cam->position[2] - below);
    snprintf(out, cap,
             "%.1f fps   CPU %.2f ms (select %.2f, upload %.2f)   draw %.2f ms\n"
             "%zu triangles   %d draw calls   %d patches drawn, %d culled   per level k=0..%d:%s\n"
             "LoD %s   error bound max %.2f m, RMS %.2f m%s   GPU %.1f MB%s\n"
             "camera  %s  height %.1f m (%s)   heading %.0f deg (N ^)\n"
             "%s\n"
             "heights are as in the DEM (SRTM/DTED: EGM96 geoid)   ? help",
             fps, fr->select_ms + fr->render.upload_ms, fr->select_ms, fr->render.upload_ms,
             fr->render.draw_ms, fr->core.triangles, fr->render.draw_calls,
             fr->render.patches_drawn, fr->core.culled_patches, sc->info.n, levels,
             lod_text, fr->core.bound_max_error_m,
             fr->core.bound_rms_error_m, measured, fr->render.gpu_bytes / 1e6, frozen ? "   (LoD frozen)" : "",
             pos[0] ? pos : "(no CRS: local metres)", cam->position[2], agl, yaw, ground);
}

/* Measures between two ground points given by E, N; prints one line; 0 if off the data. */
static int measure_points(const tp_scene* sc, const tp_selection* sel, const double e[2],
                          const double n[2], char* text, size_t cap)
{
    double h[2];
    for (int i = 0; i < 2; i++) {
        double x, y;
        tp_terrain_world_to_grid(sc->terrain, e[i], n[i], &x, &y);
        h[i] = tp_selection_drawn_height_at(sel, x, y);
        if (isnan(h[i]))
            h[i] = tp_terrain_height_at(sc->terrain, x, y);
        if (isnan(h[i])) {
            snprintf(text, cap, "point %d (E %.3f, N %.3f) is not on the terrain", i + 1, e[i], n[i]);
            return 0;
        }
    }
    tp_measurement m;
    if (!tp_measure(sc->georef, e, n, h, &m)) {
        snprintf(text, cap, "the points have no geographic position");
        return 0;
    }
    tp_measurement_text(&m, text, cap);
    return 1;
}

/* Projects a world point to pixels; 0 when behind the camera or off screen. */
static int project(const tp_camera* cam, const double p[3], double* sx, double* sy)
{
    const double* f = cam->forward;
    double lf = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    double fw[3] = {f[0] / lf, f[1] / lf, f[2] / lf};
    double r[3] = {fw[1] * cam->up[2] - fw[2] * cam->up[1], fw[2] * cam->up[0] - fw[0] * cam->up[2],
                   fw[0] * cam->up[1] - fw[1] * cam->up[0]};
    double lr = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    for (int i = 0; i < 3; i++)
        r[i] /= lr;
    double u[3] = {r[1] * fw[2] - r[2] * fw[1], r[2] * fw[0] - r[0] * fw[2], r[0] * fw[1] - r[1] * fw[0]};
    double d[3] = {p[0] - cam->position[0], p[1] - cam->position[1], p[2] - cam->position[2]};
    double z = d[0] * fw[0] + d[1] * fw[1] + d[2] * fw[2];
    if (z < 1)
        return 0;
    double fpx = cam->viewport_h_px / 2.0 / tan(cam->fov_y_rad / 2);
    *sx = cam->viewport_w_px / 2.0 + fpx * (d[0] * r[0] + d[1] * r[1] + d[2] * r[2]) / z;
    *sy = cam->viewport_h_px / 2.0 - fpx * (d[0] * u[0] + d[1] * u[1] + d[2] * u[2]) / z;
    return *sx >= 0 && *sy >= 0 && *sx < cam->viewport_w_px && *sy < cam->viewport_h_px;
}

/* Labels the grid intersections around the point the camera looks at with their grid values
 * (kilometres of easting and northing, as read off a map). */
static void grid_labels(tp_hud* hud, const tp_scene* sc, const tp_selection* sel,
                        const tp_camera* cam, double spacing, float scale)
{
    double g[3];
    if (spacing <= 0 || !ground_at_centre(sc, sel, cam, g))
        return;
    double e0 = floor(g[0] / spacing) * spacing, n0 = floor(g[1] / spacing) * spacing;
    double placed[100][2];
    int nplaced = 0;
    for (int j = -4; j <= 5; j++)
        for (int i = -4; i <= 5; i++) {
            double p[3] = {e0 + i * spacing, n0 + j * spacing, 0}, x, y, sx, sy;
            tp_terrain_world_to_grid(sc->terrain, p[0], p[1], &x, &y);
            p[2] = tp_selection_drawn_height_at(sel, x, y);
            if (isnan(p[2]) || !project(cam, p, &sx, &sy))
                continue;
            /* skip labels that would overlap one already placed (zoomed-out views) */
            int clash = 0;
            for (int k = 0; k < nplaced && !clash; k++)
                clash = fabs(placed[k][0] - sx) < 80 * scale && fabs(placed[k][1] - sy) < 14 * scale;
            if (clash)
                continue;
            placed[nplaced][0] = sx;
            placed[nplaced][1] = sy;
            nplaced++;
            char text[64];
            if (spacing >= 1000)
                snprintf(text, sizeof text, "%.0fE %.0fN", p[0] / 1000, p[1] / 1000);
            else
                snprintf(text, sizeof text, "%.1fE %.1fN", p[0] / 1000, p[1] / 1000);
            tp_hud_text(hud, cam->viewport_w_px, cam->viewport_h_px, (float)sx + 3, (float)sy + 3,
                        scale, text);
        }
}

/* North arrow and scale bar at the bottom right, measured at the ground point the camera
 * looks at: "N" sits where grid north points on screen, the bar spans a round distance. */
static void compass_and_scale(tp_hud* hud, const tp_scene* sc, const tp_selection* sel,
                              const tp_camera* cam, float scale)
{
    double g[3], gx, gy, nx, ny, ex, ey;
    if (!ground_at_centre(sc, sel, cam, g) || !project(cam, g, &gx, &gy))
        return;
    double north[3] = {g[0], g[1] + 100, g[2]}, east[3] = {g[0] + 100, g[1], g[2]};
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    float cx = (float)w - 70 * scale, cy = (float)h - 60 * scale;
    if (project(cam, north, &nx, &ny)) {
        double vx = nx - gx, vy = ny - gy, l = hypot(vx, vy);
        if (l > 1e-6) {
            tp_hud_text(hud, w, h, cx - 2 * scale, cy - 3 * scale, scale, "+");
            for (int i = 1; i <= 4; i++) /* a dotted shaft toward north */
                tp_hud_text(hud, w, h, cx + (float)(vx / l * 7 * i) * scale - 1 * scale,
                            cy + (float)(vy / l * 7 * i) * scale - 4 * scale, scale, ".");
            tp_hud_text(hud, w, h, cx + (float)(vx / l * 36) * scale - 2 * scale,
                        cy + (float)(vy / l * 36) * scale - 3 * scale, scale, "N");
        }
    }
    if (project(cam, east, &ex, &ey)) {
        double m_per_px = 100 / fmax(hypot(ex - gx, ey - gy), 1e-6);
        /* a round length about 120 px long: 1, 2 or 5 times a power of ten */
        double want = 120 * scale * m_per_px, p10 = pow(10, floor(log10(want))), len = p10;
        if (5 * p10 <= want)
            len = 5 * p10;
        else if (2 * p10 <= want)
            len = 2 * p10;
        float fw, fh;
        tp_hud_measure("-", &fw, &fh);
        int chars = (int)(len / m_per_px / (fw * scale) + 0.5);
        char bar[160];
        int at = snprintf(bar, sizeof bar, "|");
        for (int i = 0; i < chars && at < (int)sizeof bar - 40; i++)
            bar[at++] = '-';
        if (len >= 1000)
            snprintf(bar + at, sizeof bar - at, "| %g km", len / 1000);
        else
            snprintf(bar + at, sizeof bar - at, "| %g m", len);
        float bw, bh;
        tp_hud_measure(bar, &bw, &bh);
        tp_hud_text(hud, w, h, (float)w - bw * scale - 130 * scale, (float)h - 20 * scale, scale, bar);
    }
}

static const char* help_text =
    "W/S forward/back   A/D left/right   Q/E down/up   left drag: look\n"
    "L colour by level   T wireframe   F freeze LoD and culling   M LoD mode\n"
    "+/- tau (or maxdist)   [ ] mindist   , . exp   X/Z exaggeration   V filled-void tint\n"
    "J/K sun azimuth   U/N sun elevation   G 1 km grid   P screenshot   Y export mesh\n"
    "O orbit mode (drag rotates, wheel or W/S zoom, A/D/Q/E pan)   C print camera   H hide HUD\n"
    "right-click twice: measure   ? this help   Esc quit";

/* Builds the texture for the render grid and hands it to the renderer. */
static int load_texture(const tp_scene* sc, tp_renderer* r, const char* path)
{
    GLint max = 4096;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max);
    tp_texture* tex = NULL;
    tp_error err;
    if (tp_texture_build(path, sc->grid, max < 8192 ? max : 8192, &tex, &err) != TP_OK) {
        fprintf(stderr, "terrapatch: %s\n", err.message);
        return 0;
    }
    /* Tiled-grid sample x sits at render-grid x * ratio (1 unless the fit resampled), whose
     * pixel centre is at u = (x_render + 0.5) / render width. */
    const tp_terrain_info* in = &sc->info;
    double rx = in->fit == TP_FIT_RESAMPLE ? (double)(in->src_width - 1) / (in->width - 1) : 1;
    double ry = in->fit == TP_FIT_RESAMPLE ? (double)(in->src_height - 1) / (in->height - 1) : 1;
    float scale[2] = {(float)(rx / sc->grid->width), (float)(ry / sc->grid->height)};
    float offset[2] = {(float)(0.5 / sc->grid->width), (float)(0.5 / sc->grid->height)};
    int ok = tp_renderer_set_texture(r, tex->rgba, tex->width, tex->height, scale, offset);
    if (!ok)
        fprintf(stderr, "terrapatch: %s: the GPU cannot hold a %dx%d texture\n", path, tex->width,
                tex->height);
    tp_texture_destroy(tex);
    return ok;
}

typedef struct interactive {
    double yaw, pitch;
    double last_x, last_y;
    int dragging;
    int orbit;          /* orbit/pan/zoom around target instead of flying */
    double target[3];   /* orbit centre: the ground point looked at when orbit began */
    double distance;    /* eye to target */
} interactive;

static double scroll_y; /* accumulated mouse wheel, from the GLFW callback */
static int right_clicks; /* right-button presses since the last frame (a click can be shorter
                            than a frame, so polling the button would miss it) */
static double right_x, right_y;
static void on_button(GLFWwindow* w, int button, int action, int mods)
{
    (void)mods;
    if (button == GLFW_MOUSE_BUTTON_RIGHT && action == GLFW_PRESS) {
        glfwGetCursorPos(w, &right_x, &right_y);
        right_clicks++;
    }
}
static void on_scroll(GLFWwindow* w, double dx, double dy)
{
    (void)w;
    (void)dx;
    scroll_y += dy;
}

static int run_window(tp_scene* sc, tp_gl_context* ctx, tp_renderer* r, tp_selection* sel,
                      tp_camera* cam, view_options* o)
{
    GLFWwindow* win = tp_gl_context_window(ctx);
    glfwSetScrollCallback(win, on_scroll);
    glfwSetMouseButtonCallback(win, on_button);
    interactive in = {0};
    in.pitch = asin(cam->forward[2]) / DEG;
    in.yaw = atan2(cam->forward[0], cam->forward[1]) / DEG;
    int frozen = 0, shots = 0, exports = 0, show_help = 0, show_hud = !o->no_hud;
    tp_hud* hud = tp_hud_create();
    double fps = 0;
    double picks[2][3];
    int picked = 0;
    measured_error me = {0};
    double measured_at = -1e9;
    char measure_line[512] = "";
    int prev[GLFW_KEY_LAST + 1] = {0};
    double last = glfwGetTime();
    tp_lod_params lod = o->vs.lod;
    while (!glfwWindowShouldClose(win)) {
        glfwPollEvents();
        double now = glfwGetTime(), dt = now - last;
        last = now;
#define PRESSED(k) (glfwGetKey(win, k) == GLFW_PRESS)
#define TAPPED(k) (PRESSED(k) && !prev[k])
        if (PRESSED(GLFW_KEY_ESCAPE))
            break;
        double mx, my;
        glfwGetCursorPos(win, &mx, &my);
        if (glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
            if (in.dragging) {
                in.yaw += 0.2 * (mx - in.last_x);
                in.pitch = fmax(-89.9, fmin(89.9, in.pitch - 0.2 * (my - in.last_y)));
            }
            in.dragging = 1;
        } else {
            in.dragging = 0;
        }
        in.last_x = mx;
        in.last_y = my;
        /* speed scales with height above ground */
        double x, y;
        tp_terrain_world_to_grid(sc->terrain, cam->position[0], cam->position[1], &x, &y);
        double ground = tp_terrain_height_at(sc->terrain, x, y);
        double agl = isnan(ground) ? 1000 : fmax(cam->position[2] - ground, 10);
        double speed = 1.5 * agl * dt;
        double fy = sin(in.yaw * DEG), fx = cos(in.yaw * DEG);
        double step[3] = {0, 0, 0};
        if (TAPPED(GLFW_KEY_O)) {
            double g[3];
            if (!in.orbit && ground_at_centre(sc, sel, cam, g)) {
                in.orbit = 1;
                memcpy(in.target, g, sizeof g);
                in.distance = sqrt((g[0] - cam->position[0]) * (g[0] - cam->position[0]) +
                                   (g[1] - cam->position[1]) * (g[1] - cam->position[1]) +
                                   (g[2] - cam->position[2]) * (g[2] - cam->position[2]));
            } else {
                in.orbit = 0;
            }
        }
        if (in.orbit) {
            /* drag rotates around the target, wheel or W/S zoom, A/D/Q/E and arrows pan */
            double zoom = pow(0.85, scroll_y) * (PRESSED(GLFW_KEY_W) ? pow(0.3, dt) : 1) *
                          (PRESSED(GLFW_KEY_S) ? pow(3.3, dt) : 1);
            scroll_y = 0;
            in.distance = fmax(20, in.distance * zoom);
            double pan = 0.8 * in.distance * dt, px = 0, py = 0;
            if (PRESSED(GLFW_KEY_D) || PRESSED(GLFW_KEY_RIGHT)) px += 1;
            if (PRESSED(GLFW_KEY_A) || PRESSED(GLFW_KEY_LEFT)) px -= 1;
            if (PRESSED(GLFW_KEY_E) || PRESSED(GLFW_KEY_UP)) py += 1;
            if (PRESSED(GLFW_KEY_Q) || PRESSED(GLFW_KEY_DOWN)) py -= 1;
            in.target[0] += pan * (px * fx + py * fy);
            in.target[1] += pan * (-px * fy + py * fx);
            double tx, ty;
            tp_terrain_world_to_grid(sc->terrain, in.target[0], in.target[1], &tx, &ty);
            double tz = tp_terrain_height_at(sc->terrain, tx, ty);
            if (!isnan(tz))
                in.target[2] = tz;
            double cp = cos(in.pitch * DEG);
            double opos[3] = {in.target[0] - in.distance * cp * fy, in.target[1] - in.distance * cp * fx,
                              in.target[2] - in.distance * sin(in.pitch * DEG)};
            tp_selection_keep_above(sel, opos, 2.0);
            tp_camera_pose(opos[0], opos[1], opos[2], in.yaw, in.pitch, o->vs.fov_deg, o->vs.w, o->vs.h, cam);
        }
        if (PRESSED(GLFW_KEY_W)) step[0] += fy, step[1] += fx;
        if (PRESSED(GLFW_KEY_S)) step[0] -= fy, step[1] -= fx;
        if (PRESSED(GLFW_KEY_D)) step[0] += fx, step[1] -= fy;
        if (PRESSED(GLFW_KEY_A)) step[0] -= fx, step[1] += fy;
        if (PRESSED(GLFW_KEY_E)) step[2] += 1;
        if (PRESSED(GLFW_KEY_Q)) step[2] -= 1;
        if (!in.orbit) {
            double pos[3] = {cam->position[0] + speed * step[0],
                             cam->position[1] + speed * step[1], cam->position[2] + speed * step[2]};
            tp_selection_keep_above(sel, pos, 2.0); /* terrain following */
            tp_camera_pose(pos[0], pos[1], pos[2], in.yaw, in.pitch, o->vs.fov_deg, o->vs.w, o->vs.h, cam);
        }
        int w, h;
        glfwGetFramebufferSize(win, &w, &h);
        cam->viewport_w_px = w > 0 ? w : 1;
        cam->viewport_h_px = h > 0 ? h : 1;
        if (TAPPED(GLFW_KEY_L)) o->render.color_lod = !o->render.color_lod;
        if (TAPPED(GLFW_KEY_T)) o->render.wireframe = !o->render.wireframe;
        if (TAPPED(GLFW_KEY_F)) frozen = !frozen;
        if (TAPPED(GLFW_KEY_H)) show_hud = !show_hud;
        if (TAPPED(GLFW_KEY_V)) o->render.hide_filled = !o->render.hide_filled;
        if (TAPPED(GLFW_KEY_G)) o->render.grid_m = o->render.grid_m > 0 ? 0 : 1000;
        /* measuring tool: right-click two ground points */
        if (right_clicks > 0) {
            right_clicks = 0;
            int ww, wh;
            glfwGetWindowSize(win, &ww, &wh);
            double px = right_x * cam->viewport_w_px / fmax(ww, 1),
                   py = right_y * cam->viewport_h_px / fmax(wh, 1);
            if (ground_at_pixel(sc, sel, cam, px, py, picks[picked % 2])) {
                picked++;
                if (picked % 2 == 0) {
                    double e[2] = {picks[0][0], picks[1][0]}, n[2] = {picks[0][1], picks[1][1]};
                    measure_points(sc, sel, e, n, measure_line, sizeof measure_line);
                    printf("measure: %s\n", measure_line);
                    fflush(stdout);
                } else {
                    snprintf(measure_line, sizeof measure_line, "first point E %.1f N %.1f; right-click the second",
                             picks[0][0], picks[0][1]);
                }
            }
        }
        if (TAPPED(GLFW_KEY_J)) o->render.sun_azimuth_deg = fmod(o->render.sun_azimuth_deg + 345, 360);
        if (TAPPED(GLFW_KEY_K)) o->render.sun_azimuth_deg = fmod(o->render.sun_azimuth_deg + 15, 360);
        if (TAPPED(GLFW_KEY_U)) o->render.sun_elevation_deg = fmin(90, o->render.sun_elevation_deg + 5);
        if (TAPPED(GLFW_KEY_N)) o->render.sun_elevation_deg = fmax(0, o->render.sun_elevation_deg - 5);
        if (TAPPED(GLFW_KEY_X)) o->render.exaggeration *= 1.25;
        if (TAPPED(GLFW_KEY_Z)) o->render.exaggeration /= 1.25;
        if (TAPPED(GLFW_KEY_SLASH)) show_help = !show_help;
        if (TAPPED(GLFW_KEY_M))
            lod.mode = lod.mode == TP_LOD_ERROR ? TP_LOD_DISTANCE : TP_LOD_ERROR;
        int more = TAPPED(GLFW_KEY_EQUAL) || TAPPED(GLFW_KEY_KP_ADD);
        int less = TAPPED(GLFW_KEY_MINUS) || TAPPED(GLFW_KEY_KP_SUBTRACT);
        if (more || less) { /* tau in error mode, maxdist in distance mode (defaults made explicit) */
            tp_lod_params full;
            if (tp_lod_params_resolve(sc->terrain, &lod, &full, NULL) == TP_OK) {
                double f = more ? 1.5 : 1 / 1.5;
                lod.tau_px = full.tau_px * (lod.mode == TP_LOD_ERROR ? f : 1);
                lod.mindist_m = full.mindist_m;
                lod.maxdist_m = fmax(full.mindist_m, full.maxdist_m * (lod.mode == TP_LOD_DISTANCE ? f : 1));
            }
        }
        if (TAPPED(GLFW_KEY_RIGHT_BRACKET) || TAPPED(GLFW_KEY_LEFT_BRACKET)) {
            tp_lod_params full;
            if (tp_lod_params_resolve(sc->terrain, &lod, &full, NULL) == TP_OK) {
                double f = TAPPED(GLFW_KEY_RIGHT_BRACKET) ? 1.25 : 0.8;
                lod.mindist_m = fmin(full.mindist_m * f, full.maxdist_m);
                lod.maxdist_m = full.maxdist_m;
            }
        }
        if (TAPPED(GLFW_KEY_PERIOD) || TAPPED(GLFW_KEY_COMMA))
            lod.exponent = (lod.exponent > 0 ? lod.exponent : 1) * (TAPPED(GLFW_KEY_PERIOD) ? 1.25 : 0.8);
        int want_shot = TAPPED(GLFW_KEY_P);
        if (TAPPED(GLFW_KEY_Y)) { /* export the current view's mesh */
            char name[64], cam_text[256], lod_text[96];
            snprintf(name, sizeof name, "terrapatch-view-%03d.vtp", exports++);
            tp_camera_text(sc, cam, cam_text, sizeof cam_text);
            snprintf(lod_text, sizeof lod_text, "mode=%s tau_px=%g",
                     lod.mode == TP_LOD_DISTANCE ? "distance" : lod.mode == TP_LOD_FULL ? "full" : "error",
                     lod.tau_px > 0 ? lod.tau_px : 1);
            tp_export_options eo = {.camera_text = cam_text, .lod_text = lod_text};
            tp_export_result er;
            if (tp_export_selection(sc, sel, &eo, name, &er)) {
                printf("exported %s: %zu triangles, measured error max %.2f m\n", name,
                       er.triangles, er.max_error_m);
                fflush(stdout);
            }
        }
        if (TAPPED(GLFW_KEY_C)) { /* print the view so it can be reproduced */
            double lat, lon;
            if (tp_georef_proj_to_geo(sc->georef, cam->position[0], cam->position[1], &lat, &lon,
                                      NULL) == TP_OK)
                printf("--camera-geo %.9f,%.9f,%.2f,%.2f,%.2f\n", lat, lon, cam->position[2],
                       fmod(in.yaw + 360, 360), in.pitch);
            printf("--camera %.3f,%.3f,%.2f,%.2f,%.2f\n", cam->position[0], cam->position[1],
                   cam->position[2], fmod(in.yaw + 360, 360), in.pitch);
            fflush(stdout);
        }
        for (int k = 0; k <= GLFW_KEY_LAST; k++)
            prev[k] = k >= GLFW_KEY_SPACE && glfwGetKey(win, k) == GLFW_PRESS;
        tp_gl_context_begin_frame(ctx);
        frame_result fr;
        frame(sel, r, cam, o, &lod, frozen, &fr);
        fps = fps > 0 ? 0.9 * fps + 0.1 / fmax(dt, 1e-6) : 1 / fmax(dt, 1e-6);
        if (hud && o->render.grid_m > 0)
            grid_labels(hud, sc, sel, cam, o->render.grid_m, 1);
        if (hud && show_hud) {
            char text[2048];
            if (now - measured_at > 1.0) { /* once a second */
                measure_now(sel, cam, &me);
                measured_at = now;
            }
            hud_text(sc, sel, cam, &lod, &fr, &me, fps, frozen, text, sizeof text);
            tp_hud_text(hud, w, h, 10, 10, 2, text);
            if (show_help)
                tp_hud_text(hud, w, h, 10, 170, 2, help_text);
            if (measure_line[0])
                tp_hud_text(hud, w, h, 10, (float)h - 80, 2, measure_line);
            compass_and_scale(hud, sc, sel, cam, 2);
        }
        if (want_shot) {
            char name[64];
            snprintf(name, sizeof name, "terrapatch-%03d.png", shots++);
            if (screenshot(ctx, name))
                printf("screenshot: %s\n", name);
        }
        tp_gl_context_end_frame(ctx);
        char title[256];
        snprintf(title, sizeof title,
                 "terrapatch - %.1f fps, %zu triangles, %d draw calls, %d patches%s", 1 / fmax(dt, 1e-6),
                 fr.core.triangles, fr.render.draw_calls, fr.render.patches_drawn,
                 frozen ? " (LoD frozen)" : "");
        glfwSetWindowTitle(win, title);
#undef PRESSED
#undef TAPPED
    }
    tp_hud_destroy(hud);
    return TP_EXIT_OK;
}

int tp_cli_view(int argc, char** argv)
{
    view_options o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    tp_scene sc;
    if ((code = tp_scene_load(o.path, &o.scene, &sc)) != TP_EXIT_OK)
        return code;
    tp_camera cam;
    if (!tp_view_setup_camera(&sc, &o.vs, &cam, "view")) {
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }

    char msg[512];
    tp_gl_context* ctx = NULL;
    int ok = o.headless ? tp_gl_context_create_headless(o.vs.w, o.vs.h, &ctx, msg, sizeof msg)
                        : tp_gl_context_create_window(o.vs.w, o.vs.h, "terrapatch", &ctx, msg, sizeof msg);
    if (!ok) {
        fprintf(stderr, "terrapatch view: %s\n", msg);
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }
    tp_renderer* r = tp_renderer_create(sc.terrain, msg, sizeof msg);
    tp_selection* sel = NULL;
    tp_error err;
    if (!r || tp_selection_create(sc.terrain, &sel, &err) != TP_OK) {
        fprintf(stderr, "terrapatch view: %s\n", r ? err.message : msg);
        tp_renderer_destroy(r);
        tp_gl_context_destroy(ctx);
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }

    if (o.texture && !load_texture(&sc, r, o.texture)) {
        tp_selection_destroy(sel);
        tp_renderer_destroy(r);
        tp_gl_context_destroy(ctx);
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }
    code = TP_EXIT_OK;
    if (o.headless) {
        frame_result fr = {0};
        tp_hud* hud = (o.hud && !o.no_hud) || o.render.grid_m > 0 ? tp_hud_create() : NULL;
        for (int i = 0; i < o.frames; i++) {
            tp_gl_context_begin_frame(ctx);
            double t0 = now_ms();
            frame(sel, r, &cam, &o, &o.vs.lod, 0, &fr);
            if (hud && o.render.grid_m > 0)
                grid_labels(hud, &sc, sel, &cam, o.render.grid_m, 1);
            if (hud && o.hud && !o.no_hud) {
                char text[2048];
                measured_error me;
                measure_now(sel, &cam, &me);
                hud_text(&sc, sel, &cam, &o.vs.lod, &fr, &me, 1000 / fmax(now_ms() - t0, 1e-6), 0,
                         text, sizeof text);
                tp_hud_text(hud, o.vs.w, o.vs.h, 10, 10, o.vs.w >= 1000 ? 2 : 1, text);
                compass_and_scale(hud, &sc, sel, &cam, o.vs.w >= 1000 ? 2 : 1);
            }
            tp_gl_context_end_frame(ctx);
        }
        tp_hud_destroy(hud);
        if (o.screenshot && !screenshot(ctx, o.screenshot))
            code = TP_EXIT_FAILURE;
        if (o.has_measure) {
            char text[512];
            double e[2] = {o.measure[0], o.measure[2]}, n[2] = {o.measure[1], o.measure[3]};
            if (measure_points(&sc, sel, e, n, text, sizeof text)) {
                printf("%s\n", text);
            } else {
                fprintf(stderr, "terrapatch view: --measure: %s\n", text);
                code = TP_EXIT_FAILURE;
            }
        }
        if (o.stats_json && code == TP_EXIT_OK) {
            tp_error_measure em = {0};
            double max_px = 0, rms_px = 0;
            tp_selection_measure_error(sel, &em);
            tp_selection_measure_screen_error(sel, &cam, &max_px, &rms_px, NULL);
            if (!write_stats(o.stats_json, &fr, &em, max_px, rms_px, sc.info.levels))
                code = TP_EXIT_FAILURE;
        }
    } else {
        code = run_window(&sc, ctx, r, sel, &cam, &o);
    }
    tp_selection_destroy(sel);
    tp_renderer_destroy(r);
    tp_gl_context_destroy(ctx);
    tp_scene_free(&sc);
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}
