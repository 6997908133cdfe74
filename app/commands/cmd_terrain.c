/*
 * cmd_terrain.c - `terrapatch terrain DEM|STORE -o OUT [--what slope|aspect|hillshade]`: the
 * raster form of what `point` gives at one position (issue 31). The window of the render grid
 * (the whole grid, an --area in render-CRS metres, or a square --around a position:
 * tp_planner_window_choose) is read at its posts through the ground module (the stored samples,
 * as `point`, `viewshed` and `contours` read them), GDAL's gdaldem algorithms
 * (GDALDEMProcessing: tp_gdaldem_write in tp_io.h) compute the slope, aspect or hillshade, and
 * the product is written in the raster format OUT's extension names (output_check.h) on the
 * window's georeference, atomically.
 */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include "memory.h"
#include "output_check.h"
#include "planner_cli.h"
#include "terrapatch.h"

#include "tp_core.h"
#include "tp_io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The most posts one run reads: 64 Mi posts (8192 x 8192) take about 1 GiB: our heights, GDAL's
 * copy, its product and the file encoded in memory, 4 bytes a post each at most. */
#define TERRAIN_MAX_POSTS ((size_t)64 << 20)
#define TERRAIN_BYTES_PER_POST 16

typedef struct terrain_cli {
    tp_planner_source src; /* the DEM or store, --cache-dir and the DEM options */
    const char *out, *around;
    tp_gdaldem_product product;                           /* --what */
    tp_gdaldem_method method;                             /* --method */
    double radius_m, azimuth_deg, altitude_deg, z_factor; /* the last three NaN: not given */
    double area[4];                                       /* E0, N0, E1, N1 */
    int has_area, percent, zero_for_flat, compute_edges;
    tp_gdaldem_options gd; /* from the above */
} terrain_cli;

/* The CODE options of terrain's table. */
enum { OPT_AREA = 1, OPT_WHAT, OPT_METHOD };

static void print_help(void)
{
    tp_planner_help(
        "usage: terrapatch terrain DEM|STORE -o OUT [--what slope|aspect|hillshade]\n"
        "                          [--method horn|zevenbergen] [--compute-edges] [--percent]\n"
        "                          [--zero-for-flat] [--azimuth DEG] [--altitude DEG]\n"
        "                          [--z-factor Z] [--area E0,N0,E1,N1 | --around POS --radius M]\n"
        "                          [--cache-dir DIR]\n"
        "\n"
        "Slope, aspect or hillshade of the ground of DEM (any raster GDAL reads, built into the\n"
        "store cache first as 'terrapatch view' does) or of a store (.tpt): a one-band raster\n"
        "on the render grid (the DEM's own grid, or a geographic DEM warped to the UTM/UPS zone\n"
        "of its centre) computed by GDAL's gdaldem algorithms (GDALDEMProcessing) over the\n"
        "stored samples, as 'gdaldem slope|aspect|hillshade' computes them on a file of that\n"
        "grid: the raster form of what 'terrapatch point' gives at one position. Voids stay\n"
        "nodata, and so does every post whose 3x3 window has a void or leaves the grid, unless\n"
        "--compute-edges.\n"
        "\n"
        "  slope      Float32, degrees from horizontal (or percent), nodata -9999\n"
        "  aspect     Float32, degrees clockwise from grid north (the render CRS's +N axis) that\n"
        "             the slope faces, downhill; nodata -9999, also on flat ground\n"
        "  hillshade  Byte 1..255, the ground lit from --azimuth and --altitude; nodata 0\n"
        "\n"
        "options:\n"
        "  -o, --output OUT       the raster to write (required), in the format its extension\n"
        "                         names: slope and aspect .tif GeoTIFF, .gpkg, .img, .asc; the\n"
        "                         hillshade those and .png, .jp2 (lossless), .bmp\n"
        "  --what PRODUCT         slope (default), aspect or hillshade\n"
        "  --method M             horn (Horn's 3x3 window, gdaldem's default and point's) or\n"
        "                         zevenbergen (Zevenbergen-Thorne: gdaldem -alg\n"
        "                         ZevenbergenThorne)\n"
        "  --compute-edges        values at the grid's edge and beside voids too, the missing\n"
        "                         neighbours filled (gdaldem -compute_edges)\n"
        "  --percent              slope in percent (100 * rise / run) instead of degrees\n"
        "  --zero-for-flat        aspect 0 on flat ground instead of nodata\n"
        "  --azimuth DEG          hillshade: the light's direction, clockwise from grid north,\n"
        "                         0 .. 360 (default 315)\n"
        "  --altitude DEG         hillshade: the light's elevation, 0 .. 90 (default 45)\n"
        "  --z-factor Z           hillshade: heights multiplied by Z (> 0, default 1)\n"
        "  --area E0,N0,E1,N1     only the posts inside this rectangle of the render CRS\n"
        "                         (metres; 'terrapatch info' gives the render CRS)\n"
        "  --around POS           only the posts within --radius M (a square) of POS (any\n"
        "                         form 'terrapatch coord' reads; quote it when it has spaces)\n"
        "  --radius M             half the side of that square, metres (> 0)\n"
        "  -h, --help             show this help\n"
        "\n"
        "By default the whole DEM; a window of more than 67108864 posts (8192 x 8192) is\n"
        "refused (use --area or --around), as is one that does not fit the memory left\n"
        "(16 bytes a post).\n",
        "example:\n"
        "  $ terrapatch terrain N42E001.hgt --what hillshade -o shade.tif\n"
        "\n"
        "Exit status: 0 written; 1 the DEM cannot be read, the area or position is outside\n"
        "it, the window is too big, OUT cannot be written (nothing is left behind, an older\n"
        "OUT stays); 2 usage error (OUT's extension naming no format written for the product\n"
        "included).\n");
}

/* --area E0,N0,E1,N1, --what and --method (tp_option_handler): the options of terrain that
 * are no plain slot. */
static int own_option(void* ctx, int code, const char* value, const char* cmd)
{
    terrain_cli* o = ctx;
    if (code == OPT_AREA) {
        if (!tp_parse_numbers(value, o->area, 4) || !(o->area[0] < o->area[2]) ||
            !(o->area[1] < o->area[3]))
            return tp_option_error(cmd, "--area", "E0,N0,E1,N1 with E0 < E1, N0 < N1", value);
        o->has_area = 1;
    } else if (code == OPT_WHAT) {
        const tp_gdaldem_product all[] = {TP_GDALDEM_SLOPE, TP_GDALDEM_ASPECT,
                                          TP_GDALDEM_HILLSHADE};
        size_t i = 0;
        while (i < 3 && strcmp(value, tp_gdaldem_product_name(all[i])))
            ++i;
        if (i == 3)
            return tp_option_error(cmd, "--what", "slope, aspect or hillshade", value);
        o->product = all[i];
    } else {
        if (strcmp(value, "horn") && strcmp(value, "zevenbergen"))
            return tp_option_error(cmd, "--method", "horn or zevenbergen", value);
        o->method = strcmp(value, "horn") ? TP_GDALDEM_ZEVENBERGEN : TP_GDALDEM_HORN;
    }
    return 1;
}

/* The product's options from what was typed: -1, or 2 after a usage line (an option of another
 * product). */
static int product_options(terrain_cli* o)
{
    o->gd = tp_gdaldem_options_default(o->product);
    o->gd.method = o->method;
    const struct {
        int given;
        const char* name;
        tp_gdaldem_product product;
    } only[] = {
        {o->percent, "--percent", TP_GDALDEM_SLOPE},
        {o->zero_for_flat, "--zero-for-flat", TP_GDALDEM_ASPECT},
        {!isnan(o->azimuth_deg), "--azimuth", TP_GDALDEM_HILLSHADE},
        {!isnan(o->altitude_deg), "--altitude", TP_GDALDEM_HILLSHADE},
        {!isnan(o->z_factor), "--z-factor", TP_GDALDEM_HILLSHADE},
    };
    for (size_t i = 0; i < sizeof only / sizeof only[0]; ++i)
        if (only[i].given && only[i].product != o->gd.product)
            return tp_cli_usage("terrain", "%s is for --what %s, not %s", only[i].name,
                                tp_gdaldem_product_name(only[i].product),
                                tp_gdaldem_product_name(o->product));
    o->gd.compute_edges = o->compute_edges;
    o->gd.slope_percent = o->percent;
    o->gd.zero_for_flat = o->zero_for_flat;
    if (!isnan(o->azimuth_deg))
        o->gd.azimuth_deg = o->azimuth_deg;
    if (!isnan(o->altitude_deg))
        o->gd.altitude_deg = o->altitude_deg;
    if (!isnan(o->z_factor))
        o->gd.z_factor = o->z_factor;
    return -1;
}

static int parse_options(int argc, char** argv, terrain_cli* o)
{
    memset(o, 0, sizeof *o);
    tp_planner_source_init(&o->src);
    o->product = TP_GDALDEM_SLOPE;
    o->method = TP_GDALDEM_HORN;
    o->azimuth_deg = o->altitude_deg = o->z_factor = NAN;
    const tp_option options[] = {
        TP_OPT_TEXT("--output", "-o", &o->out),
        TP_OPT_CODE("--what", NULL, OPT_WHAT, 1),
        TP_OPT_CODE("--method", NULL, OPT_METHOD, 1),
        TP_OPT_FLAG("--compute-edges", &o->compute_edges),
        TP_OPT_FLAG("--percent", &o->percent),
        TP_OPT_FLAG("--zero-for-flat", &o->zero_for_flat),
        TP_OPT_NUMBER("--azimuth", &o->azimuth_deg, 0.0, 360.0, "degrees 0 .. 360"),
        TP_OPT_NUMBER("--altitude", &o->altitude_deg, 0.0, 90.0, "degrees 0 .. 90"),
        TP_OPT_NUMBER_ABOVE("--z-factor", &o->z_factor, 0.0, 1e6, "a number > 0 (up to 1e6)"),
        TP_OPT_NUMBER_ABOVE("--radius", &o->radius_m, 0.0, HUGE_VAL, "a number > 0"),
        TP_OPT_CODE("--area", NULL, OPT_AREA, 1),
        TP_OPT_TEXT("--around", NULL, &o->around),
    };
    const tp_option_table own = {options, TP_OPTIONS_COUNT(options), own_option, o};
    const int code = tp_planner_parse("terrain", argc, argv, print_help, own, &o->src,
                                      " (quote a position with spaces: --around "
                                      "\"45.37 -121.69\")");
    if (code >= 0)
        return code;
    if (!o->out)
        return tp_cli_usage("terrain", "missing -o OUT");
    if (o->has_area && o->around)
        return tp_cli_usage("terrain", "--area and --around exclude each other");
    if (!!o->around != (o->radius_m > 0.0))
        return tp_cli_usage("terrain", "%s",
                            o->around ? "--around needs --radius M"
                                      : "--radius needs --around POS");
    return product_options(o);
}

/* The summary on stdout. */
static void print_summary(const terrain_cli* o, const tp_planner_window* pw, int W, int H,
                          double step_m, const tp_gdaldem_stats* st)
{
    const tp_gdaldem_options* g = &o->gd;
    tp_planner_print_ground(pw, W, H, o->has_area || o->around, step_m);
    const char* unit = g->product == TP_GDALDEM_HILLSHADE                   ? ""
                       : g->product == TP_GDALDEM_SLOPE && g->slope_percent ? " %"
                                                                            : " deg";
    char how[160];
    snprintf(how, sizeof how, "%s%s", g->method == TP_GDALDEM_HORN ? "Horn" : "Zevenbergen-Thorne",
             g->compute_edges ? ", edges computed" : "");
    if (g->product == TP_GDALDEM_HILLSHADE)
        snprintf(how + strlen(how), sizeof how - strlen(how),
                 "; light from azimuth %g deg, altitude %g deg, z factor %g", g->azimuth_deg,
                 g->altitude_deg, g->z_factor);
    if (st->valid)
        printf("%-10s %.*f .. %.*f%s%s (%s)\n", tp_gdaldem_product_name(g->product),
               g->product == TP_GDALDEM_HILLSHADE ? 0 : 2, st->min,
               g->product == TP_GDALDEM_HILLSHADE ? 0 : 2, st->max, unit,
               g->product == TP_GDALDEM_ASPECT ? " from grid north" : "", how);
    else
        printf("%-10s no value: every post nodata (%s)\n", tp_gdaldem_product_name(g->product),
               how);
    printf("posts      %zu with a value, %zu nodata (voids%s%s)\n", st->valid, st->nodata,
           g->compute_edges ? "" : ", the edge, beside voids",
           g->product == TP_GDALDEM_ASPECT && !g->zero_for_flat ? ", flat" : "");
    printf("time       %.1f ms reading the ground, %.1f ms for the %s (GDAL), %.1f ms writing\n",
           1e3 * pw->read_s, 1e3 * st->compute_s, tp_gdaldem_product_name(g->product),
           1e3 * st->write_s);
}

int tp_cli_terrain(int argc, char** argv)
{
    terrain_cli o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    tp_position_readings around;
    if (o.around && !tp_planner_position("terrain", "--around", o.around, &around))
        return TP_EXIT_USAGE;
    char cmd[64];
    snprintf(cmd, sizeof cmd, "terrain --what %s", tp_gdaldem_product_name(o.gd.product));
    if ((code = tp_cli_output_check(cmd, "-o", o.out, tp_gdaldem_output_kind(o.gd.product))) !=
        TP_EXIT_OK)
        return code;
    tp_error err = {{0}};
    tp_ground* g = NULL;
    if ((code = tp_planner_ground_open("terrain", &o.src, &g)) != TP_EXIT_OK)
        return code;
    const tp_store_scene* sc = tp_ground_scene(g);
    const tp_tree_geometry* geom = &sc->info.header.geometry;
    tp_planner_window pw;
    if (!tp_planner_window_choose("terrain", o.src.path, g, o.has_area ? o.area : NULL,
                                  o.around ? &around : NULL, o.around, o.radius_m, &pw) ||
        !tp_planner_window_fits(o.src.path, &pw, TERRAIN_MAX_POSTS, TERRAIN_BYTES_PER_POST)) {
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }
    tp_status s = tp_planner_window_read(g, &pw, "terrain", &err);
    if (pw.n >= TP_GROUND_PROGRESS_POSTS && s == TP_OK)
        tp_cli_note("reading the ground 100%%, computing the %s",
                    tp_gdaldem_product_name(o.gd.product));
    tp_gdaldem_stats st;
    tp_interrupt_hold(); /* a signal during the work is only recorded (tp_interrupt_finished) */
    if (s == TP_OK)
        s = tp_gdaldem_write(o.out, pw.z, pw.n, pw.w, pw.h, pw.gt, sc->info.header.crs_wkt, &o.gd,
                             &st, &err);
    if (s == TP_OK)
        tp_interrupt_finished();
    tp_interrupt_release();
    if (s != TP_OK) {
        if (!tp_interrupted())
            tp_cli_error("%s: %s", o.src.path, err.message);
        tp_planner_window_free(&pw);
        tp_ground_destroy(g);
        return tp_planner_finish(TP_EXIT_FAILURE);
    }
    print_summary(&o, &pw, geom->src_width, geom->src_height, sc->info.header.height_step_m, &st);
    tp_cli_note("wrote %s", o.out);
    tp_planner_window_free(&pw);
    tp_ground_destroy(g);
    return tp_cli_finish(TP_EXIT_OK);
}
