/*
 * cmd_bench.c - `terrapatch bench DEM [options]`: speed against error, measured the same way for
 * every configuration in one run: headless (EGL) frames along a deterministic camera path, for
 * full resolution (frustum-culled) and each LoD mode, with per-frame CPU stages, draw time,
 * triangles, draw calls, GPU bytes and the measured error of the frame's geometry.
 */
#define _POSIX_C_SOURCE 200809L
#include "atomic_file.h"
#include "camera_pose.h"
#include "cli.h"
#include "gl_context.h"
#include "json.h"
#include "renderer.h"
#include "scene.h"
#include "view_options.h"

#include <epoxy/gl.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define DEG (3.14159265358979323846 / 180.0)

typedef struct bench_options {
    tp_scene_options scene;
    tp_view_setup vs; /* LoD parameters for the LoD modes, size, field of view; --camera or
                         --camera-geo makes a path of one camera */
    const char* path_name;
    const char* path_file;
    int frames;
    const char* json;
    const char* csv;
    int no_error;      /* skip the (slow) error measurement */
    const char* dem;
} bench_options;

enum {
    OPT_PATH = 256,
    OPT_PATH_FILE,
    OPT_FRAMES,
    OPT_JSON,
    OPT_CSV,
    OPT_NO_ERROR,
};

static void print_help(void)
{
    fputs("usage: terrapatch bench [options] DEM\n"
          "\n"
          "Renders headless frames (EGL) along a deterministic camera path for full resolution\n"
          "(frustum-culled), the distance LoD and the error LoD, in one run, and reports per\n"
          "configuration the median frame rate, CPU time (select + stitch + cull + upload), draw\n"
          "time (glFinish), triangles, draw calls, GPU bytes, and the measured error of the\n"
          "drawn geometry: vertical (m) and screen-space (px; for every full-resolution sample in\n"
          "view, the on-screen length between it and the drawn surface above or below it).\n"
          "\n"
          "options:\n"
          "  --path low|high|orbit  low: 60 m above the ground across the DEM's middle, looking\n"
          "                         ahead 10 deg down (default); high: a high oblique pass;\n"
          "                         orbit: around the centre\n"
          "  --path-file F          one --camera-geo LAT,LON,H,YAW,PITCH (or E,N,H,YAW,PITCH\n"
          "                         with a leading 'proj ') per line\n"
          "  --camera E,N,H,YAW,PITCH, --camera-geo LAT,LON,H,YAW,PITCH\n"
          "                         every frame from this one camera instead of a path\n"
          "  --frames N             frames per configuration (default 60)\n"
          "  --size WxH             default 1280x720; --fov DEG default 60\n"
          "  --tau PX, --mindist M, --maxdist M, --exp E   the LoD parameters (as for view;\n"
          "                         --lod is ignored: every mode is measured)\n"
          "  --json FILE            summary; --csv FILE: one row per frame and configuration\n"
          "  --no-error             skip the error measurement (faster)\n"
          "DEM:\n",
          stdout);
    tp_scene_options_help(stdout);
    fputs("\nExit status: 0 success, 1 failure, 2 usage error.\n", stdout);
}

static int bad(const char* opt, const char* expected, const char* got)
{
    tp_option_error("bench", opt, expected, got);
    return TP_EXIT_USAGE;
}

static int parse_options(int argc, char** argv, bench_options* o)
{
    static const struct option longs[] = {
        TP_SCENE_LONG_OPTIONS,
        {"path", required_argument, NULL, OPT_PATH},
        {"path-file", required_argument, NULL, OPT_PATH_FILE},
        {"frames", required_argument, NULL, OPT_FRAMES},
        TP_VIEW_LONG_OPTIONS,
        {"json", required_argument, NULL, OPT_JSON},
        {"csv", required_argument, NULL, OPT_CSV},
        {"no-error", no_argument, NULL, OPT_NO_ERROR},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    memset(o, 0, sizeof *o);
    tp_scene_options_default(&o->scene);
    o->path_name = "low";
    o->frames = 60;
    tp_view_setup_default(&o->vs);
    opterr = 0;
    optind = 1;
    int c;
    char* end;
    while ((c = getopt_long(argc, argv, ":h", longs, NULL)) != -1) {
        int taken = c == '?' || c == ':' ? 0 : tp_scene_option(c, optarg, &o->scene, "bench");
        if (!taken && c != '?' && c != ':')
            taken = tp_view_option(c, optarg, &o->vs, "bench");
        if (taken < 0)
            return TP_EXIT_USAGE;
        if (taken)
            continue;
        switch (c) {
        case OPT_PATH:
            if (strcmp(optarg, "low") && strcmp(optarg, "high") && strcmp(optarg, "orbit"))
                return bad("--path", "low, high or orbit", optarg);
            o->path_name = optarg;
            break;
        case OPT_PATH_FILE: o->path_file = optarg; break;
        case OPT_FRAMES: {
            long n = strtol(optarg, &end, 10);
            if (*end || n < 1 || n > 100000)
                return bad("--frames", "a count >= 1", optarg);
            o->frames = (int)n;
            break;
        }
        case OPT_JSON: o->json = optarg; break;
        case OPT_CSV: o->csv = optarg; break;
        case OPT_NO_ERROR: o->no_error = 1; break;
        case 'h': print_help(); return tp_cli_finish(TP_EXIT_OK);
        case ':':
            fprintf(stderr, "terrapatch bench: missing value for %s\n", argv[optind - 1]);
            return TP_EXIT_USAGE;
        default:
            fprintf(stderr, "terrapatch bench: unknown option '%s' (see 'terrapatch bench --help')\n",
                    argv[optind - 1]);
            return TP_EXIT_USAGE;
        }
    }
    if (optind >= argc) {
        fprintf(stderr, "terrapatch bench: missing DEM file\n");
        return TP_EXIT_USAGE;
    }
    o->dem = argv[optind];
    if (tp_view_setup_check(&o->vs, "bench") < 0)
        return TP_EXIT_USAGE;
    return -1;
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

/* Camera i of n along the path. */
static void path_camera(const tp_scene* sc, const bench_options* o, int i, int n, tp_camera* cam)
{
    const tp_terrain_info* in = &sc->info;
    double e0, n0, e1, n1;
    tp_terrain_grid_to_world(sc->terrain, 0, 0, &e0, &n0);
    tp_terrain_grid_to_world(sc->terrain, in->src_width - 1, in->src_height - 1, &e1, &n1);
    double ce = (e0 + e1) / 2, cn = (n0 + n1) / 2, size = fmax(fabs(e1 - e0), fabs(n1 - n0));
    double a = (i + 0.5) / n;
    if (!strcmp(o->path_name, "high")) {
        double e = e0 + (0.1 + 0.8 * a) * (e1 - e0), nn = fmin(n0, n1) - 0.15 * size;
        tp_camera_pose(e, nn, in->max_height_m + 0.35 * size, 0, -35, o->vs.fov_deg, o->vs.w, o->vs.h, cam);
    } else if (!strcmp(o->path_name, "orbit")) {
        double ang = 2 * 3.14159265358979323846 * a, r = 0.45 * size;
        double e = ce - r * sin(ang), nn = cn - r * cos(ang), h = in->max_height_m + 0.2 * size;
        double pitch = -atan2(h - (in->min_height_m + in->max_height_m) / 2, r) / DEG;
        tp_camera_pose(e, nn, h, ang / DEG, pitch, o->vs.fov_deg, o->vs.w, o->vs.h, cam);
    } else { /* low: across the middle row, 60 m above the ground, looking ahead */
        double e = e0 + (0.05 + 0.9 * a) * (e1 - e0), x, y;
        tp_terrain_world_to_grid(sc->terrain, e, cn, &x, &y);
        double g = tp_terrain_height_at(sc->terrain, x, y);
        tp_camera_pose(e, cn, (isnan(g) ? in->max_height_m : g) + 60, 90, -10, o->vs.fov_deg, o->vs.w,
                       o->vs.h, cam);
    }
}

/* Cameras from --path-file: "LAT,LON,H,YAW,PITCH" per line (or "proj E,N,H,YAW,PITCH"). */
static int read_path_file(const tp_scene* sc, const bench_options* o, tp_camera** out, int* count)
{
    FILE* f = fopen(o->path_file, "r");
    if (!f) {
        fprintf(stderr, "terrapatch: %s: cannot open: %s\n", o->path_file, strerror(errno));
        return 0;
    }
    int cap = 64, n = 0, line_no = 0;
    tp_camera* cams = malloc((size_t)cap * sizeof *cams);
    char line[512];
    while (cams && fgets(line, sizeof line, f)) {
        line_no++;
        char* s = line;
        while (*s == ' ' || *s == '\t')
            s++;
        if (*s == '#' || *s == '\n' || *s == '\0')
            continue;
        int proj = !strncmp(s, "proj ", 5);
        if (proj)
            s += 5;
        if (!strncmp(s, "--camera-geo ", 13))
            s += 13;
        double v[5];
        if (sscanf(s, "%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4]) != 5) {
            fprintf(stderr, "terrapatch: %s: line %d: expected LAT,LON,H,YAW,PITCH\n", o->path_file,
                    line_no);
            free(cams);
            fclose(f);
            return 0;
        }
        if (n == cap) {
            tp_camera* more = realloc(cams, (size_t)(cap *= 2) * sizeof *cams);
            if (!more)
                break;
            cams = more;
        }
        if (!tp_camera_from_option(sc, !proj, v, o->vs.fov_deg, o->vs.w, o->vs.h, &cams[n], "bench")) {
            free(cams);
            fclose(f);
            return 0;
        }
        n++;
    }
    fclose(f);
    if (!cams || n == 0) {
        fprintf(stderr, "terrapatch: %s: no camera in the file\n", o->path_file);
        free(cams);
        return 0;
    }
    *out = cams;
    *count = n;
    return 1;
}

typedef struct frame_row {
    double select_ms, upload_ms, draw_ms, frame_ms;
    size_t triangles, gpu_bytes;
    int draw_calls, patches;
    double max_m, rms_m, max_px, rms_px;
} frame_row;

typedef struct config_result {
    const char* name;
    tp_lod_params lod;
    frame_row* rows;
    double fps_median, frame_ms, cpu_ms, draw_ms, triangles, draw_calls;
    size_t gpu_bytes;
    double max_px, rms_px, max_m, rms_m; /* over all frames: max of maxima, RMS of RMS */
} config_result;

static int cmp_double(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static double median(double* v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static void summarize(config_result* c, int n)
{
    double* v = malloc((size_t)n * sizeof *v);
    if (!v)
        return;
    for (int i = 0; i < n; i++)
        v[i] = c->rows[i].frame_ms;
    c->frame_ms = median(v, n);
    c->fps_median = 1000 / c->frame_ms;
    for (int i = 0; i < n; i++)
        v[i] = c->rows[i].select_ms + c->rows[i].upload_ms;
    c->cpu_ms = median(v, n);
    for (int i = 0; i < n; i++)
        v[i] = c->rows[i].draw_ms;
    c->draw_ms = median(v, n);
    for (int i = 0; i < n; i++)
        v[i] = (double)c->rows[i].triangles;
    c->triangles = median(v, n);
    for (int i = 0; i < n; i++)
        v[i] = c->rows[i].draw_calls;
    c->draw_calls = median(v, n);
    double sum_m = 0, sum_px = 0;
    c->gpu_bytes = 0;
    for (int i = 0; i < n; i++) {
        const frame_row* r = &c->rows[i];
        c->max_m = fmax(c->max_m, r->max_m);
        c->max_px = fmax(c->max_px, r->max_px);
        sum_m += r->rms_m * r->rms_m;
        sum_px += r->rms_px * r->rms_px;
        c->gpu_bytes = r->gpu_bytes > c->gpu_bytes ? r->gpu_bytes : c->gpu_bytes;
    }
    c->rms_m = sqrt(sum_m / n);
    c->rms_px = sqrt(sum_px / n);
    free(v);
}

static const char* mode_name(tp_lod_mode m)
{
    return m == TP_LOD_FULL ? "full" : m == TP_LOD_DISTANCE ? "distance" : "error";
}

static int write_json(const bench_options* o, const tp_scene* sc, const config_result* c, int nc,
                      int frames)
{
    tp_atomic_file file;
    if (!tp_atomic_open(&file, o->json))
        return 0;
    FILE* f = file.f;
    tp_json j;
    tp_json_init(&j, f);
    const config_result* full = &c[0];
    const config_result* best = &c[nc - 1]; /* the error mode: the headline configuration */
    tp_json_object_begin(&j);
#define KS(k, v) (tp_json_key(&j, k), tp_json_string(&j, v))
#define KN(k, v) (tp_json_key(&j, k), tp_json_number(&j, v))
    KS("dem", o->dem);
    char size[32];
    snprintf(size, sizeof size, "%dx%d", o->vs.w, o->vs.h);
    KS("size", size);
    KS("path", o->path_file ? o->path_file : o->path_name);
    KN("frames", frames);
    KN("patches", sc->info.patch_count);
    KS("lod_mode", mode_name(best->lod.mode));
    KN("tau_px", best->lod.tau_px);
    KN("fps_median", best->fps_median);
    KN("frame_ms_median", best->frame_ms);
    KN("cpu_ms_median", best->cpu_ms);
    KN("draw_ms_median", best->draw_ms);
    KN("triangles_median", best->triangles);
    KN("draw_calls_median", best->draw_calls);
    KN("gpu_bytes", (double)best->gpu_bytes);
    KN("max_screen_error_px", best->max_px);
    KN("rms_screen_error_px", best->rms_px);
    KN("max_vertical_error_m", best->max_m);
    KN("rms_vertical_error_m", best->rms_m);
    tp_json_key(&j, "full_res");
    tp_json_object_begin(&j);
    KN("fps_median", full->fps_median);
    KN("triangles_median", full->triangles);
    KN("draw_ms_median", full->draw_ms);
    KN("cpu_ms_median", full->cpu_ms);
    tp_json_object_end(&j);
    KN("speedup_vs_full", best->fps_median / full->fps_median);
    tp_json_key(&j, "configurations");
    tp_json_array_begin(&j);
    for (int i = 0; i < nc; i++) {
        tp_json_object_begin(&j);
        KS("lod_mode", mode_name(c[i].lod.mode));
        KN("fps_median", c[i].fps_median);
        KN("frame_ms_median", c[i].frame_ms);
        KN("cpu_ms_median", c[i].cpu_ms);
        KN("draw_ms_median", c[i].draw_ms);
        KN("triangles_median", c[i].triangles);
        KN("draw_calls_median", c[i].draw_calls);
        KN("gpu_bytes", (double)c[i].gpu_bytes);
        KN("max_screen_error_px", c[i].max_px);
        KN("rms_screen_error_px", c[i].rms_px);
        KN("max_vertical_error_m", c[i].max_m);
        KN("rms_vertical_error_m", c[i].rms_m);
        tp_json_object_end(&j);
    }
    tp_json_array_end(&j);
#undef KS
#undef KN
    tp_json_object_end(&j);
    fputc('\n', f);
    return tp_atomic_commit(&file);
}

static int write_csv(const bench_options* o, const config_result* c, int nc, int frames)
{
    tp_atomic_file file;
    if (!tp_atomic_open(&file, o->csv))
        return 0;
    FILE* f = file.f;
    fprintf(f, "lod_mode,frame,frame_ms,select_ms,upload_ms,draw_ms,triangles,draw_calls,patches,"
               "gpu_bytes,max_vertical_error_m,rms_vertical_error_m,max_screen_error_px,"
               "rms_screen_error_px\n");
    for (int k = 0; k < nc; k++)
        for (int i = 0; i < frames; i++) {
            const frame_row* r = &c[k].rows[i];
            fprintf(f, "%s,%d,%.4f,%.4f,%.4f,%.4f,%zu,%d,%d,%zu,%.4f,%.4f,%.4f,%.4f\n",
                    mode_name(c[k].lod.mode), i, r->frame_ms, r->select_ms, r->upload_ms,
                    r->draw_ms, r->triangles, r->draw_calls, r->patches, r->gpu_bytes, r->max_m,
                    r->rms_m, r->max_px, r->rms_px);
        }
    return tp_atomic_commit(&file);
}

int tp_cli_bench(int argc, char** argv)
{
    bench_options o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    tp_scene sc;
    if (tp_scene_load(o.dem, &o.scene, &sc) != TP_EXIT_OK)
        return TP_EXIT_FAILURE;
    tp_camera* cams = NULL;
    int frames = o.frames;
    if (o.path_file && !read_path_file(&sc, &o, &cams, &frames)) {
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }
    tp_camera fixed;
    if (o.vs.has_camera && !tp_view_setup_camera(&sc, &o.vs, &fixed, "bench")) {
        free(cams);
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }
    char msg[512];
    tp_gl_context* ctx = NULL;
    if (!tp_gl_context_create_headless(o.vs.w, o.vs.h, &ctx, msg, sizeof msg)) {
        fprintf(stderr, "terrapatch bench: %s\n", msg);
        free(cams);
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }
    const GLubyte* renderer_name = glGetString(GL_RENDERER);
    config_result c[3] = {{.name = "full"}, {.name = "distance"}, {.name = "error"}};
    tp_lod_mode modes[3] = {TP_LOD_FULL, TP_LOD_DISTANCE, TP_LOD_ERROR};
    code = TP_EXIT_OK;
    for (int k = 0; k < 3 && code == TP_EXIT_OK; k++) {
        tp_lod_params lp = o.vs.lod;
        lp.mode = modes[k];
        tp_lod_params_resolve(sc.terrain, &lp, &c[k].lod, NULL);
        c[k].rows = calloc((size_t)frames, sizeof *c[k].rows);
        /* a fresh renderer and selection per configuration: each starts cold, as a viewer would */
        tp_renderer* r = tp_renderer_create(sc.terrain, msg, sizeof msg);
        tp_selection* sel = NULL;
        tp_error err;
        if (!c[k].rows || !r || tp_selection_create(sc.terrain, &sel, &err) != TP_OK) {
            fprintf(stderr, "terrapatch bench: %s\n", r ? "out of memory" : msg);
            tp_renderer_destroy(r);
            code = TP_EXIT_FAILURE;
            break;
        }
        tp_render_settings rs;
        tp_render_settings_default(&rs);
        for (int i = 0; i < frames; i++) {
            tp_camera cam;
            if (cams)
                cam = cams[i];
            else if (o.vs.has_camera)
                cam = fixed;
            else
                path_camera(&sc, &o, i, frames, &cam);
            frame_row* row = &c[k].rows[i];
            tp_gl_context_begin_frame(ctx);
            double t0 = now_ms();
            tp_selection_update(sel, &cam, &c[k].lod, &err);
            double t1 = now_ms();
            tp_render_stats st;
            tp_renderer_draw(r, sel, &cam, &rs, 1, &st);
            tp_gl_context_end_frame(ctx);
            double t2 = now_ms();
            tp_frame_stats fs;
            tp_selection_stats(sel, &fs);
            row->select_ms = t1 - t0;
            row->upload_ms = st.upload_ms;
            row->draw_ms = st.draw_ms;
            row->frame_ms = t2 - t0;
            row->triangles = fs.triangles;
            row->draw_calls = st.draw_calls;
            row->patches = st.patches_drawn;
            row->gpu_bytes = st.gpu_bytes;
            if (!o.no_error) { /* outside the timed part of the frame */
                tp_error_measure em;
                tp_selection_measure_error(sel, &em);
                tp_selection_measure_screen_error(sel, &cam, &row->max_px, &row->rms_px, NULL);
                row->max_m = em.max_error_m;
                row->rms_m = em.rms_error_m;
            }
            fprintf(stderr, "\rterrapatch: bench %s: frame %d/%d, %.1f ms, %zu triangles   ",
                    c[k].name, i + 1, frames, row->frame_ms, row->triangles);
        }
        fprintf(stderr, "\n");
        summarize(&c[k], frames);
        tp_selection_destroy(sel);
        tp_renderer_destroy(r);
    }
    if (code == TP_EXIT_OK) {
        printf("%s, %dx%d, %s path, %d frames, %d patches of %d, renderer %s\n", o.dem, o.vs.w, o.vs.h,
               o.path_file ? o.path_file : o.path_name, frames, sc.info.patch_count,
               sc.info.patch_size, renderer_name ? (const char*)renderer_name : "?");
        printf("%-9s %8s %9s %8s %8s %10s %6s %9s %9s %9s %9s\n", "lod", "fps", "frame ms",
               "cpu ms", "draw ms", "triangles", "calls", "max px", "rms px", "max m", "rms m");
        for (int k = 0; k < 3; k++)
            printf("%-9s %8.2f %9.2f %8.3f %8.2f %10.0f %6.0f %9.3f %9.3f %9.3f %9.3f\n",
                   c[k].name, c[k].fps_median, c[k].frame_ms, c[k].cpu_ms, c[k].draw_ms,
                   c[k].triangles, c[k].draw_calls, c[k].max_px, c[k].rms_px, c[k].max_m,
                   c[k].rms_m);
        printf("error mode vs full resolution: %.2fx the frame rate\n",
               c[2].fps_median / c[0].fps_median);
        if (o.json && !write_json(&o, &sc, c, 3, frames))
            code = TP_EXIT_FAILURE;
        if (o.csv && !write_csv(&o, c, 3, frames))
            code = TP_EXIT_FAILURE;
    }
    for (int k = 0; k < 3; k++)
        free(c[k].rows);
    free(cams);
    tp_gl_context_destroy(ctx);
    tp_scene_free(&sc);
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}
