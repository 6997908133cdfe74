/* scene.c - the DEM pipeline shared by the commands (see scene.h). */
#include "scene.h"
#include "clock.h"

#include "cli.h"
#include "progress.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void tp_scene_options_default(tp_scene_options* o)
{
    memset(o, 0, sizeof *o);
    o->patch_size = TP_DEFAULT_PATCH_SIZE;
    o->fit = TP_FIT_PAD;
}

static const tp_option dem_options[] = {
    TP_OPT_CODE("--patch", NULL, TP_OPT_PATCH, 1),
    TP_OPT_CODE("--fit", NULL, TP_OPT_FIT, 1),
    TP_OPT_CODE("--crs", NULL, TP_OPT_CRS, 1),
    TP_OPT_CODE("--resampling", NULL, TP_OPT_RESAMPLING, 1),
    TP_OPT_CODE("--fill-max", NULL, TP_OPT_FILL_MAX, 1),
    TP_OPT_CODE("--fill-from", NULL, TP_OPT_FILL_FROM, 1),
    TP_OPT_CODE("--spacing", NULL, TP_OPT_SPACING, 1),
    TP_OPT_CODE("--zscale", NULL, TP_OPT_ZSCALE, 1),
    TP_OPT_CODE("--origin", NULL, TP_OPT_ORIGIN, 1),
    TP_OPT_CODE("--z-unit", NULL, TP_OPT_Z_UNIT, 1),
};
#define DEM_OPTION_COUNT (sizeof dem_options / sizeof dem_options[0])

static int scene_option(int opt, const char* arg, tp_scene_options* o);

int tp_scene_option(int opt, const char* arg, tp_scene_options* o, const char* cmd)
{
    (void)cmd; /* messages name the command main() dispatched to (tp_cli_error) */
    int r = scene_option(opt, arg, o);
    if (r == 1)
        o->given |= TP_SCENE_GIVEN(opt);
    return r;
}

/* tp_option_handler of the DEM options. */
static int dem_option_handler(void* ctx, int code, const char* value, const char* cmd)
{
    return tp_scene_option(code, value, ctx, cmd) == 1 ? 1 : -1;
}

void tp_scene_options_add(tp_options* p, tp_scene_options* o)
{
    tp_options_add(p, dem_options, DEM_OPTION_COUNT, dem_option_handler, o);
}

void tp_scene_options_names(unsigned mask, char* out, size_t cap)
{
    size_t at = 0;
    out[0] = '\0';
    for (size_t k = 0; k < DEM_OPTION_COUNT && at < cap; ++k)
        if (mask & TP_SCENE_GIVEN(dem_options[k].code)) {
            int n = snprintf(out + at, cap - at, "%s%s", at ? ", " : "", dem_options[k].name);
            at += n > 0 ? (size_t)n : 0;
        }
}

static int scene_option(int opt, const char* arg, tp_scene_options* o)
{
    char* end;
    switch (opt) {
    case TP_OPT_PATCH: {
        long v = strtol(arg, &end, 10);
        if (*arg == '\0' || *end != '\0' ||
            (v != 17 && v != 33 && v != 65 && v != 129 && v != 257)) {
            tp_cli_error("--patch: expected 17, 33, 65, 129 or 257, got %s", arg);
            return -1;
        }
        o->patch_size = (int)v;
        return 1;
    }
    case TP_OPT_FIT:
        if (!strcmp(arg, "pad"))
            o->fit = TP_FIT_PAD;
        else if (!strcmp(arg, "resample"))
            o->fit = TP_FIT_RESAMPLE;
        else {
            tp_cli_error("--fit: expected pad or resample, got %s", arg);
            return -1;
        }
        return 1;
    case TP_OPT_CRS:
        if (!*arg) {
            tp_cli_error("--crs: expected a CRS such as EPSG:4326");
            return -1;
        }
        o->grid.crs = arg;
        return 1;
    case TP_OPT_RESAMPLING:
        if (!strcmp(arg, "bilinear"))
            o->grid.resampling = TP_RESAMPLING_BILINEAR;
        else if (!strcmp(arg, "cubic"))
            o->grid.resampling = TP_RESAMPLING_CUBIC;
        else {
            tp_cli_error("--resampling: expected bilinear or cubic, got %s", arg);
            return -1;
        }
        return 1;
    case TP_OPT_FILL_MAX: {
        long v = strtol(arg, &end, 10);
        if (*arg == '\0' || *end != '\0' || v < 0 || v > 100000) {
            tp_cli_error("--fill-max: expected 0 .. 100000 samples, got %s", arg);
            return -1;
        }
        o->grid.fill_max_px = v == 0 ? -1 : (int)v; /* 0 on the command line: fill nothing */
        return 1;
    }
    case TP_OPT_FILL_FROM:
        if (!*arg) {
            tp_cli_error("--fill-from: expected a raster file");
            return -1;
        }
        o->grid.fill_from = arg;
        return 1;
    case TP_OPT_Z_UNIT:
        if (strcmp(arg, "m") && strcmp(arg, "ft") && strcmp(arg, "us-ft")) {
            tp_cli_error("--z-unit: expected m, ft or us-ft, got %s", arg);
            return -1;
        }
        o->z_unit = arg;
        return 1;
    case TP_OPT_SPACING:
    case TP_OPT_ZSCALE: {
        double v = strtod(arg, &end);
        int spacing = opt == TP_OPT_SPACING;
        double lo = spacing ? TP_IMAGE_SPACING_MIN_M : TP_IMAGE_ZSCALE_MIN;
        double hi = spacing ? TP_IMAGE_SPACING_MAX_M : TP_IMAGE_ZSCALE_MAX;
        if (*arg == '\0' || *end != '\0' || !(v >= lo && v <= hi)) {
            tp_cli_error("--%s: expected a number from %g to %g%s, got %s",
                         spacing ? "spacing" : "zscale", lo, hi,
                         spacing ? " (metres)" : " (metres per count)", arg);
            return -1;
        }
        *(opt == TP_OPT_SPACING ? &o->image.spacing_m : &o->image.zscale) = v;
        o->image_given = 1;
        return 1;
    }
    case TP_OPT_ORIGIN: {
        double lat = strtod(arg, &end), lon = NAN;
        if (end != arg && *end == ',')
            lon = strtod(end + 1, &end);
        if (*end != '\0' || !(fabs(lat) <= 90) || !(fabs(lon) <= 180)) {
            tp_cli_error("--origin: expected LAT,LON in degrees, got %s", arg);
            return -1;
        }
        o->image.has_origin = 1;
        o->image.origin_lat_deg = lat;
        o->image.origin_lon_deg = lon;
        o->image_given = 1;
        return 1;
    }
    }
    return 0;
}

void tp_scene_options_help(FILE* f)
{
    fputs(
        "  --patch N           patch size in samples: 17, 33, 65, 129 or 257 (default 17)\n"
        "  --fit pad|resample  fit the grid to whole patches by padding the right and bottom\n"
        "                      edges (exact, the default) or by bilinear resampling\n"
        "  --crs CRS           the DEM's CRS, overriding the file's (e.g. EPSG:4326 for an\n"
        "                      ASCII grid in degrees without a .prj); DEMs without any CRS\n"
        "                      are taken as EPSG:4326 when plainly in degrees (cells under\n"
        "                      0.1, extent within +-180/+-90), else as metres\n"
        "  --resampling bilinear|cubic\n"
        "                      how geographic DEMs are warped to UTM/UPS (default bilinear)\n"
        "  --fill-max N        fill interior voids up to N x N samples only (default: any\n"
        "                      size; 0 fills nothing); filled samples are tinted\n"
        "  --fill-from FILE    fill voids from this raster (any CRS and resolution), shifted\n"
        "                      to meet the ground around each void; else interpolated\n"
        "  --z-unit m|ft|us-ft the unit of the DEM's heights, overriding the file's (band\n"
        "                      unit, else its vertical CRS); feet are converted to metres\n"
        "  --spacing METRES    heightmap images (PNG, ...; read with OpenImageIO): post\n"
        "                      spacing, 0.001 to 1e6 (default 1)\n"
        "  --zscale S          heightmap images: metres per count, 1e-6 to 1e5 (default 1);\n"
        "                      heights beyond +-1e5 m after scaling are refused\n"
        "  --origin LAT,LON    heightmap images: put the image's centre there (WGS84), in the\n"
        "                      UTM/UPS zone of that point; default: local metres\n"
        "                      (these three are refused for rasters with a CRS or geotransform)\n",
        f);
}

void tp_print_warnings(const char* path, const char* text)
{
    while (text && *text) {
        const char* nl = strchr(text, '\n');
        int len = nl ? (int)(nl - text) : (int)strlen(text);
        tp_cli_warning("%s: %.*s", path, len, text);
        text += len + (nl ? 1 : 0);
    }
}

int tp_scene_load(const char* path, const tp_scene_options* o, tp_scene* scene)
{
    memset(scene, 0, sizeof *scene);
    scene->path = path;
    tp_error err = {{0}};
    tp_status s = o->image_given || tp_is_heightmap_image(path)
                      ? tp_dem_read_image(path, &o->image, &scene->dem, &err)
                      : tp_dem_read_z(path, o->z_unit, &scene->dem, &err);
    if (s != TP_OK) {
        tp_cli_error("%s", err.message); /* io messages name the file */
        /* heightmap options that do not fit the file (e.g. --spacing on a GeoTIFF) */
        return s == TP_ERR_INVALID_ARG ? TP_EXIT_USAGE : TP_EXIT_FAILURE;
    }
    /* dem warnings already name the file */
    for (const char* w = scene->dem->warnings; w && *w;) {
        const char* nl = strchr(w, '\n');
        int len = nl ? (int)(nl - w) : (int)strlen(w);
        tp_cli_warning("%.*s", len, w);
        w += len + (nl ? 1 : 0);
    }
    /* The memory the command will need, from the planned render grid fitted to whole patches
     * (padding rounds each side up to patches of patch_size - 1 cells), before any of it. */
    int plan_w = 0, plan_h = 0;
    s = tp_render_grid_plan(scene->dem, &o->grid, &plan_w, &plan_h, &err);
    if (s == TP_OK) {
        /* in 64 bits: a planned side near INT_MAX would overflow when rounded up */
        int64_t cells = o->patch_size - 1;
        int64_t fit_w = ((int64_t)plan_w - 1 + cells - 1) / cells * cells + 1;
        int64_t fit_h = ((int64_t)plan_h - 1 + cells - 1) / cells * cells + 1;
        if (tp_memory_check(path, o->use, (int)(fit_w < INT_MAX ? fit_w : INT_MAX),
                            (int)(fit_h < INT_MAX ? fit_h : INT_MAX)) < 0) {
            tp_scene_free(scene);
            return TP_EXIT_FAILURE;
        }
        /* a grid that takes seconds says what it is doing, a line a step (issue 29, 4.8) */
        const int steps = (double)plan_w * plan_h >= TP_SCENE_PROGRESS_SAMPLES;
        double t0 = tp_clock_s();
        if (steps)
            tp_cli_note("%s: putting %dx%d samples on the %dx%d render grid ...", path,
                        scene->dem->width, scene->dem->height, plan_w, plan_h);
        s = tp_render_grid_build(scene->dem, &o->grid, &scene->grid, &err);
        if (s == TP_OK && steps) {
            tp_cli_note("%s: render grid done (%.1f s); tiling it into patches "
                        "of %d and their error bounds ...",
                        path, tp_clock_s() - t0, o->patch_size);
            t0 = tp_clock_s();
        }
        if (s == TP_OK) {
            tp_print_warnings(path, scene->grid->warnings);
            tp_terrain_desc desc = tp_render_grid_terrain_desc(scene->grid, o->patch_size, o->fit);
            s = tp_terrain_create(&desc, &scene->terrain, &err);
        }
        if (s == TP_OK && steps)
            tp_cli_note("%s: patches done (%.1f s)", path, tp_clock_s() - t0);
    }
    if (s == TP_OK) {
        /* the fitted grid's geotransform: resampling changes the spacing */
        tp_terrain_get_info(scene->terrain, &scene->info);
        s = tp_georef_create(scene->grid->crs_wkt, scene->info.geotransform, &scene->georef,
                             &err);
    }
    if (s != TP_OK) {
        tp_cli_error("%s: %s", path, err.message[0] ? err.message : tp_status_str(s));
        tp_scene_free(scene);
        return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}

void tp_scene_free(tp_scene* scene)
{
    tp_georef_destroy(scene->georef);
    tp_terrain_destroy(scene->terrain);
    tp_render_grid_destroy(scene->grid);
    tp_dem_destroy(scene->dem);
    memset(scene, 0, sizeof *scene);
}
