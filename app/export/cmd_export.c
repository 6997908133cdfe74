/*
 * cmd_export.c - `terrapatch export DEM -o OUT [mode] [options]`: the meshes we draw, written
 * with VTK for ParaView: full resolution, the view-dependent mesh of a camera, or a static
 * error-bounded mesh.
 */
#include "terrapatch.h"
#include "atomic_file.h"
#include "camera_pose.h"
#include "cli.h"
#include "full_export.h"
#include "mesh_export.h"
#include "options.h"
#include "output_check.h"
#include "qm_export.h"
#include "scene.h"
#include "store_export.h"
#include "store_scene.h"
#include "terrain_open.h"
#include "tin_export.h"
#include "view_options.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef enum { MODE_VIEW = 0, MODE_FULL, MODE_MAX_ERROR, MODE_TILES } export_mode;

typedef enum { MESH_DEFAULT = 0, MESH_TIN, MESH_PATCHES } mesh_kind;

typedef struct export_options {
    tp_scene_options scene;
    export_mode mode;
    double max_error_m;
    mesh_kind mesh;   /* --max-error: a TIN (default on a DEM) or whole patches */
    tp_view_setup vs; /* level of detail, camera, field of view, size: as for view */
    int no_cull, origin_local, per_patch;
    tp_mesh_format format;
    const char* out;
    const char* path;
    /* --tiles quantized-mesh (qm_export.h) */
    const char* tiles;
    int max_zoom;
    const char* bounds;
    const char* heights;
    double bounds_deg[4];
    int threads; /* 0: not given (every core) */
} export_options;

enum { OPT_MESH = 1, OPT_ORIGIN };

static void print_help(void)
{
    fputs("usage: terrapatch export [options] DEM|STORE.tpt -o OUT\n"
          "\n"
          "Writes the triangle mesh terrapatch draws, for ParaView and GIS comparison: points in\n"
          "double precision in the render CRS (true UTM/projected metres, elevation in metres),\n"
          "shared vertices merged into one connected surface, triangles as cells. Point data\n"
          "elevation_m, void_filled; cell data patch_id, lod, max_error_m (measured against the\n"
          "source samples each triangle covers); field data CRS, UTM zone, source, camera, LoD\n"
          "parameters, triangle count, program version.\n"
          "\n"
          "mode (one of):\n"
          "  (default)             the mesh the viewer draws for --camera/--camera-geo (or the\n"
          "                        viewer's default camera), after crack removal, culled\n"
          "                        patches left out\n"
          "  --full                full resolution: every drawn sample, two triangles per cell;\n"
          "                        to a .vtp it is written a piece at a time (bands of rows;\n"
          "                        on a store, blocks of leaves) in bounded memory whatever\n"
          "                        the map's size, the points where pieces meet repeated\n"
          "                        (ParaView's Clean merges them); heights are the grid's own\n"
          "  --max-error M         static error-bounded mesh: vertical error <= M metres at every\n"
          "                        valid source sample (measured, per triangle in max_error_m)\n"
          "  --mesh tin|patches    with --max-error: tin (the default) is a triangulated\n"
          "                        irregular network (greedy Delaunay insertion, near-minimal\n"
          "                        triangles) over exactly the cells the full mesh covers, cut\n"
          "                        at voids, without patch_id and lod; patches is what the\n"
          "                        viewer draws: every patch at the coarsest\n"
          "                        level whose error stays <= M, cracks removed (M may not be\n"
          "                        below the quantisation error); a camera's mesh of a store:\n"
          "                        patches (the default) or tin, what `view --mesh tin` draws\n"
          "                        (each complete node's TIN where it has fewer triangles)\n"
          "  --no-cull             view-dependent mesh: keep the patches outside the view too\n"
          "                        (DEMs only)\n"
          "on a store (.tpt): the same modes over the tree's cut. Every node the mesh draws is\n"
          "read at full detail first (nothing substituted), nodes no longer needed are released;\n"
          "default: the cut the viewer draws for the camera; --max-error M: the TIN built in\n"
          "tiles of 256 cells, one window of full-resolution samples at a time (the map is never\n"
          "in memory whole), error <= M against the store's samples; with --mesh patches each\n"
          "node at the coarsest level whose stored bound (stitching and quantisation included)\n"
          "is <= M; --full to a .vtk or .vtm is refused above 50 M triangles (the other modes\n"
          "when they pass it); to a .vtp it streams.\n"
          "patch_id is the node id; max_error_m is measured against the store's full-resolution\n"
          "samples; void_filled comes from the store's filled bits.\n"
          "view-dependent options (as for view):\n",
          stdout);
    tp_view_options_help(stdout);
    fputs("output:\n"
          "  -o, --output OUT      .vtp (VTK XML, binary, compressed), .vtk (legacy) or .vtm\n"
          "  --per-patch           one block per patch (.vtm; DEMs only)\n"
          "  --origin local        subtract a scene origin (written to the field data)\n"
          "Cesium terrain tiles (docs/quantized_mesh.md):\n"
          "  --tiles quantized-mesh  -o DIR: a Cesium terrain tile set: DIR/layer.json and\n"
          "                        DIR/Z/X/Y.terrain, quantized-mesh-1.0 with oct-encoded\n"
          "                        normals, gzip-compressed: the HTTP server must send them\n"
          "                        with 'Content-Encoding: gzip' (as Cesium's servers do);\n"
          "                        geographic scheme (EPSG:4326, two root tiles, TMS). Each\n"
          "                        tile is an error-bounded TIN of a 218x218 lon/lat lattice\n"
          "                        of the store's surface; its true error against the store's\n"
          "                        full-resolution posts is measured and written to\n"
          "                        DIR/errors.json and layer.json's \"terrapatch\" object.\n"
          "                        Resumable: a rerun with the same options keeps the tiles\n"
          "                        written (DIR/tiles.log); other options are refused.\n"
          "  --max-zoom Z          deepest level (default: the first whose lattice is as fine\n"
          "                        as the store's posts)\n"
          "  --bounds W,S,E,N      only the tiles over this box (degrees; default the store's\n"
          "                        extent)\n"
          "  --heights ellipsoid|geoid\n"
          "                        heights above the WGS84 ellipsoid (the default: EGM96's\n"
          "                        undulation added, PROJ's egm96_15 grid) or as stored\n"
          "                        (above the geoid for SRTM)\n"
          "  --max-error M         the TIN's bound at the deepest level, doubled per level\n"
          "                        above it (default: Cesium's geometric error of each level,\n"
          "                        77067 m / 2^z)\n"
          "  --threads N           threads building a level's tiles (default: every core);\n"
          "                        the tile set is the same bytes for any N\n"
          "DEM:\n",
          stdout);
    tp_scene_options_help(stdout);
    fputs("\nWrites atomically (a temporary file of a random name beside OUT, then a rename): a\n"
          "failure, a full disk or SIGINT/SIGTERM leaves no temporary file and an older OUT as it\n"
          "was. OUT's folder is checked before the DEM is read.\n"
          "Exit status: 0 success, 1 failure, 2 usage error, 130/143 after SIGINT/SIGTERM.\n",
          stdout);
}

static int bad(const char* opt, const char* expected, const char* got)
{
    tp_option_error("export", opt, expected, got);
    return TP_EXIT_USAGE;
}

/* --mesh and --origin (tp_option_handler). */
static int code_option(void* ctx, int code, const char* v, const char* cmd)
{
    export_options* o = ctx;
    if (code == OPT_MESH) {
        if (strcmp(v, "tin") && strcmp(v, "patches"))
            return bad("--mesh", "tin or patches", v), -1;
        o->mesh = !strcmp(v, "tin") ? MESH_TIN : MESH_PATCHES;
    } else if (!strcmp(v, "local")) { /* --origin: "local" here, LAT,LON for heightmap images */
        o->origin_local = 1;
    } else if (tp_scene_option(TP_OPT_ORIGIN, v, &o->scene, cmd) < 0) {
        return -1;
    }
    return 1;
}

/* --tiles and its options (parse_options' tail for a tile set). */
static int parse_tiles(export_options* o, int full, const char* extra)
{
    if (!o->tiles) {
        tp_cli_error("--max-zoom, --bounds, --heights and --threads go with --tiles "
                     "quantized-mesh");
        return TP_EXIT_USAGE;
    }
    if (strcmp(o->tiles, "quantized-mesh"))
        return bad("--tiles", "quantized-mesh", o->tiles);
    if (full || o->mesh != MESH_DEFAULT || o->no_cull || o->per_patch || o->origin_local ||
        o->vs.has_camera) {
        tp_cli_error("--tiles quantized-mesh takes none of --full, --mesh, --no-cull, "
                     "--per-patch, --origin, --camera");
        return TP_EXIT_USAGE;
    }
    if (o->heights && strcmp(o->heights, "ellipsoid") && strcmp(o->heights, "geoid"))
        return bad("--heights", "ellipsoid or geoid", o->heights);
    if (o->bounds) {
        double* b = o->bounds_deg;
        char tail;
        if (sscanf(o->bounds, "%lf,%lf,%lf,%lf%c", &b[0], &b[1], &b[2], &b[3], &tail) != 4 ||
            !(b[0] < b[2] && b[1] < b[3]) || b[0] < -180 || b[2] > 180 || b[1] < -90 ||
            b[3] > 90)
            return bad("--bounds", "W,S,E,N in degrees, W < E within -180..180, S < N within "
                       "-90..90", o->bounds);
    }
    if (!o->out) {
        tp_cli_error("missing -o DIR (the tile set's folder)");
        return TP_EXIT_USAGE;
    }
    if (!o->path) {
        tp_cli_error("missing DEM or store");
        return TP_EXIT_USAGE;
    }
    if (extra) {
        tp_cli_error("expected one DEM, got extra argument '%s'", extra);
        return TP_EXIT_USAGE;
    }
    if (o->threads == 0) { /* as build's --threads */
        long n = sysconf(_SC_NPROCESSORS_ONLN);
        o->threads = n > 0 ? (int)(n > 1024 ? 1024 : n) : 1;
    }
    o->mode = MODE_TILES;
    return -1;
}

static int parse_options(int argc, char** argv, export_options* o)
{
    memset(o, 0, sizeof *o);
    tp_scene_options_default(&o->scene);
    tp_view_setup_default(&o->vs);
    int full = 0;
    o->max_error_m = -1; /* not given */
    o->max_zoom = -1;
    const tp_option options[] = {
        TP_OPT_TEXT("--output", "-o", &o->out),
        TP_OPT_FLAG("--full", &full),
        TP_OPT_NUMBER("--max-error", &o->max_error_m, 0, DBL_MAX, "metres >= 0"),
        TP_OPT_CODE("--mesh", NULL, OPT_MESH, 1),
        TP_OPT_FLAG("--no-cull", &o->no_cull),
        TP_OPT_CODE("--origin", NULL, OPT_ORIGIN, 1), /* before the DEM options' --origin */
        TP_OPT_FLAG("--per-patch", &o->per_patch),
        TP_OPT_TEXT("--tiles", NULL, &o->tiles),
        TP_OPT_INTEGER("--max-zoom", &o->max_zoom, 0, 22, "a level 0..22"),
        TP_OPT_TEXT("--bounds", NULL, &o->bounds),
        TP_OPT_TEXT("--heights", NULL, &o->heights),
        TP_OPT_INTEGER("--threads", &o->threads, 1, 1024, "1 .. 1024"),
    };
    const tp_option_table own = {options, TP_OPTIONS_COUNT(options), code_option, o};
    const char* extra;
    const int code = tp_view_command_parse("export", argc, argv, print_help, own, &o->scene,
                                           &o->vs, 0, &o->path, &extra);
    if (code >= 0)
        return code;
    if (o->tiles || o->bounds || o->heights || o->max_zoom >= 0 || o->threads)
        return parse_tiles(o, full, extra);
    if (full && o->max_error_m >= 0) {
        tp_cli_error("--full and --max-error exclude each other");
        return TP_EXIT_USAGE;
    }
    o->mode = full ? MODE_FULL : o->max_error_m >= 0 ? MODE_MAX_ERROR : MODE_VIEW;
    o->max_error_m = fmax(o->max_error_m, 0);
    if (o->mesh != MESH_DEFAULT && o->mode == MODE_FULL) {
        tp_cli_error("--mesh goes with --max-error M or a camera's mesh (--full writes every "
                     "sample)");
        return TP_EXIT_USAGE;
    }
    if (!o->out) {
        tp_cli_error("missing -o OUT (a .vtp, .vtk or .vtm file)");
        return TP_EXIT_USAGE;
    }
    tp_output_format of;
    if (tp_cli_output_format("export", "-o", o->out, TP_OUTPUT_MESH, &of) != TP_EXIT_OK)
        return TP_EXIT_USAGE;
    o->format = of.mesh;
    if (o->per_patch && o->format != TP_MESH_VTM)
        return bad("--per-patch", "an output ending in .vtm", o->out);
    if (!o->path) {
        tp_cli_error("missing DEM file");
        return TP_EXIT_USAGE;
    }
    if (extra) {
        tp_cli_error("expected one DEM, got extra argument '%s'", extra);
        return TP_EXIT_USAGE;
    }
    if (tp_view_setup_check(&o->vs, "export") < 0)
        return TP_EXIT_USAGE;
    return -1;
}

static void print_written(const char* out, const tp_export_result* res, size_t full)
{
    printf("wrote %s: %zu points, %zu triangles (%.1f%% of the %zu of the full mesh), "
           "measured error max %.3f m, RMS %.3f m\n",
           out, res->points, res->triangles, 100.0 * res->triangles / (full ? full : 1), full,
           res->max_error_m, res->rms_error_m);
}

/* --max-error M --mesh tin on a DEM; frees the scene. */
static int export_tin(const export_options* o, tp_scene* sc)
{
    char lod_text[160];
    snprintf(lod_text, sizeof lod_text, "mode=max-error mesh=tin max_error_m=%g", o->max_error_m);
    tp_export_options eo = {.format = o->format,
                            .origin_local = o->origin_local,
                            .camera_text = "",
                            .lod_text = lod_text};
    tp_export_result res;
    tp_error err;
    int code = TP_EXIT_OK;
    if (tp_export_tin(sc, o->max_error_m, &eo, o->out, &res, &err) != TP_OK) {
        if (tp_interrupted()) {
            code = tp_cli_interrupted();
        } else {
            tp_cli_error("%s", err.message);
            code = TP_EXIT_FAILURE;
        }
    } else {
        print_written(o->out, &res, tp_full_mesh_triangles(sc));
    }
    tp_scene_free(sc);
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}

/* --full to a .vtp: streamed a piece at a time (full_export.h). TP_EXPORT_PIECE_SAMPLES (a
 * number of samples) makes the pieces smaller: tests cut a small DEM into many. */
static int export_full_streamed(const export_options* o, int is_store)
{
    const char* env = getenv("TP_EXPORT_PIECE_SAMPLES");
    char* end = NULL;
    long long samples = env && *env ? strtoll(env, &end, 10) : 0;
    if (env && *env && (*end != '\0' || samples < 4)) {
        tp_cli_error("TP_EXPORT_PIECE_SAMPLES=%s: expected a number of "
                     "samples >= 4",
                     env);
        return TP_EXIT_USAGE;
    }
    tp_full_export_request r = {.path = o->path,
                                .is_store = is_store,
                                .scene = &o->scene,
                                .out = o->out,
                                .origin_local = o->origin_local,
                                .piece_samples = (size_t)samples};
    int code = tp_export_full_streamed(&r);
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}

int tp_cli_export(int argc, char** argv)
{
    export_options o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    if (o.mode == MODE_TILES) {
        tp_qm_request q = {.path = o.path,
                           .out_dir = o.out,
                           .dem = &o.scene,
                           .max_zoom = o.max_zoom,
                           .has_bounds = o.bounds != NULL,
                           .ellipsoid = !o.heights || !strcmp(o.heights, "ellipsoid"),
                           .max_error_m = o.max_error_m,
                           .threads = o.threads};
        memcpy(q.bounds, o.bounds_deg, sizeof q.bounds);
        code = tp_export_qm(&q);
        return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
    }
    /* An unwritable output is found before the DEM is read, not after the mesh is built. */
    if (!tp_atomic_check_dir(o.out))
        return TP_EXIT_FAILURE;
    int is_store;
    if ((code = tp_terrain_classify("export", o.path, &o.scene, &is_store)) >= 0)
        return code;
    if (is_store) {
        if (o.no_cull || o.per_patch) {
            tp_cli_error("%s is a store: --no-cull and --per-patch apply "
                         "to a DEM only",
                         o.path);
            return TP_EXIT_USAGE;
        }
        if (o.mode == MODE_FULL && tp_full_export_streams(o.path, 1, &o.scene, o.format))
            return export_full_streamed(&o, 1);
        tp_store_export_request r = {
            .view_tins = o.mode == MODE_VIEW && o.mesh == MESH_TIN,
            .store_path = o.path,
            .out = o.out,
            .max_error_m = o.max_error_m,
            .vs = &o.vs,
            .format = o.format,
            .origin_local = o.origin_local,
            .tin = o.mode == MODE_MAX_ERROR && o.mesh != MESH_PATCHES,
            .mode = o.mode == MODE_FULL        ? TP_STORE_EXPORT_FULL
                    : o.mode == MODE_MAX_ERROR ? TP_STORE_EXPORT_MAX_ERROR
                                               : TP_STORE_EXPORT_VIEW,
        };
        code = tp_export_store(&r);
        return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
    }
    if (o.mode == MODE_VIEW && o.mesh == MESH_TIN) {
        tp_cli_error("%s: a camera's mesh of TIN nodes needs a store (terrapatch build %s -o "
                     "MAP.tpt, or the store `view` caches for it)",
                     o.path, o.path);
        return TP_EXIT_USAGE;
    }
    int tin = o.mode == MODE_MAX_ERROR && o.mesh != MESH_PATCHES;
    if (tin && o.per_patch) {
        tp_cli_error("--per-patch needs patches: add --mesh patches (a "
                     "TIN has none)");
        return TP_EXIT_USAGE;
    }
    if (o.mode == MODE_FULL && tp_full_export_streams(o.path, 0, &o.scene, o.format))
        return export_full_streamed(&o, 0);
    tp_scene sc;
    o.scene.use = o.mode == MODE_FULL ? TP_MEMORY_USE_EXPORT_FULL : TP_MEMORY_USE_EXPORT;
    if ((code = tp_scene_load(o.path, &o.scene, &sc)) != TP_EXIT_OK)
        return code;
    if (tin)
        return export_tin(&o, &sc);
    tp_view_setup_warn(&sc, &o.vs, "export");
    tp_selection* sel = NULL;
    tp_error err;
    if (tp_selection_create(sc.terrain, &sel, &err) != TP_OK) {
        tp_cli_error("%s: %s", o.path, err.message);
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }
    tp_export_options eo = {.format = o.format, .origin_local = o.origin_local};
    char camera_text[256] = "", lod_text[160] = "";
    code = TP_EXIT_OK;
    if (o.mode == MODE_FULL) {
        for (int p = 0; p < sc.info.patch_count; p++)
            tp_selection_set_level(sel, p, sc.info.n);
        eo.include_culled = 1;
        eo.full_cells_only = 1;
        snprintf(lod_text, sizeof lod_text, "mode=full");
    } else if (o.mode == MODE_MAX_ERROR) {
        double floor_m = sc.info.quant_max_error_m;
        if (o.max_error_m < floor_m) {
            tp_cli_error("--max-error %g m is below the quantisation error of this "
                         "DEM (%g m, half of its %g m height step at most)",
                         o.max_error_m, floor_m, sc.info.height_step_m);
            code = TP_EXIT_USAGE;
        } else {
            if (tp_select_max_error(&sc, sel, o.max_error_m, &err) != TP_OK) {
                tp_cli_error("%s", err.message);
                code = TP_EXIT_FAILURE;
            }
            eo.include_culled = 1;
            snprintf(lod_text, sizeof lod_text, "mode=max-error max_error_m=%g", o.max_error_m);
        }
    } else {
        tp_camera cam;
        if (!tp_view_setup_camera(&sc, &o.vs, &cam, "export"))
            code = TP_EXIT_FAILURE;
        if (code == TP_EXIT_OK && tp_selection_update(sel, &cam, &o.vs.lod, &err) != TP_OK) {
            tp_cli_error("%s", err.message);
            code = TP_EXIT_USAGE;
        }
        eo.include_culled = o.no_cull;
        tp_camera_text(&sc, &cam, camera_text, sizeof camera_text);
        tp_lod_params lp;
        tp_lod_params_resolve(sc.terrain, &o.vs.lod, &lp, NULL);
        snprintf(lod_text, sizeof lod_text,
                 "mode=%s tau_px=%g mindist_m=%g maxdist_m=%g exp=%g fov_deg=%g size=%dx%d%s",
                 lp.mode == TP_LOD_DISTANCE ? "distance"
                 : lp.mode == TP_LOD_FULL   ? "full"
                                            : "error",
                 lp.tau_px, lp.mindist_m, lp.maxdist_m, lp.exponent, o.vs.fov_deg, o.vs.w, o.vs.h,
                 o.no_cull ? " no_cull" : "");
    }
    eo.camera_text = camera_text;
    eo.lod_text = lod_text;
    tp_export_result res;
    if (code == TP_EXIT_OK) {
        if (tp_export_selection(&sc, sel, &eo, o.out, &res, &err) != TP_OK) {
            if (tp_interrupted()) { /* nothing written, the temporary file removed */
                code = tp_cli_interrupted();
            } else {
                tp_cli_error("%s", err.message);
                code = TP_EXIT_FAILURE;
            }
        } else {
            print_written(o.out, &res, tp_full_mesh_triangles(&sc));
        }
    }
    tp_selection_destroy(sel);
    tp_scene_free(&sc);
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}
