/* view_options.c - the camera and level-of-detail options (see view_options.h). */
#include "view_options.h"

#include "camera_pose.h"
#include "cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void tp_view_setup_default(tp_view_setup* v)
{
    memset(v, 0, sizeof *v);
    v->lod.mode = TP_LOD_ERROR;
    v->fov_deg = 60;
    v->vertical_scale = 1;
    v->w = 1280;
    v->h = 720;
    v->msaa = -1; /* auto */
}

/* The codes of the view options (their tables below). */
enum {
    TP_OPT_LOD = 1100,
    TP_OPT_TAU,
    TP_OPT_MINDIST,
    TP_OPT_MAXDIST,
    TP_OPT_EXP,
    TP_OPT_HOLE,
    TP_OPT_CAMERA,
    TP_OPT_CAMERA_GEO,
    TP_OPT_FOV,
    TP_OPT_SIZE,
    TP_OPT_RENDERER,
    TP_OPT_PGM_GRID,
    TP_OPT_PGM_WINDOW,
    TP_OPT_MSAA,
    TP_OPT_MESH,
};

/* Reads arg for view option opt into v: 1, or -1 after a one-line message (a bad value). */
static int view_option(int opt, const char* arg, tp_view_setup* v, const char* cmd)
{
    double x;
    switch (opt) {
    case TP_OPT_LOD:
        v->lod.sphere_tree = !strcmp(arg, "spheres"); /* the distance mode, Blow's sphere tree */
        if (!strcmp(arg, "distance") || v->lod.sphere_tree)
            v->lod.mode = TP_LOD_DISTANCE;
        else if (!strcmp(arg, "error"))
            v->lod.mode = TP_LOD_ERROR;
        else if (!strcmp(arg, "full"))
            v->lod.mode = TP_LOD_FULL;
        else
            return tp_option_error(cmd, "--lod", "distance, spheres, error or full",
                                   arg);
        return 1;
    case TP_OPT_TAU:
    case TP_OPT_MINDIST:
    case TP_OPT_MAXDIST:
    case TP_OPT_EXP: {
        static const char* names[] = {"--tau", "--mindist", "--maxdist", "--exp"};
        if (!tp_parse_numbers(arg, &x, 1) || x < 0)
            return tp_option_error(cmd, names[opt - TP_OPT_TAU], "a number >= 0", arg);
        double* field[] = {&v->lod.tau_px, &v->lod.mindist_m, &v->lod.maxdist_m,
                           &v->lod.exponent};
        *field[opt - TP_OPT_TAU] = x;
        return 1;
    }
    case TP_OPT_HOLE:
        if (!tp_parse_numbers(arg, &x, 1) || !(x > 0))
            return tp_option_error(cmd, "--hole", "pixels > 0", arg);
        v->lod.hole_px = x;
        return 1;
    case TP_OPT_FOV:
        if (!tp_parse_numbers(arg, &x, 1) || !(x > 0 && x < 180))
            return tp_option_error(cmd, "--fov", "degrees in (0, 180)", arg);
        v->fov_deg = x;
        return 1;
    case TP_OPT_CAMERA:
    case TP_OPT_CAMERA_GEO: {
        int geo = opt == TP_OPT_CAMERA_GEO;
        if (!tp_parse_numbers(arg, v->camera, 5))
            return tp_option_error(cmd, geo ? "--camera-geo" : "--camera",
                                   geo ? "LAT,LON,H,YAW,PITCH" : "E,N,H,YAW,PITCH", arg);
        if (geo && !(fabs(v->camera[0]) <= 90))
            return tp_option_error(cmd, "--camera-geo", "a latitude in [-90, 90]", arg);
        v->has_camera = 1;
        v->camera_geo = geo;
        return 1;
    }
    case TP_OPT_SIZE: {
        char* end;
        long w = strtol(arg, &end, 10), h = 0;
        if (*end == 'x')
            h = strtol(end + 1, &end, 10);
        if (*end || w < 16 || h < 16 || w > 16384 || h > 16384)
            return tp_option_error(cmd, "--size", "WxH between 16 and 16384", arg);
        v->w = (int)w;
        v->h = (int)h;
        return 1;
    }
    case TP_OPT_RENDERER:
        if (strcmp(arg, "pgm") && strcmp(arg, "patches"))
            return tp_option_error(cmd, "--renderer", "patches or pgm", arg);
        v->pgm = !strcmp(arg, "pgm");
        return 1;
    case TP_OPT_PGM_GRID: {
        /* COLSxROWS[,COLSxROWS...] */
        int count = 0;
        const char* s = arg;
        while (*s) {
            char* end;
            long c = strtol(s, &end, 10), r = 0;
            if (end != s && *end == 'x')
                r = strtol(end + 1, &end, 10);
            if (c < 2 || r < 2 || c > 8192 || r > 8192 || (*end && *end != ',') ||
                count == (int)(sizeof v->pgm_grid / sizeof v->pgm_grid[0]))
                return tp_option_error(cmd, "--pgm-grid",
                                       "COLSxROWS (2 to 8192 each), at most 8 separated by commas",
                                       arg);
            v->pgm_grid[count][0] = (int)c;
            v->pgm_grid[count][1] = (int)r;
            count++;
            s = *end ? end + 1 : end;
        }
        if (count == 0)
            return tp_option_error(cmd, "--pgm-grid", "COLSxROWS", arg);
        v->pgm_grid_count = count;
        return 1;
    }
    case TP_OPT_MSAA: {
        static const char* const ok[] = {"0", "1", "2", "4", "8", "16"};
        v->msaa = -2;
        if (!strcmp(arg, "auto"))
            v->msaa = -1;
        for (int i = 0; i < 6; i++)
            if (!strcmp(arg, ok[i]))
                v->msaa = atoi(arg);
        if (v->msaa == -2)
            return tp_option_error(cmd, "--msaa", "0, 1, 2, 4, 8 or 16 (samples a pixel), or auto",
                                   arg);
        return 1;
    }
    case TP_OPT_MESH:
        if (strcmp(arg, "lattice") && strcmp(arg, "tin"))
            return tp_option_error(cmd, "--mesh", "lattice or tin", arg);
        v->mesh_tin = !strcmp(arg, "tin");
        return 1;
    case TP_OPT_PGM_WINDOW: {
        char* end;
        long n = strtol(arg, &end, 10);
        if (end == arg || *end || n < 16 || n > 8192 || (n & (n - 1)))
            return tp_option_error(cmd, "--pgm-window", "a power of two from 16 to 8192", arg);
        v->pgm_window = (int)n;
        return 1;
    }
    }
    return 1; /* not reached: opt is one of the codes above */
}

static const tp_option view_options[] = {
    TP_OPT_CODE("--lod", NULL, TP_OPT_LOD, 1),
    TP_OPT_CODE("--tau", NULL, TP_OPT_TAU, 1),
    TP_OPT_CODE("--mindist", NULL, TP_OPT_MINDIST, 1),
    TP_OPT_CODE("--maxdist", NULL, TP_OPT_MAXDIST, 1),
    TP_OPT_CODE("--exp", NULL, TP_OPT_EXP, 1),
    TP_OPT_CODE("--hole", NULL, TP_OPT_HOLE, 1),
    TP_OPT_CODE("--camera", NULL, TP_OPT_CAMERA, 1),
    TP_OPT_CODE("--camera-geo", NULL, TP_OPT_CAMERA_GEO, 1),
    TP_OPT_CODE("--fov", NULL, TP_OPT_FOV, 1),
    TP_OPT_CODE("--size", NULL, TP_OPT_SIZE, 1),
};

static const tp_option renderer_options[] = {
    TP_OPT_CODE("--renderer", NULL, TP_OPT_RENDERER, 1),
    TP_OPT_CODE("--pgm-grid", NULL, TP_OPT_PGM_GRID, 1),
    TP_OPT_CODE("--pgm-window", NULL, TP_OPT_PGM_WINDOW, 1),
    TP_OPT_CODE("--msaa", NULL, TP_OPT_MSAA, 1),
    TP_OPT_CODE("--mesh", NULL, TP_OPT_MESH, 1),
};

/* tp_option_handler of the view options. */
static int view_option_handler(void* ctx, int code, const char* value, const char* cmd)
{
    return view_option(code, value, ctx, cmd);
}

void tp_view_options_add(tp_options* p, tp_view_setup* v, int renderer)
{
    tp_options_add(p, view_options, TP_OPTIONS_COUNT(view_options), view_option_handler, v);
    if (renderer)
        tp_options_add(p, renderer_options, TP_OPTIONS_COUNT(renderer_options),
                       view_option_handler, v);
}

int tp_view_command_parse(const char* cmd, int argc, char** argv, void (*help)(void),
                          tp_option_table own, tp_scene_options* dem, tp_view_setup* v,
                          int renderer, const char** path, const char** extra)
{
    tp_options p;
    tp_options_init(&p, cmd, argc, argv, help);
    tp_options_add(&p, own.options, own.count, own.handler, own.ctx);
    tp_scene_options_add(&p, dem);
    tp_view_options_add(&p, v, renderer);
    *extra = NULL;
    for (int c; (c = tp_options_next(&p)) != TP_OPTIONS_END;) {
        if (c != TP_OPTIONS_OPERAND) /* EXIT: no CODE option is left without a handler */
            return p.exit;
        if (!*path)
            *path = p.value;
        else if (!*extra)
            *extra = p.value;
    }
    return -1;
}

int tp_view_setup_check(const tp_view_setup* v, const char* cmd)
{
    (void)cmd; /* messages name the command main() dispatched to (tp_cli_error) */
    tp_lod_params resolved;
    tp_error err;
    if (tp_lod_params_resolve(NULL, &v->lod, &resolved, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return -1;
    }
    return 0;
}

void tp_view_options_help(FILE* out)
{
    fputs("level of detail:\n"
          "  --lod error|distance|full|spheres   error (default): each patch at the coarsest level whose\n"
          "                        error projects to <= --tau px on screen; distance: Vanek &\n"
          "                        Jezek's rule on the distance from the eye to the patch;\n"
          "                        spheres: the distance rule selected through Blow's sphere\n"
          "                        tree (a store: the same cut, a frame re-deciding only the\n"
          "                        nodes whose distances the eye crossed; a DEM: as distance);\n"
          "                        full: every patch at full resolution\n"
          "  --tau PX              error mode: screen-space error threshold (default 1)\n"
          "  --mindist METRES, --maxdist METRES   distance mode, both in metres of the render\n"
          "                        grid: full resolution up to mindist, level 0 beyond maxdist\n"
          "                        (defaults: 1 and 24 patch widths, e.g. 480 and 11520 m for\n"
          "                        17-sample patches at 30 m spacing; the HUD shows them)\n"
          "  --exp E               distance mode: exponent of the rule (default 1)\n"
          "  --hole PX             a built store: the widest gap a node over a void's edge may\n"
          "                        leave along the void when drawn coarser than its samples\n"
          "                        (default 4; smaller keeps more nodes at full resolution;\n"
          "                        export ignores it and keeps every drawn sample)\n"
          "camera:\n"
          "  --camera E,N,H,YAW,PITCH      position in the render grid's projected CRS (metres),\n"
          "                                height H above the DEM's vertical datum (times view's\n"
          "                                --exaggeration: the drawn space), yaw degrees\n"
          "                                clockwise from grid north, pitch degrees (-90: down)\n"
          "  --camera-geo LAT,LON,H,YAW,PITCH   the same with a WGS84 position\n"
          "  --fov DEG             vertical field of view (default 60)\n"
          "  --size WxH            window or image size (default 1280x720)\n"
          "  (default camera: the whole DEM in view, from the south)\n",
          out);
}

void tp_view_renderer_help(FILE* out, int bench)
{
    fputs("renderer:\n"
          "  --renderer patches|pgm\n"
          "                        patches (default): the LoD options above; pgm: Persistent\n"
          "                        Grid Mapping (Livny, Kogan & El-Sana): a grid fixed in screen\n"
          "                        space mapped onto the terrain by the vertex shader every\n"
          "                        frame (rays from the eye to the base plane, heights from a\n"
          "                        pyramid at the level the ray spacing asks for: a DEM's whole,\n"
          "                        or a store's clipmap of windows around the eye, GPU memory\n"
          "                        bounded whatever its size); the LoD options do not apply\n"
          "  --pgm-window N        over a store: each pyramid level's window, N x N posts (a\n"
          "                        power of two, 16 to 8192; default 512)\n"
          "  --msaa N|auto         multisampling: N samples a pixel (0, 1, 2, 4, 8 or 16; 0 and\n"
          "                        1: none; at most what the driver offers). auto (default):\n"
          "                        4 on a GPU, none on a software renderer (Mesa's llvmpipe:\n"
          "                        GL_RENDERER), where 4 samples make a frame 2.5 to 4 times\n"
          "                        as long (docs/PERFORMANCE.md)\n"
          "  --mesh lattice|tin    over a store (a DEM's is built into the cache): lattice\n"
          "                        (default) draws each node's level-k vertex lattice; tin\n"
          "                        draws, where it has fewer triangles within the same error\n"
          "                        bound, an error-bounded TIN of the node with the lattice's\n"
          "                        outline (built on the cut's thread as the view first needs\n"
          "                        it; the lattice is drawn meanwhile). About half the\n"
          "                        triangles at --tau 1 on real relief (docs/tin.md)\n",
          out);
    fputs(bench ? "  --pgm-grid COLSxROWS[,COLSxROWS...]   with --renderer pgm: the grids to\n"
                  "                        measure, each a configuration beside the patch ones\n"
                  "                        (default 150x600,300x300,600x600: the paper's Table 1)\n"
                : "  --pgm-grid COLSxROWS  the persistent grid's vertices (default 300x300;\n"
                  "                        the paper's Table 1 has 150x600 to 400x1600)\n",
          out);
}

void tp_view_setup_warn(const tp_scene* sc, const tp_view_setup* v, const char* cmd)
{
    (void)cmd; /* messages name the command main() dispatched to (tp_cli_error) */
    tp_lod_params lp;
    if (v->lod.mode != TP_LOD_DISTANCE ||
        tp_lod_params_resolve(sc->terrain, &v->lod, &lp, NULL) != TP_OK)
        return;
    tp_terrain_info ti;
    tp_terrain_get_info(sc->terrain, &ti);
    /* one patch width in metres: 2^n grid steps */
    double patch_m = (double)(ti.patch_size - 1) * fmin(fabs(ti.geotransform[1]), fabs(ti.geotransform[5]));
    if (lp.maxdist_m < patch_m)
        tp_cli_warning(
            "--maxdist %g m is less than one patch width (%.0f m): "
            "every patch farther than %g m is drawn at level 0 (distances are in metres; the "
            "defaults are %.0f and %.0f m)",
            lp.maxdist_m, patch_m, lp.maxdist_m, patch_m, 24 * patch_m);
}

int tp_view_setup_camera(const tp_scene* sc, const tp_view_setup* v, tp_camera* cam,
                         const char* cmd)
{
    if (!v->has_camera) {
        tp_camera_default(sc, v->fov_deg, v->w, v->h, v->vertical_scale, cam);
        return 1;
    }
    return tp_camera_from_option(sc, v->camera_geo, v->camera, v->fov_deg, v->w, v->h, cam, cmd);
}
