/*
 * test_georef.c - the render grid (tp_render_grid_build) and the georeference (tp_georef_*):
 * projected DEMs kept on their own grid, geographic DEMs warped to the UTM/UPS zone of their
 * centre, void classification and filling, DEMs without a CRS, round trips grid <-> projected
 * <-> WGS84, and the awkward places: the antimeridian, the poles, a UTM zone edge, latitude 91.
 *
 * Real DEMs come from TP_SHARED_DATA_DIR (skipped, exit 77, when missing); the synthetic ones
 * are tp_dem structs built here with malloc'd fields, so tp_dem_destroy frees them.
 */
#include "tp_test.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

#define TESTS(X)                                                                                   \
    X(utm_dem_keeps_its_own_grid)                                                                  \
    X(utm_dem_heights_unchanged)                                                                   \
    X(nad83_datum_accuracy_reported)                                                               \
    X(n42e001_warped_to_utm_31n)                                                                   \
    X(mt_rainier_warped_to_utm_10n)                                                                \
    X(craterlake_warped_to_utm_10n)                                                                \
    X(warped_spacing_is_finest_source_spacing)                                                     \
    X(warped_heights_within_source_range)                                                          \
    X(craterlake_untagged_nodata_stays_nodata)                                                     \
    X(n42e001_voids_filled_and_flagged)                                                            \
    X(n42e001_filled_samples_lie_on_source_voids)                                                  \
    X(n42e001_negative_fill_max_fills_nothing)                                                     \
    X(interior_hole_filled_and_flagged)                                                            \
    X(hole_touching_border_is_outside)                                                             \
    X(large_hole_filled_by_default)                                                                \
    X(fill_max_px_bounds_the_void_box)                                                             \
    X(diagonal_voids_are_separate_regions)                                                         \
    X(no_crs_taken_as_metres_with_warning)                                                         \
    X(no_crs_georef_has_no_geo)                                                                    \
    X(no_crs_degrees_taken_as_epsg4326_with_warning)                                               \
    X(no_crs_geographic_guess_is_narrow)                                                           \
    X(crs_option_warps_front_range_to_13n)                                                         \
    X(unknown_crs_fails_naming_it)                                                                 \
    X(georef_create_rejects_null_geotransform)                                                     \
    X(destroy_functions_accept_null)                                                               \
    X(round_trip_n42e001_exact)                                                                    \
    X(round_trip_mt_hood_proj_exact)                                                               \
    X(source_posts_land_where_warp_put_them)                                                       \
    X(mt_rainier_summit_at_its_coordinates)                                                        \
    X(mt_hood_summit_at_its_coordinates)                                                           \
    X(antimeridian_dem_builds_in_one_zone)                                                         \
    X(antimeridian_plane_preserved)                                                                \
    X(ups_north_above_84n)                                                                         \
    X(ups_south_below_80s)                                                                         \
    X(zone_edge_uses_centre_zone)                                                                  \
    X(latitude_91_rejected)                                                                        \
    X(latitude_minus_91_rejected)                                                                  \
    X(extent_touching_pole_builds)                                                                 \
    X(n41_n42_share_boundary_row)                                                                  \
    X(render_max_matches_dem_max)                                                                  \
    X(unwarped_grid_reports_no_warp_error)                                                         \
    X(terrain_desc_points_into_render_grid)                                                        \
    X(projected_feet_dem_is_warped)                                                                \
    X(cubic_resampling_is_used)                                                                    \
    X(georef_rejects_impossible_points)                                                            \
    X(longitude_beyond_180_same_position)                                                          \
    X(georef_conversion_errors_stay_inside_io)                                                     \
    X(terrain_desc_of_null_grid_is_refused)

#ifdef TP_TEST_NO_IO
/* Every test skips; the TEST lines below are not compiled. */
#define TP_GEOREF_STUB_(name)                                                                      \
    static void test_##name(void) { SKIP("built without tp_io"); }
TESTS(TP_GEOREF_STUB_)
#else

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#define DEG (M_PI / 180.0)
#define WGS84_A 6378137.0
#define WGS84_F (1.0 / 298.257223563)
#define ARCSEC3 (3.0 / 3600.0)

/* ---------------------------------------------------------------------------------------------
 * Helpers
 */
static tp_dem* read_or_skip(const char* file)
{
    char path[1024];
    tp_dem* dem = NULL;
    tp_error err;
    tp_status s;
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", file);
    memset(&err, 0, sizeof err);
    s = tp_dem_read(path, &dem, &err);
    if (s != TP_OK || !dem)
        FAIL("tp_dem_read(%s): %s: %s", path, tp_test_status_name_(s), err.message);
    return dem;
}

static char* dup_str(const char* s)
{
    size_t n = strlen(s) + 1;
    char* p = (char*)malloc(n);
    ASSERT_TRUE(p != NULL);
    memcpy(p, s, n);
    return p;
}

/* A DEM built by hand: w x h heights (all 0), geotransform (x0, dx, 0, y0, 0, dy), no CRS. */
static tp_dem* synth_dem(int w, int h, double x0, double dx, double y0, double dy)
{
    tp_dem* d = (tp_dem*)calloc(1, sizeof *d);
    ASSERT_TRUE(d != NULL);
    d->width = w;
    d->height = h;
    d->heights = (float*)calloc((size_t)w * h, sizeof(float));
    ASSERT_TRUE(d->heights != NULL);
    d->geotransform[0] = x0;
    d->geotransform[1] = dx;
    d->geotransform[3] = y0;
    d->geotransform[5] = dy;
    d->has_geotransform = 1;
    d->crs_wkt = dup_str("");
    d->warnings = dup_str("");
    strcpy(d->driver, "MEM");
    strcpy(d->data_type, "Float32");
    return d;
}

/* Recomputes void_count, min_m and max_m of a hand-built DEM. */
static void synth_finish(tp_dem* d)
{
    size_t i, n = (size_t)d->width * d->height;
    d->void_count = 0;
    d->min_m = INFINITY;
    d->max_m = -INFINITY;
    for (i = 0; i < n; ++i) {
        double v = d->heights[i];
        if (isnan(v)) {
            d->void_count++;
            continue;
        }
        if (v < d->min_m)
            d->min_m = v;
        if (v > d->max_m)
            d->max_m = v;
    }
}

/* Plane z = 100 + 0.5 col + 0.25 row: exact in float, a few hundred metres. */
static double plane_xy(int col, int row) { return 100.0 + 0.5 * col + 0.25 * row; }

static tp_dem* synth_plane(int w, int h)
{
    int c, r;
    tp_dem* d = synth_dem(w, h, 1000.0, 10.0, 5000.0, -10.0);
    for (r = 0; r < h; ++r)
        for (c = 0; c < w; ++c)
            d->heights[(size_t)r * w + c] = (float)plane_xy(c, r);
    return d;
}

static void punch(tp_dem* d, int c0, int r0, int cw, int rh)
{
    int c, r;
    for (r = r0; r < r0 + rh; ++r)
        for (c = c0; c < c0 + cw; ++c)
            d->heights[(size_t)r * d->width + c] = NAN;
}

static tp_render_grid* build_ok(const tp_dem* dem, const tp_grid_options* opt)
{
    tp_render_grid* g = NULL;
    tp_error err;
    tp_status s;
    memset(&err, 0, sizeof err);
    s = tp_render_grid_build(dem, opt, &g, &err);
    if (s != TP_OK || !g)
        FAIL("tp_render_grid_build: %s: %s", tp_test_status_name_(s), err.message);
    ASSERT_TRUE(g->heights != NULL);
    ASSERT_TRUE(g->filled != NULL);
    ASSERT_TRUE(g->crs_wkt != NULL);
    ASSERT_TRUE(g->warnings != NULL);
    ASSERT_GE_INT(g->width, 1);
    ASSERT_GE_INT(g->height, 1);
    return g;
}

static tp_render_grid* build_file_or_skip(const char* file, tp_dem** dem_out)
{
    tp_dem* dem = read_or_skip(file);
    tp_render_grid* g = build_ok(dem, NULL);
    if (dem_out)
        *dem_out = dem;
    else
        tp_dem_destroy(dem);
    return g;
}

static tp_georef* georef_ok(const char* wkt, const double gt[6])
{
    tp_georef* g = NULL;
    tp_error err;
    tp_status s;
    memset(&err, 0, sizeof err);
    s = tp_georef_create(wkt, gt, &g, &err);
    if (s != TP_OK || !g)
        FAIL("tp_georef_create: %s: %s", tp_test_status_name_(s), err.message);
    return g;
}

static tp_georef* grid_georef(const tp_render_grid* g) { return georef_ok(g->crs_wkt, g->geotransform); }

/* Render grid sample (x, y) -> WGS84 (lat, lon); fails the test if it cannot. */
static void grid_to_geo(const tp_georef* ref, double x, double y, double* lat, double* lon)
{
    double e, n;
    tp_error err;
    tp_status s;
    tp_georef_grid_to_proj(ref, x, y, &e, &n);
    s = tp_georef_proj_to_geo(ref, e, n, lat, lon, &err);
    if (s != TP_OK)
        FAIL("proj_to_geo(%.3f, %.3f): %s: %s", e, n, tp_test_status_name_(s), err.message);
}

static void geo_to_grid(const tp_georef* ref, double lat, double lon, double* x, double* y)
{
    double e, n;
    tp_error err;
    tp_status s = tp_georef_geo_to_proj(ref, lat, lon, &e, &n, &err);
    if (s != TP_OK)
        FAIL("geo_to_proj(%.9f, %.9f): %s: %s", lat, lon, tp_test_status_name_(s), err.message);
    tp_georef_proj_to_grid(ref, e, n, x, y);
}

/* Source post (col, row) of a DEM <-> its own CRS (degrees for a geographic DEM). */
static void dem_post_xy(const tp_dem* d, double col, double row, double* x, double* y)
{
    *x = d->geotransform[0] + (col + 0.5) * d->geotransform[1];
    *y = d->geotransform[3] + (row + 0.5) * d->geotransform[5];
}
static void dem_xy_post(const tp_dem* d, double x, double y, double* col, double* row)
{
    *col = (x - d->geotransform[0]) / d->geotransform[1] - 0.5;
    *row = (y - d->geotransform[3]) / d->geotransform[5] - 0.5;
}

static float dem_at(const tp_dem* d, int col, int row)
{
    if (col < 0 || row < 0 || col >= d->width || row >= d->height)
        return NAN;
    return d->heights[(size_t)row * d->width + col];
}

/* Among the source posts within `reach` posts of (col, row) (both axes): how many are valid,
 * how many are nodata (posts off the raster count as nodata). */
static void posts_near(const tp_dem* d, double col, double row, double reach, int* valid,
                       int* nodata)
{
    int c, r;
    *valid = *nodata = 0;
    for (r = (int)ceil(row - reach); r <= (int)floor(row + reach); ++r)
        for (c = (int)ceil(col - reach); c <= (int)floor(col + reach); ++c) {
            if (isnan(dem_at(d, c, r)))
                ++*nodata;
            else
                ++*valid;
        }
}

/* The surface the core draws (tp_core.h: each cell split along the diagonal from (c+1, r) to
 * (c, r+1)) at grid position (x, y); NaN outside or next to a sample that is not drawn. */
static double surface_at(const tp_render_grid* g, double x, double y)
{
    int cx, cy;
    double fx, fy, z00, z10, z01, z11;
    if (!(x >= 0 && y >= 0 && x <= g->width - 1 && y <= g->height - 1) || g->width < 2 ||
        g->height < 2)
        return NAN;
    cx = (int)x < g->width - 2 ? (int)x : g->width - 2;
    cy = (int)y < g->height - 2 ? (int)y : g->height - 2;
    fx = x - cx;
    fy = y - cy;
    z00 = g->heights[(size_t)cy * g->width + cx];
    z10 = g->heights[(size_t)cy * g->width + cx + 1];
    z01 = g->heights[(size_t)(cy + 1) * g->width + cx];
    z11 = g->heights[(size_t)(cy + 1) * g->width + cx + 1];
    if (fx + fy <= 1)
        return z00 + fx * (z10 - z00) + fy * (z01 - z00);
    return z11 + (1 - fx) * (z01 - z11) + (1 - fy) * (z10 - z11);
}

typedef struct grid_counts {
    size_t nan, filled_flags, filled_nonfinite, flagged_nan;
} grid_counts;

static grid_counts count_grid(const tp_render_grid* g)
{
    grid_counts k;
    size_t i, n = (size_t)g->width * g->height;
    memset(&k, 0, sizeof k);
    for (i = 0; i < n; ++i) {
        if (isnan(g->heights[i]))
            k.nan++;
        if (g->filled[i]) {
            k.filled_flags++;
            if (!isfinite(g->heights[i]))
                k.filled_nonfinite++;
        }
    }
    return k;
}

/* The NaN samples are exactly the outside and large-void ones; every flag marks a finite,
 * counted sample. */
static void check_void_accounting(const tp_render_grid* g)
{
    grid_counts k = count_grid(g);
    EXPECT_EQ_INT(g->outside_samples + g->large_void_samples, k.nan);
    EXPECT_EQ_INT(g->filled_samples, k.filled_flags);
    EXPECT_EQ_INT(0, k.filled_nonfinite);
}

/* East-west distance (m) on the WGS84 ellipsoid of dlon degrees at latitude lat. */
static double ellipsoid_ew_m(double lat_deg, double dlon_deg)
{
    double e2 = WGS84_F * (2 - WGS84_F), s = sin(lat_deg * DEG);
    return DEG * WGS84_A * cos(lat_deg * DEG) / sqrt(1 - e2 * s * s) * dlon_deg;
}

/* Ground distance (m) between two nearby WGS84 points (equirectangular, fine below ~10 km). */
static double near_distance_m(double lat1, double lon1, double lat2, double lon2)
{
    double e2 = WGS84_F * (2 - WGS84_F), phi = 0.5 * (lat1 + lat2) * DEG, s = sin(phi);
    double w = sqrt(1 - e2 * s * s);
    double m = WGS84_A * (1 - e2) / (w * w * w), nu = WGS84_A / w;
    double dn = (lat2 - lat1) * DEG * m, de = remainder(lon2 - lon1, 360.0) * DEG * nu * cos(phi);
    return sqrt(dn * dn + de * de);
}

/* ---------------------------------------------------------------------------------------------
 * Projected metric DEMs: their own grid
 */

/* NAD83 / UTM 10N in metres: no warp, the DEM's own grid and CRS. */
TEST(utm_dem_keeps_its_own_grid)
{
    tp_dem* dem;
    tp_render_grid* g = build_file_or_skip("lf_elev_220_mt_hood_utm.tif", &dem);
    int i;
    EXPECT_EQ_INT(dem->width, g->width);
    EXPECT_EQ_INT(dem->height, g->height);
    for (i = 0; i < 6; ++i)
        EXPECT_EQ_DBL(dem->geotransform[i], g->geotransform[i]);
    EXPECT_EQ_INT(0, g->warped);
    EXPECT_EQ_INT(10, g->utm_zone);
    EXPECT_EQ_INT(1, g->northp);
    EXPECT_EQ_INT(26910, g->epsg);
    EXPECT_EQ_INT(0, g->wgs84); /* NAD83 is not WGS84 */
    EXPECT_TRUE(g->crs_wkt[0] != '\0');
    EXPECT_CONTAINS(g->crs_name, "UTM zone 10N");
    EXPECT_NEAR(30.0, g->spacing_m, 0.01);
    check_void_accounting(g);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* Not warped: every valid DEM sample is carried over bit for bit (no datum shift, no units
 * change); NaN samples are NaN or filled. */
TEST(utm_dem_heights_unchanged)
{
    tp_dem* dem;
    tp_render_grid* g = build_file_or_skip("lf_elev_220_mt_hood_utm.tif", &dem);
    size_t i, n, changed = 0, invented = 0;
    ASSERT_EQ_INT(dem->width, g->width);
    ASSERT_EQ_INT(dem->height, g->height);
    n = (size_t)g->width * g->height;
    for (i = 0; i < n; ++i) {
        if (!isnan(dem->heights[i])) {
            changed += !(g->heights[i] == dem->heights[i]) || g->filled[i];
        } else {
            invented += !isnan(g->heights[i]) && !g->filled[i];
        }
    }
    EXPECT_EQ_INT(0, changed);
    EXPECT_EQ_INT(0, invented);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* NAD83 -> WGS84 goes through PROJ: its accuracy is stated (> 0) or unknown (-1), never the 0
 * of an exact step, and the note says which operation it is. */
TEST(nad83_datum_accuracy_reported)
{
    tp_render_grid* g = build_file_or_skip("lf_elev_220_mt_hood_utm.tif", NULL);
    tp_georef* ref = grid_georef(g);
    double acc = tp_georef_datum_accuracy_m(ref);
    const char* note = tp_georef_datum_note(ref);
    EXPECT_EQ_INT(1, tp_georef_has_geo(ref));
    EXPECT_TRUE(acc > 0 || acc == -1);
    ASSERT_TRUE(note != NULL);
    EXPECT_TRUE(note[0] != '\0');
    tp_test_note("accuracy %g m, \"%s\"", acc, note);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
}

/* ---------------------------------------------------------------------------------------------
 * Geographic DEMs: warped to the UTM zone of their centre
 */
static void check_warped(const char* file, int zone, int epsg)
{
    tp_dem* dem;
    tp_render_grid* g = build_file_or_skip(file, &dem);
    tp_georef* ref;
    EXPECT_EQ_INT(1, g->warped);
    EXPECT_EQ_INT(zone, g->utm_zone);
    EXPECT_EQ_INT(1, g->northp);
    EXPECT_EQ_INT(epsg, g->epsg);
    EXPECT_EQ_INT(1, g->wgs84);
    /* square, north-up posts */
    EXPECT_EQ_DBL(fabs(g->geotransform[1]), fabs(g->geotransform[5]));
    EXPECT_GT(g->geotransform[1], 0);
    EXPECT_LT(g->geotransform[5], 0);
    EXPECT_EQ_DBL(0, g->geotransform[2]);
    EXPECT_EQ_DBL(0, g->geotransform[4]);
    EXPECT_EQ_DBL(fabs(g->geotransform[1]), g->spacing_m);
    /* the warp error: measured, finite, sane */
    EXPECT_TRUE(isfinite(g->warp_max_error_m));
    EXPECT_TRUE(isfinite(g->warp_rms_error_m));
    EXPECT_GE(g->warp_rms_error_m, 0);
    EXPECT_LT(g->warp_rms_error_m, 10.0);
    EXPECT_GE(g->warp_max_error_m, g->warp_rms_error_m);
    EXPECT_GT(g->warp_posts, 0);
    EXPECT_LE_INT(g->warp_posts, (size_t)dem->width * dem->height - dem->void_count);
    /* nearly every valid post is measured (only those on the very rim may be missed) */
    EXPECT_GE((double)g->warp_posts, 0.95 * (double)((size_t)dem->width * dem->height - dem->void_count));
    check_void_accounting(g);
    /* the render CRS is WGS84 UTM: the exact path */
    ref = grid_georef(g);
    EXPECT_EQ_DBL(0, tp_georef_datum_accuracy_m(ref));
    tp_test_note("%dx%d -> %dx%d, %.3f m posts, warp max %.2f m rms %.3f m over %zu posts; "
                 "filled %zu, large %zu, outside %zu",
                 dem->width, dem->height, g->width, g->height, g->spacing_m, g->warp_max_error_m,
                 g->warp_rms_error_m, g->warp_posts, g->filled_samples, g->large_void_samples,
                 g->outside_samples);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* Centre 42.5N 1.5E -> WGS 84 / UTM zone 31N. */
TEST(n42e001_warped_to_utm_31n) { check_warped("N42E001.hgt", 31, 32631); }
/* Centre 46.5N 121.5W -> zone 10N. */
TEST(mt_rainier_warped_to_utm_10n) { check_warped("mt_rainier_90m.tif", 10, 32610); }
/* Centre about 42.94N 122.11W -> zone 10N. */
TEST(craterlake_warped_to_utm_10n) { check_warped("craterlake-elev-16bit-30m.tif", 10, 32610); }

/* The posts are as fine as the finest source spacing: for SRTM3 at 42-43N that is one column
 * (3") on the poleward edge, 67.95 m on the ellipsoid; in UTM metres it is the projected
 * length of that step (scale factor < 1 near the central meridian). */
TEST(warped_spacing_is_finest_source_spacing)
{
    tp_dem* dem;
    tp_render_grid* g = build_file_or_skip("N42E001.hgt", &dem);
    tp_georef* ref = grid_georef(g);
    double ground = ellipsoid_ew_m(43.0, ARCSEC3), finest = INFINITY;
    /* the column and row steps at the corners and the centre, measured in the render CRS */
    const double at[5][2] = {{0, 0}, {1199, 0}, {0, 1199}, {1199, 1199}, {600, 600}};
    int i;
    for (i = 0; i < 5; ++i) {
        double lon0, lat0, lon1, lat1, lon2, lat2, x0, y0, x1, y1, x2, y2, dc, dr;
        dem_post_xy(dem, at[i][0], at[i][1], &lon0, &lat0);
        dem_post_xy(dem, at[i][0] + 1, at[i][1], &lon1, &lat1);
        dem_post_xy(dem, at[i][0], at[i][1] + 1, &lon2, &lat2);
        geo_to_grid(ref, lat0, lon0, &x0, &y0);
        geo_to_grid(ref, lat1, lon1, &x1, &y1);
        geo_to_grid(ref, lat2, lon2, &x2, &y2);
        dc = hypot(x1 - x0, y1 - y0) * g->spacing_m;
        dr = hypot(x2 - x0, y2 - y0) * g->spacing_m;
        finest = fmin(finest, fmin(dc, dr));
    }
    tp_test_note("spacing %.4f m; finest projected step %.4f m; ellipsoid step at 43N %.4f m",
                 g->spacing_m, finest, ground);
    EXPECT_NEAR(67.95, ground, 0.01); /* the formula itself */
    EXPECT_LE(g->spacing_m, ground);  /* never undersampled */
    EXPECT_LE(g->spacing_m, finest * (1 + 1e-9));
    EXPECT_NEAR(finest, g->spacing_m, 1e-3); /* and not needlessly finer */
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* Bilinear resampling and inverse-distance filling are averages: every drawn height lies in the
 * source's range, so no nodata value (-32768, -32767) leaks into the grid. */
TEST(warped_heights_within_source_range)
{
    static const char* const files[] = {"N42E001.hgt", "mt_rainier_90m.tif",
                                        "craterlake-elev-16bit-30m.tif"};
    size_t f;
    for (f = 0; f < sizeof files / sizeof files[0]; ++f) {
        tp_dem* dem;
        tp_render_grid* g = build_file_or_skip(files[f], &dem);
        size_t i, n = (size_t)g->width * g->height, below = 0, above = 0, drawn = 0;
        for (i = 0; i < n; ++i) {
            float z = g->heights[i];
            if (isnan(z))
                continue;
            drawn++;
            below += z < dem->min_m - 1e-3;
            above += z > dem->max_m + 1e-3;
        }
        if (below || above)
            ADD_FAILURE("%s: %zu samples below %g, %zu above %g", files[f], below, dem->min_m,
                        above, dem->max_m);
        EXPECT_GT(drawn, 0);
        tp_render_grid_destroy(g);
        tp_dem_destroy(dem);
    }
}

/* Crater Lake has -32767 outside its footprint and no nodata tag: it is read as nodata, and after
 * the warp no sample is drawn where the source has no data, and none is missing where it has.
 * (The neighbourhood is 1.25 posts wide on each side to allow for GDAL's approximate
 * transformer, 0.125 px by default.) */
TEST(craterlake_untagged_nodata_stays_nodata)
{
    tp_dem* dem;
    tp_render_grid* g = build_file_or_skip("craterlake-elev-16bit-30m.tif", &dem);
    tp_georef* ref = grid_georef(g);
    int x, y;
    size_t drawn_on_nodata = 0, missing_on_data = 0, drawn = 0, nan_in_footprint = 0;
    ASSERT_GT(dem->void_count, 39000); /* tp_dem_read took the untagged -32767 as nodata */
    for (y = 0; y < g->height; ++y)
        for (x = 0; x < g->width; ++x) {
            size_t i = (size_t)y * g->width + x;
            double lat, lon, col, row;
            int valid, nodata;
            grid_to_geo(ref, x, y, &lat, &lon);
            dem_xy_post(dem, lon, lat, &col, &row);
            posts_near(dem, col, row, 1.25, &valid, &nodata);
            if (!isnan(g->heights[i])) {
                drawn++;
                if (!g->filled[i] && valid == 0)
                    drawn_on_nodata++;
            } else {
                /* NaN although the posts around it (and their neighbours) are all valid */
                missing_on_data += nodata == 0;
                if (valid > 0)
                    nan_in_footprint++;
            }
        }
    EXPECT_GT(drawn, 0);
    EXPECT_EQ_INT(0, drawn_on_nodata);
    EXPECT_EQ_INT(0, missing_on_data);
    tp_test_note("%zu drawn, %zu NaN samples next to some valid post (the footprint's rim)", drawn,
                 nan_in_footprint);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* ---------------------------------------------------------------------------------------------
 * Voids
 */

/* N42E001 has 7652 void posts: the interior ones are filled and flagged, the warp's wedges at
 * the border are outside and stay NaN. */
TEST(n42e001_voids_filled_and_flagged)
{
    tp_render_grid* g = build_file_or_skip("N42E001.hgt", NULL);
    tp_georef* ref = grid_georef(g);
    int x, y;
    size_t outside_footprint = 0;
    EXPECT_GT(g->filled_samples, 0);
    EXPECT_GT(g->outside_samples, 0);
    check_void_accounting(g);
    /* filled samples lie within the tile (42..43N, 1..2E) */
    for (y = 0; y < g->height; ++y)
        for (x = 0; x < g->width; ++x) {
            double lat, lon;
            if (!g->filled[(size_t)y * g->width + x])
                continue;
            grid_to_geo(ref, x, y, &lat, &lon);
            outside_footprint += !(lat >= 42 && lat <= 43 && lon >= 1 && lon <= 2);
        }
    EXPECT_EQ_INT(0, outside_footprint);
    /* the border rows and columns are never filled (a void touching them is outside) */
    for (x = 0; x < g->width; ++x) {
        EXPECT_EQ_INT(0, g->filled[x]);
        EXPECT_EQ_INT(0, g->filled[(size_t)(g->height - 1) * g->width + x]);
        ASSERT_NO_FAILURE();
    }
    tp_test_note("filled %zu, large %zu, outside %zu", g->filled_samples, g->large_void_samples,
                 g->outside_samples);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
}

/* What is filled is where the source has voids, never over measured data. */
TEST(n42e001_filled_samples_lie_on_source_voids)
{
    tp_dem* dem;
    tp_render_grid* g = build_file_or_skip("N42E001.hgt", &dem);
    tp_georef* ref = grid_georef(g);
    int x, y;
    size_t filled = 0, on_data = 0;
    for (y = 0; y < g->height; ++y)
        for (x = 0; x < g->width; ++x) {
            double lat, lon, col, row;
            int valid, nodata;
            if (!g->filled[(size_t)y * g->width + x])
                continue;
            filled++;
            grid_to_geo(ref, x, y, &lat, &lon);
            dem_xy_post(dem, lon, lat, &col, &row);
            posts_near(dem, col, row, 1.25, &valid, &nodata);
            on_data += nodata == 0;
        }
    EXPECT_GT(filled, 0);
    EXPECT_EQ_INT(0, on_data);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* fill_max_px < 0: nothing is filled; the interior voids stay NaN (counted as large voids) and
 * the outside is classified as before. */
TEST(n42e001_negative_fill_max_fills_nothing)
{
    tp_dem* dem = read_or_skip("N42E001.hgt");
    tp_grid_options opt;
    tp_render_grid *g0, *g1;
    grid_counts k;
    memset(&opt, 0, sizeof opt);
    g0 = build_ok(dem, &opt);
    opt.fill_max_px = -1;
    g1 = build_ok(dem, &opt);
    k = count_grid(g1);
    EXPECT_EQ_INT(0, g1->filled_samples);
    EXPECT_EQ_INT(0, k.filled_flags);
    EXPECT_EQ_INT(g0->outside_samples, g1->outside_samples);
    EXPECT_EQ_INT(g0->filled_samples + g0->large_void_samples, g1->large_void_samples);
    check_void_accounting(g1);
    tp_render_grid_destroy(g0);
    tp_render_grid_destroy(g1);
    tp_dem_destroy(dem);
}

/* A 3x3 hole inside a plane: filled, flagged, between the heights around it; nothing else
 * changes. */
TEST(interior_hole_filled_and_flagged)
{
    tp_dem* dem = synth_plane(32, 24);
    tp_render_grid* g;
    int c, r;
    punch(dem, 10, 8, 3, 3);
    synth_finish(dem);
    g = build_ok(dem, NULL);
    ASSERT_EQ_INT(32, g->width);
    ASSERT_EQ_INT(24, g->height);
    EXPECT_EQ_INT(9, g->filled_samples);
    EXPECT_EQ_INT(0, g->outside_samples);
    EXPECT_EQ_INT(0, g->large_void_samples);
    check_void_accounting(g);
    for (r = 0; r < 24; ++r)
        for (c = 0; c < 32; ++c) {
            size_t i = (size_t)r * 32 + c;
            int in_hole = c >= 10 && c < 13 && r >= 8 && r < 11;
            EXPECT_EQ_INT(in_hole, g->filled[i]);
            if (in_hole) {
                /* inverse-distance weights of posts a few samples away */
                EXPECT_GE(g->heights[i], plane_xy(10 - 4, 8 - 4));
                EXPECT_LE(g->heights[i], plane_xy(12 + 4, 10 + 4));
            } else {
                EXPECT_EQ_DBL(plane_xy(c, r), g->heights[i]);
            }
            ASSERT_NO_FAILURE();
        }
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* A hole that touches the grid's border is outside the data: not filled, NaN, counted. */
TEST(hole_touching_border_is_outside)
{
    tp_dem* dem = synth_plane(32, 24);
    tp_render_grid* g;
    int c, r;
    punch(dem, 10, 0, 3, 3);  /* touches the top row */
    punch(dem, 29, 15, 3, 2); /* touches the right column */
    synth_finish(dem);
    g = build_ok(dem, NULL);
    EXPECT_EQ_INT(0, g->filled_samples);
    EXPECT_EQ_INT(15, g->outside_samples);
    EXPECT_EQ_INT(0, g->large_void_samples);
    check_void_accounting(g);
    for (r = 0; r < 3; ++r)
        for (c = 10; c < 13; ++c)
            EXPECT_NAN(g->heights[(size_t)r * 32 + c]);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* A 100x100 hole in a 300x300 grid: filled by default (it was left as a large void before, when
 * the default was --fill-max 64); with fill_max_px 64 it is a large void, not fabricated. */
TEST(large_hole_filled_by_default)
{
    tp_dem* dem = synth_plane(300, 300);
    tp_render_grid* g;
    grid_counts k;
    punch(dem, 100, 100, 100, 100);
    synth_finish(dem);
    g = build_ok(dem, NULL);
    k = count_grid(g);
    EXPECT_EQ_INT(10000, g->filled_samples);
    EXPECT_EQ_INT(0, g->large_void_samples);
    EXPECT_EQ_INT(0, k.nan);
    EXPECT_EQ_INT(1, g->filled[(size_t)150 * 300 + 150]);
    tp_render_grid_destroy(g);
    tp_grid_options opt = {.fill_max_px = 64};
    g = build_ok(dem, &opt);
    k = count_grid(g);
    EXPECT_EQ_INT(0, g->filled_samples);
    EXPECT_EQ_INT(10000, g->large_void_samples);
    EXPECT_EQ_INT(0, g->outside_samples);
    EXPECT_EQ_INT(10000, k.nan);
    EXPECT_NAN(g->heights[(size_t)150 * 300 + 150]);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* By default every interior void is filled, 65 wide too (it was left before: --fill-max 64);
 * "bounding box at most fill_max_px samples wide and high": with 64, 64 wide is filled and 65 is
 * not; with fill_max_px = 3 a 3x3 hole is filled and a 4x1 one is not. */
TEST(fill_max_px_bounds_the_void_box)
{
    tp_dem* dem = synth_plane(100, 40);
    tp_grid_options opt;
    tp_render_grid* g;
    punch(dem, 10, 10, 64, 1); /* 64 x 1: filled with the default */
    punch(dem, 10, 20, 65, 1); /* 65 x 1: large */
    punch(dem, 10, 30, 3, 3);  /* 3 x 3 */
    punch(dem, 20, 30, 4, 1);  /* 4 x 1 */
    synth_finish(dem);
    memset(&opt, 0, sizeof opt);
    g = build_ok(dem, &opt);
    EXPECT_EQ_INT(64 + 65 + 9 + 4, g->filled_samples);
    EXPECT_EQ_INT(0, g->large_void_samples);
    EXPECT_EQ_INT(1, g->filled[(size_t)20 * 100 + 74]);
    check_void_accounting(g);
    tp_render_grid_destroy(g);
    opt.fill_max_px = 64;
    g = build_ok(dem, &opt);
    EXPECT_EQ_INT(64 + 9 + 4, g->filled_samples);
    EXPECT_EQ_INT(65, g->large_void_samples);
    EXPECT_EQ_INT(1, g->filled[(size_t)10 * 100 + 73]);
    EXPECT_NAN(g->heights[(size_t)20 * 100 + 74]);
    check_void_accounting(g);
    tp_render_grid_destroy(g);
    opt.fill_max_px = 3;
    g = build_ok(dem, &opt);
    EXPECT_EQ_INT(9, g->filled_samples);
    EXPECT_EQ_INT(64 + 65 + 4, g->large_void_samples);
    EXPECT_EQ_INT(1, g->filled[(size_t)31 * 100 + 11]);
    EXPECT_EQ_INT(0, g->filled[(size_t)30 * 100 + 20]);
    check_void_accounting(g);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* Regions are 4-connected: a diagonal chain of single voids is many 1x1 voids (filled with
 * fill_max_px = 2), not one 10x10 region; its link on the border is outside on its own. */
TEST(diagonal_voids_are_separate_regions)
{
    tp_dem* dem = synth_plane(40, 40);
    tp_grid_options opt;
    tp_render_grid* g;
    int i;
    for (i = 0; i < 10; ++i)
        punch(dem, i, i, 1, 1); /* (0,0) is on the border */
    synth_finish(dem);
    memset(&opt, 0, sizeof opt);
    opt.fill_max_px = 2;
    g = build_ok(dem, &opt);
    EXPECT_EQ_INT(9, g->filled_samples);
    EXPECT_EQ_INT(1, g->outside_samples);
    EXPECT_EQ_INT(0, g->large_void_samples);
    EXPECT_NAN(g->heights[0]);
    for (i = 1; i < 10; ++i)
        EXPECT_EQ_INT(1, g->filled[(size_t)i * 40 + i]);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* ---------------------------------------------------------------------------------------------
 * No CRS
 */

/* A DEM without a CRS whose extent is not plainly geographic (UTM-sized numbers, 30 m posts):
 * used as is, as metres, with a warning. */
TEST(no_crs_taken_as_metres_with_warning)
{
    tp_dem* dem = synth_dem(65, 65, 500000, 30, 5000000, -30);
    tp_render_grid* g;
    int i;
    synth_finish(dem);
    g = build_ok(dem, NULL);
    EXPECT_CONTAINS(g->warnings, "no CRS: coordinates taken as metres");
    EXPECT_EQ_INT(-1, g->utm_zone);
    EXPECT_EQ_INT(0, g->warped);
    EXPECT_EQ_INT(0, g->epsg);
    EXPECT_TRUE(g->crs_wkt[0] == '\0');
    EXPECT_CONTAINS(g->crs_name, "local metres");
    EXPECT_EQ_INT(dem->width, g->width);
    EXPECT_EQ_INT(dem->height, g->height);
    for (i = 0; i < 6; ++i)
        EXPECT_EQ_DBL(dem->geotransform[i], g->geotransform[i]);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* Without a CRS there is no latitude/longitude: INVALID_ARG and the outputs left alone. */
TEST(no_crs_georef_has_no_geo)
{
    tp_dem* dem = synth_dem(65, 65, 500000, 30, 5000000, -30);
    tp_render_grid* g;
    tp_georef* ref;
    double lat = 12345, lon = 678, e = -1, n = -2, x, y;
    tp_error err;
    synth_finish(dem);
    g = build_ok(dem, NULL);
    ref = grid_georef(g);
    memset(&err, 0, sizeof err);
    EXPECT_EQ_INT(0, tp_georef_has_geo(ref));
    tp_georef_grid_to_proj(ref, 3, 4, &e, &n);
    EXPECT_EQ_DBL(g->geotransform[0] + 3.5 * g->geotransform[1], e);
    EXPECT_EQ_DBL(g->geotransform[3] + 4.5 * g->geotransform[5], n);
    tp_georef_proj_to_grid(ref, e, n, &x, &y);
    EXPECT_NEAR(3, x, 1e-9);
    EXPECT_NEAR(4, y, 1e-9);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_proj_to_geo(ref, e, n, &lat, &lon, &err));
    EXPECT_TRUE(err.message[0] != '\0');
    EXPECT_EQ_DBL(12345, lat);
    EXPECT_EQ_DBL(678, lon);
    e = -1;
    n = -2;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_geo_to_proj(ref, 40, -105, &e, &n, NULL));
    EXPECT_EQ_DBL(-1, e);
    EXPECT_EQ_DBL(-2, n);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* front_range_srtmgl3_144.asc has no .prj, but its 0.000833 cells and its extent (105.5W,
 * 40.1N) are plainly degrees: taken as EPSG:4326 with a warning that says how to override,
 * giving exactly the grid of --crs EPSG:4326 (before: 0.000833 m posts, an empty picture). */
TEST(no_crs_degrees_taken_as_epsg4326_with_warning)
{
    tp_dem* dem;
    tp_render_grid* g = build_file_or_skip("front_range_srtmgl3_144.asc", &dem);
    tp_grid_options opt;
    tp_render_grid* given;
    size_t i, n, differ = 0;
    ASSERT_TRUE(dem->crs_wkt[0] == '\0'); /* no .prj beside it */
    memset(&opt, 0, sizeof opt);
    opt.crs = "EPSG:4326";
    given = build_ok(dem, &opt);
    EXPECT_CONTAINS(g->warnings, "taken as EPSG:4326");
    EXPECT_CONTAINS(g->warnings, "--crs");
    EXPECT_TRUE(strstr(g->warnings, "taken as metres") == NULL);
    EXPECT_EQ_INT(1, g->warped);
    EXPECT_EQ_INT(13, g->utm_zone);
    EXPECT_EQ_INT(1, g->northp);
    EXPECT_EQ_INT(32613, g->epsg);
    EXPECT_GT(g->spacing_m, 60.0); /* 3" east-west at 40.2N is about 71 m */
    EXPECT_LT(g->spacing_m, 72.0);
    ASSERT_EQ_INT(given->width, g->width);
    ASSERT_EQ_INT(given->height, g->height);
    n = (size_t)g->width * g->height;
    for (i = 0; i < n; ++i)
        differ += memcmp(&g->heights[i], &given->heights[i], sizeof(float)) != 0;
    EXPECT_EQ_INT(0, differ);
    tp_render_grid_destroy(given);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* The guess is narrow: cells under 0.1 and every edge within +-180 / +-90, else metres. */
TEST(no_crs_geographic_guess_is_narrow)
{
    static const struct {
        double x0, dx, y0, dy;
        int geographic;
    } cases[] = {
        {-105.5, 0.01, 40.5, -0.01, 1},
        {179.3, 0.01, 10.0, -0.01, 1},   /* right up to the antimeridian */
        {-105.5, 0.1, 40.5, -0.1, 0},    /* 0.1 cells: could be metres */
        {-105.5, 0.01, 40.5, -0.2, 0},
        {179.6, 0.01, 40.5, -0.01, 0},   /* reaches 180.24 */
        {-105.5, 0.01, -89.8, -0.01, 0}, /* reaches 90.44 S */
        {-105.5, 0.01, 90.5, -0.01, 0},
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        tp_dem* dem = synth_dem(65, 65, cases[i].x0, cases[i].dx, cases[i].y0, cases[i].dy);
        tp_render_grid* g;
        synth_finish(dem);
        g = build_ok(dem, NULL);
        if ((g->utm_zone >= 0) != cases[i].geographic ||
            (strstr(g->warnings, "taken as EPSG:4326") != NULL) != cases[i].geographic)
            ADD_FAILURE("case %d: utm_zone %d, warnings '%s'", (int)i, g->utm_zone, g->warnings);
        tp_render_grid_destroy(g);
        tp_dem_destroy(dem);
    }
}

/* --crs EPSG:4326 on the same file: geographic, centre 40.15N 105.5W -> zone 13N. */
TEST(crs_option_warps_front_range_to_13n)
{
    tp_dem* dem = read_or_skip("front_range_srtmgl3_144.asc");
    tp_grid_options opt;
    tp_render_grid* g;
    memset(&opt, 0, sizeof opt);
    opt.crs = "EPSG:4326";
    g = build_ok(dem, &opt);
    EXPECT_EQ_INT(1, g->warped);
    EXPECT_EQ_INT(13, g->utm_zone);
    EXPECT_EQ_INT(1, g->northp);
    EXPECT_EQ_INT(32613, g->epsg);
    EXPECT_TRUE(strstr(g->warnings, "no CRS") == NULL);
    EXPECT_LT(g->spacing_m, 72.0); /* 3" east-west at 40.2N is about 71 m */
    EXPECT_GT(g->spacing_m, 60.0);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* An unknown CRS string: INVALID_ARG, the message names it, *out untouched. */
TEST(unknown_crs_fails_naming_it)
{
    static const char* const bad[] = {"EPSG:999999", "nonsense"};
    tp_dem* dem = synth_plane(8, 8);
    size_t i;
    synth_finish(dem);
    for (i = 0; i < 2; ++i) {
        tp_grid_options opt;
        tp_render_grid* sentinel = (tp_render_grid*)&opt;
        tp_render_grid* g = sentinel;
        tp_error err;
        memset(&opt, 0, sizeof opt);
        memset(&err, 0, sizeof err);
        opt.crs = bad[i];
        EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_render_grid_build(dem, &opt, &g, &err));
        EXPECT_TRUE(g == sentinel);
        EXPECT_CONTAINS(err.message, bad[i]);
    }
    tp_dem_destroy(dem);
}

TEST(georef_create_rejects_null_geotransform)
{
    tp_georef* sentinel = (tp_georef*)&sentinel;
    tp_georef* ref = sentinel;
    tp_error err;
    memset(&err, 0, sizeof err);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_create("", NULL, &ref, &err));
    EXPECT_TRUE(ref == sentinel);
    EXPECT_TRUE(err.message[0] != '\0');
}

TEST(destroy_functions_accept_null)
{
    tp_render_grid_destroy(NULL);
    tp_georef_destroy(NULL);
    tp_dem_destroy(NULL);
}

/* ---------------------------------------------------------------------------------------------
 * Round trips
 */
static void check_round_trips(const char* file, double tol_cells)
{
    tp_render_grid* g = build_file_or_skip(file, NULL);
    tp_georef* ref = grid_georef(g);
    tp_rng rng = tp_rng_seed(0x6e6f7274ull);
    double worst = 0;
    int i;
    for (i = 0; i < 2000; ++i) {
        double x = tp_rng_range(&rng, 0, g->width - 1), y = tp_rng_range(&rng, 0, g->height - 1);
        double lat, lon, x2, y2;
        grid_to_geo(ref, x, y, &lat, &lon);
        geo_to_grid(ref, lat, lon, &x2, &y2);
        worst = fmax(worst, fmax(fabs(x2 - x), fabs(y2 - y)));
    }
    tp_test_note("worst round trip %.3g cells (%s)", worst, tp_georef_datum_note(ref));
    EXPECT_LE(worst, tol_cells);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
}

/* grid -> UTM -> WGS84 -> UTM -> grid through GeographicLib. */
TEST(round_trip_n42e001_exact) { check_round_trips("N42E001.hgt", 1e-9); }
/* The same through PROJ (NAD83 / UTM 10N -> WGS84 and back). */
TEST(round_trip_mt_hood_proj_exact) { check_round_trips("lf_elev_220_mt_hood_utm.tif", 1e-9); }

/* The geographic position of a source post, put through tp_georef_geo_to_proj, lands on the
 * render grid where the warp put that post's height: the drawn surface there agrees with the
 * post within the reported warp error, and far better than half a post off. */
TEST(source_posts_land_where_warp_put_them)
{
    tp_dem* dem;
    tp_render_grid* g = build_file_or_skip("N42E001.hgt", &dem);
    tp_georef* ref = grid_georef(g);
    double mx = 0, sum = 0, sum_shift = 0;
    size_t count = 0;
    int c, r;
    /* pixel-is-point: post (0, 0) is exactly 43N 1E */
    {
        double lon, lat;
        dem_post_xy(dem, 0, 0, &lon, &lat);
        EXPECT_NEAR(1.0, lon, 1e-9);
        EXPECT_NEAR(43.0, lat, 1e-9);
    }
    for (r = 0; r < dem->height; r += 5)
        for (c = 0; c < dem->width; c += 5) {
            double lon, lat, x, y, z, zs, s = dem_at(dem, c, r);
            if (isnan(s))
                continue;
            dem_post_xy(dem, c, r, &lon, &lat);
            geo_to_grid(ref, lat, lon, &x, &y);
            z = surface_at(g, x, y);
            zs = surface_at(g, x + 0.5, y + 0.5);
            if (isnan(z) || isnan(zs))
                continue;
            mx = fmax(mx, fabs(z - s));
            sum += (z - s) * (z - s);
            sum_shift += (zs - s) * (zs - s);
            count++;
        }
    ASSERT_GT(count, 50000);
    tp_test_note("%zu posts: max %.3f m, rms %.3f m (reported %.3f, %.3f); half a sample off: "
                 "rms %.3f m",
                 count, mx, sqrt(sum / count), g->warp_max_error_m, g->warp_rms_error_m,
                 sqrt(sum_shift / count));
    EXPECT_LE(mx, g->warp_max_error_m + 1e-3);
    EXPECT_NEAR(g->warp_rms_error_m, sqrt(sum / count), 0.1 * g->warp_rms_error_m + 0.01);
    EXPECT_LT(sqrt(sum / count), 0.5 * sqrt(sum_shift / count));
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* The highest render sample, through the georeference, is at the summit's published position. */
static void check_summit(const char* file, double lat0, double lon0, double tol_m)
{
    tp_render_grid* g = build_file_or_skip(file, NULL);
    tp_georef* ref = grid_georef(g);
    size_t i, n = (size_t)g->width * g->height, best = 0;
    double lat, lon, d;
    float top = -INFINITY;
    for (i = 0; i < n; ++i)
        if (g->heights[i] > top) {
            top = g->heights[i];
            best = i;
        }
    grid_to_geo(ref, (double)(best % g->width), (double)(best / g->width), &lat, &lon);
    d = near_distance_m(lat, lon, lat0, lon0);
    tp_test_note("highest sample %.1f m at %.6f, %.6f: %.0f m from the summit", top, lat, lon, d);
    EXPECT_LT(d, tol_m);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
}

/* Mount Rainier, 46.8529N 121.7604W (USGS GNIS); 90 m posts. */
TEST(mt_rainier_summit_at_its_coordinates)
{
    check_summit("mt_rainier_90m.tif", 46.8529, -121.7604, 250);
}
/* Mount Hood, 45.3736N 121.6959W (USGS GNIS); 30 m posts, NAD83 through PROJ. */
TEST(mt_hood_summit_at_its_coordinates)
{
    check_summit("lf_elev_220_mt_hood_utm.tif", 45.3736, -121.6959, 150);
}

/* ---------------------------------------------------------------------------------------------
 * Antimeridian, poles, zone edges, latitude 91
 */

/* 100 x 100 posts of 0.01 degree, 179.5..180.5E x 65..66N (Chukotka), heights a plane in
 * (lon, lat): 1000 + 100 (lon - 179.5) + 50 (lat - 65). */
static double am_plane(double lat, double lon360) { return 1000 + 100 * (lon360 - 179.5) + 50 * (lat - 65); }

static tp_dem* antimeridian_dem(void)
{
    tp_dem* dem = synth_dem(100, 100, 179.5, 0.01, 66.0, -0.01);
    int c, r;
    for (r = 0; r < 100; ++r)
        for (c = 0; c < 100; ++c) {
            double lon, lat;
            dem_post_xy(dem, c, r, &lon, &lat);
            dem->heights[(size_t)r * 100 + c] = (float)am_plane(lat, lon);
        }
    synth_finish(dem);
    return dem;
}

static tp_render_grid* build_with_crs(const tp_dem* dem, const char* crs)
{
    tp_grid_options opt;
    memset(&opt, 0, sizeof opt);
    opt.crs = crs;
    return build_ok(dem, &opt);
}

/* The centre is exactly 180E: one zone for the scene. GeographicLib's standard zone of
 * longitude 180 is zone 1 (longitudes are normalised to [-180, 180)); the test accepts 60 too
 * and notes which. Every drawn sample lies in 179.5..180.5E (mod 360), 65..66N. */
TEST(antimeridian_dem_builds_in_one_zone)
{
    tp_dem* dem = antimeridian_dem();
    tp_render_grid* g = build_with_crs(dem, "EPSG:4326");
    tp_georef* ref = grid_georef(g);
    int x, y;
    size_t drawn = 0, off = 0;
    double lon_lo = 400, lon_hi = -400, tol = 0.01 / 8;
    EXPECT_EQ_INT(1, g->warped);
    EXPECT_TRUE(g->utm_zone == 1 || g->utm_zone == 60);
    EXPECT_EQ_INT(1, g->northp);
    EXPECT_EQ_INT(32600 + g->utm_zone, g->epsg);
    tp_test_note("zone %d, %dx%d samples of %.2f m", g->utm_zone, g->width, g->height, g->spacing_m);
    for (y = 0; y < g->height; ++y)
        for (x = 0; x < g->width; ++x) {
            double lat, lon;
            if (isnan(g->heights[(size_t)y * g->width + x]))
                continue;
            drawn++;
            grid_to_geo(ref, x, y, &lat, &lon);
            EXPECT_TRUE(lon >= -180 && lon <= 180);
            lon = fmod(lon + 360.0, 360.0);
            lon_lo = fmin(lon_lo, lon);
            lon_hi = fmax(lon_hi, lon);
            /* the raster's extent, give or take GDAL's approximate transformer (1/8 post) */
            off += !(lon >= 179.5 - tol && lon <= 180.5 + tol && lat >= 65 - tol &&
                     lat <= 66 + tol);
        }
    tp_test_note("drawn longitudes %.6f .. %.6f", lon_lo, lon_hi);
    EXPECT_GT(drawn, 0.5 * g->width * g->height);
    EXPECT_EQ_INT(0, off);
    /* the scene really crosses the antimeridian */
    EXPECT_LT(lon_lo, 179.6);
    EXPECT_GT(lon_hi, 180.4);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* A plane in (lon, lat) stays that plane after the warp across 180 (bilinear interpolation of a
 * linear function is exact up to the warp's coordinate approximation), within the reported warp
 * error, wherever a sample lies between source posts. (In the half-post rim between the
 * outermost posts and the raster's edge GDAL holds the edge values: only noted.) */
TEST(antimeridian_plane_preserved)
{
    tp_dem* dem = antimeridian_dem();
    tp_render_grid* g = build_with_crs(dem, "EPSG:4326");
    tp_georef* ref = grid_georef(g);
    int x, y;
    double worst = 0, worst_rim = 0;
    size_t inside = 0;
    for (y = 0; y < g->height; ++y)
        for (x = 0; x < g->width; ++x) {
            double lat, lon, col, row, err, z = g->heights[(size_t)y * g->width + x];
            if (isnan(z))
                continue;
            grid_to_geo(ref, x, y, &lat, &lon);
            lon = fmod(lon + 360.0, 360.0);
            dem_xy_post(dem, lon, lat, &col, &row);
            err = fabs(z - am_plane(lat, lon));
            if (col >= 0 && row >= 0 && col <= dem->width - 1 && row <= dem->height - 1) {
                worst = fmax(worst, err);
                inside++;
            } else {
                worst_rim = fmax(worst_rim, err);
            }
        }
    tp_test_note("%zu samples between the posts: worst %.4f m; in the half-post rim: worst %.4f m; "
                 "warp max %.4f m rms %.4f m",
                 inside, worst, worst_rim, g->warp_max_error_m, g->warp_rms_error_m);
    EXPECT_GT(inside, 0.5 * g->width * g->height);
    EXPECT_LT(g->warp_max_error_m, 0.25);
    EXPECT_LE(worst, g->warp_max_error_m + 1e-3);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* grid -> proj -> geo -> proj -> grid on random points; geo -> proj -> geo too. */
static void check_geo_round_trips(const tp_render_grid* g, const tp_georef* ref)
{
    tp_rng rng = tp_rng_seed(0x706f6c65ull);
    double worst = 0;
    int i;
    for (i = 0; i < 1000; ++i) {
        double x = tp_rng_range(&rng, 0, g->width - 1), y = tp_rng_range(&rng, 0, g->height - 1);
        double lat, lon, x2, y2;
        grid_to_geo(ref, x, y, &lat, &lon);
        geo_to_grid(ref, lat, lon, &x2, &y2);
        worst = fmax(worst, fmax(fabs(x2 - x), fabs(y2 - y)));
    }
    EXPECT_LE(worst, 1e-9);
}

static void check_ups(double lat_top, int northp, int epsg)
{
    /* 2 degrees of longitude (0.1-degree columns) by 1 degree of latitude (0.01-degree rows) */
    tp_dem* dem = synth_dem(20, 100, 10.0, 0.1, lat_top, -0.01);
    tp_render_grid* g;
    tp_georef* ref;
    double lat, lon;
    int c, r;
    for (r = 0; r < 100; ++r)
        for (c = 0; c < 20; ++c)
            dem->heights[(size_t)r * 20 + c] = (float)(500 + 3 * c + r);
    synth_finish(dem);
    g = build_with_crs(dem, "EPSG:4326");
    EXPECT_EQ_INT(1, g->warped);
    EXPECT_EQ_INT(0, g->utm_zone);
    EXPECT_EQ_INT(northp, g->northp);
    EXPECT_EQ_INT(epsg, g->epsg);
    EXPECT_EQ_INT(1, g->wgs84);
    ref = grid_georef(g);
    EXPECT_EQ_DBL(0, tp_georef_datum_accuracy_m(ref));
    check_geo_round_trips(g, ref);
    /* the grid's centre is near the DEM's centre */
    grid_to_geo(ref, (g->width - 1) / 2.0, (g->height - 1) / 2.0, &lat, &lon);
    EXPECT_NEAR(lat_top - 0.5, lat, 0.1);
    EXPECT_NEAR(11.0, lon, 0.5);
    tp_test_note("%s: %dx%d samples of %.1f m, centre %.4f %.4f", g->crs_name, g->width, g->height,
                 g->spacing_m, lat, lon);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* 85..86N -> UPS north (EPSG:32661). */
TEST(ups_north_above_84n) { check_ups(86.0, 1, 32661); }
/* 81..80S -> UPS south (EPSG:32761). */
TEST(ups_south_below_80s) { check_ups(-80.0, 0, 32761); }

/* 5.0..6.5E at 44.5..45.5N: the centre (5.75E) is in zone 31, so the whole scene is zone 31,
 * including the part east of 6E (standard zone 32); round trips stay exact there. */
TEST(zone_edge_uses_centre_zone)
{
    tp_dem* dem = synth_dem(150, 100, 5.0, 0.01, 45.5, -0.01);
    tp_render_grid* g;
    tp_georef* ref;
    tp_rng rng = tp_rng_seed(0x7a6f6e65ull);
    double worst = 0, e, n, x, y;
    int c, r, i, east = 0;
    for (r = 0; r < 100; ++r)
        for (c = 0; c < 150; ++c)
            dem->heights[(size_t)r * 150 + c] = (float)(200 + c + 2 * r);
    synth_finish(dem);
    g = build_with_crs(dem, "EPSG:4326");
    EXPECT_EQ_INT(31, g->utm_zone);
    EXPECT_EQ_INT(32631, g->epsg);
    ref = grid_georef(g);
    /* a point in zone 32 gets zone-31 coordinates: about 760 km east, not 290 km */
    ASSERT_OK(tp_georef_geo_to_proj(ref, 45.0, 6.3, &e, &n, NULL));
    EXPECT_GT(e, 700000);
    tp_georef_proj_to_grid(ref, e, n, &x, &y);
    EXPECT_TRUE(x > 0 && x < g->width - 1 && y > 0 && y < g->height - 1);
    /* round trips of points east of 6E */
    for (i = 0; i < 4000 && east < 500; ++i) {
        double gx = tp_rng_range(&rng, 0, g->width - 1), gy = tp_rng_range(&rng, 0, g->height - 1);
        double lat, lon, x2, y2;
        grid_to_geo(ref, gx, gy, &lat, &lon);
        if (lon <= 6.0)
            continue;
        east++;
        geo_to_grid(ref, lat, lon, &x2, &y2);
        worst = fmax(worst, fmax(fabs(x2 - gx), fabs(y2 - gy)));
    }
    EXPECT_GE_INT(east, 500);
    EXPECT_LE(worst, 1e-9);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

static void check_latitude_rejected(double lat_top)
{
    tp_dem* dem = synth_dem(50, 100, 10.0, 0.01, lat_top, -0.01);
    tp_grid_options opt;
    tp_render_grid* sentinel = (tp_render_grid*)&opt;
    tp_render_grid* g = sentinel;
    tp_error err;
    synth_finish(dem);
    memset(&opt, 0, sizeof opt);
    memset(&err, 0, sizeof err);
    opt.crs = "EPSG:4326";
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_render_grid_build(dem, &opt, &g, &err));
    EXPECT_TRUE(g == sentinel);
    EXPECT_TRUE(err.message[0] != '\0');
    tp_test_note("%s", err.message);
    tp_dem_destroy(dem);
}

/* Rows 90..91N. */
TEST(latitude_91_rejected) { check_latitude_rejected(91.0); }
/* Rows -90..-91 (the top edge at -90). */
TEST(latitude_minus_91_rejected) { check_latitude_rejected(-90.0); }

/* 89..90N: the extent touches the pole but is not beyond it; UPS north. */
TEST(extent_touching_pole_builds)
{
    tp_dem* dem = synth_dem(36, 100, 0.0, 10.0, 90.0, -0.01);
    tp_render_grid* g;
    int c, r;
    for (r = 0; r < 100; ++r)
        for (c = 0; c < 36; ++c)
            dem->heights[(size_t)r * 36 + c] = (float)(100 + r);
    synth_finish(dem);
    g = build_with_crs(dem, "EPSG:4326");
    EXPECT_EQ_INT(0, g->utm_zone);
    EXPECT_EQ_INT(32661, g->epsg);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* ---------------------------------------------------------------------------------------------
 * Real-data facts
 */

/* The tiles share the 42N row: N42E001's last row is N41E001's first, value for value. */
TEST(n41_n42_share_boundary_row)
{
    tp_dem* north = read_or_skip("N42E001.hgt");
    tp_dem* south = read_or_skip("N41E001.hgt");
    double lon_n, lat_n, lon_s, lat_s;
    int c, compared = 0, differ = 0;
    ASSERT_EQ_INT(north->width, south->width);
    dem_post_xy(north, 0, north->height - 1, &lon_n, &lat_n);
    dem_post_xy(south, 0, 0, &lon_s, &lat_s);
    EXPECT_NEAR(42.0, lat_n, 1e-9);
    EXPECT_NEAR(lat_n, lat_s, 1e-9);
    EXPECT_NEAR(lon_n, lon_s, 1e-9);
    for (c = 0; c < north->width; ++c) {
        float a = dem_at(north, c, north->height - 1), b = dem_at(south, c, 0);
        if (isnan(a) || isnan(b))
            continue;
        compared++;
        differ += a != b;
    }
    EXPECT_GT(compared, 1100);
    EXPECT_EQ_INT(0, differ);
    tp_dem_destroy(north);
    tp_dem_destroy(south);
}

/* Heights stay metres as in the DEM (no datum shift): the render maximum is at most the DEM's and
 * no lower than the DEM's minus the warp error (the surface at the highest post is within it). */
TEST(render_max_matches_dem_max)
{
    tp_dem* dem;
    tp_render_grid* g = build_file_or_skip("N42E001.hgt", &dem);
    size_t i, n = (size_t)g->width * g->height;
    double hi = -INFINITY, lo = INFINITY;
    for (i = 0; i < n; ++i) {
        if (isnan(g->heights[i]))
            continue;
        hi = fmax(hi, g->heights[i]);
        lo = fmin(lo, g->heights[i]);
    }
    tp_test_note("render %.2f .. %.2f m, DEM %.0f .. %.0f m, warp max error %.2f m", lo, hi,
                 dem->min_m, dem->max_m, g->warp_max_error_m);
    EXPECT_LE(hi, dem->max_m + 1e-3);
    EXPECT_GE(hi, dem->max_m - g->warp_max_error_m - 1e-3);
    EXPECT_GE(lo, dem->min_m - 1e-3);
    EXPECT_LE(lo, dem->min_m + g->warp_max_error_m + 1e-3);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* A grid used as is reports no warp: errors 0, no posts measured. */
TEST(unwarped_grid_reports_no_warp_error)
{
    tp_dem* dem = synth_plane(16, 16);
    tp_render_grid* g;
    synth_finish(dem);
    g = build_ok(dem, NULL);
    EXPECT_EQ_INT(0, g->warped);
    EXPECT_EQ_DBL(0, g->warp_max_error_m);
    EXPECT_EQ_DBL(0, g->warp_rms_error_m);
    EXPECT_EQ_INT(0, g->warp_posts);
    EXPECT_EQ_DBL(10.0, g->spacing_m);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* tp_render_grid_terrain_desc points into the grid, flags included, and the core accepts it. */
TEST(terrain_desc_points_into_render_grid)
{
    tp_dem* dem = synth_plane(40, 30);
    tp_render_grid* g;
    tp_terrain_desc d;
    tp_terrain* t = NULL;
    tp_terrain_info info;
    tp_error err;
    int i;
    punch(dem, 10, 10, 2, 2);
    synth_finish(dem);
    g = build_ok(dem, NULL);
    d = tp_render_grid_terrain_desc(g, 17, TP_FIT_PAD);
    EXPECT_TRUE(d.heights == g->heights);
    EXPECT_TRUE(d.filled == g->filled);
    EXPECT_EQ_INT((size_t)40 * 30, d.height_count);
    EXPECT_EQ_INT((size_t)40 * 30, d.filled_count);
    EXPECT_EQ_INT(40, d.width);
    EXPECT_EQ_INT(30, d.height);
    EXPECT_EQ_INT(17, d.patch_size);
    EXPECT_EQ_INT(TP_FIT_PAD, d.fit);
    for (i = 0; i < 6; ++i)
        EXPECT_EQ_DBL(g->geotransform[i], d.geotransform[i]);
    memset(&err, 0, sizeof err);
    EXPECT_OK(tp_terrain_create(&d, &t, &err));
    if (t) {
        tp_terrain_get_info(t, &info);
        EXPECT_EQ_INT(4, info.filled_samples);
    }
    tp_terrain_destroy(t);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* A projected DEM in feet (NAD83 / Oregon GIC Lambert (ft), EPSG:2992) is not used as is: it is
 * warped to the UTM zone of its centre (near Mount Hood: 10N), heights untouched (a constant
 * stays that constant). */
TEST(projected_feet_dem_is_warped)
{
    tp_dem* dem = synth_dem(50, 40, 1000000.0, 100.0, 1320000.0, -100.0);
    tp_render_grid* g;
    size_t i, n, drawn = 0, changed = 0;
    for (i = 0; i < (size_t)50 * 40; ++i)
        dem->heights[i] = 1234.5f;
    synth_finish(dem);
    g = build_with_crs(dem, "EPSG:2992");
    EXPECT_EQ_INT(1, g->warped);
    EXPECT_EQ_INT(10, g->utm_zone);
    EXPECT_EQ_INT(32610, g->epsg);
    /* 100 ft = 30.48 m posts, in metres now */
    EXPECT_NEAR(30.48, g->spacing_m, 0.1);
    n = (size_t)g->width * g->height;
    for (i = 0; i < n; ++i) {
        if (isnan(g->heights[i]))
            continue;
        drawn++;
        changed += fabs(g->heights[i] - 1234.5) > 1e-3;
    }
    EXPECT_GT(drawn, n / 2);
    EXPECT_EQ_INT(0, changed);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* TP_RESAMPLING_CUBIC is honoured: on a curved surface it gives other heights than bilinear on
 * the same grid. */
TEST(cubic_resampling_is_used)
{
    tp_dem* dem = synth_dem(60, 60, 7.0, 0.002, 46.0, -0.002);
    tp_grid_options opt;
    tp_render_grid *bil, *cub;
    size_t i, n, differ = 0;
    int c, r;
    for (r = 0; r < 60; ++r)
        for (c = 0; c < 60; ++c)
            dem->heights[(size_t)r * 60 + c] = (float)(1000 + 0.5 * (c - 30) * (c - 30) + 0.3 * (r - 30) * (r - 30));
    synth_finish(dem);
    memset(&opt, 0, sizeof opt);
    opt.crs = "EPSG:4326";
    opt.resampling = TP_RESAMPLING_BILINEAR;
    bil = build_ok(dem, &opt);
    opt.resampling = TP_RESAMPLING_CUBIC;
    cub = build_ok(dem, &opt);
    ASSERT_EQ_INT(bil->width, cub->width);
    ASSERT_EQ_INT(bil->height, cub->height);
    EXPECT_EQ_INT(1, cub->warped);
    n = (size_t)bil->width * bil->height;
    for (i = 0; i < n; ++i)
        differ += !isnan(bil->heights[i]) && !isnan(cub->heights[i]) &&
                  fabs(bil->heights[i] - cub->heights[i]) > 1e-3;
    EXPECT_GT(differ, n / 10);
    tp_test_note("warp rms: bilinear %.4f m, cubic %.4f m", bil->warp_rms_error_m,
                 cub->warp_rms_error_m);
    tp_render_grid_destroy(bil);
    tp_render_grid_destroy(cub);
    tp_dem_destroy(dem);
}

/* Points that have no position: INVALID_ARG, outputs untouched; on the GeographicLib path (a
 * warped synthetic DEM) and on the PROJ path (Mt Hood, NAD83). */
static void check_impossible_points(const tp_georef* ref)
{
    double lat = 1, lon = 2, e = 3, n = 4;
    tp_error err;
    memset(&err, 0, sizeof err);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_proj_to_geo(ref, 1e12, -1e12, &lat, &lon, &err));
    EXPECT_TRUE(err.message[0] != '\0');
    EXPECT_EQ_DBL(1, lat);
    EXPECT_EQ_DBL(2, lon);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_geo_to_proj(ref, 91, 0, &e, &n, NULL));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_geo_to_proj(ref, NAN, 0, &e, &n, NULL));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_geo_to_proj(ref, 45, NAN, &e, &n, NULL));
    EXPECT_EQ_DBL(3, e);
    EXPECT_EQ_DBL(4, n);
}

TEST(georef_rejects_impossible_points)
{
    tp_dem* dem = synth_dem(20, 20, 5.0, 0.01, 45.5, -0.01);
    tp_render_grid* g;
    tp_georef* ref;
    synth_finish(dem);
    g = build_with_crs(dem, "EPSG:4326");
    ref = grid_georef(g);
    check_impossible_points(ref);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
    g = build_file_or_skip("lf_elev_220_mt_hood_utm.tif", NULL);
    ref = grid_georef(g);
    check_impossible_points(ref);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
}

/* GeographicLib throws (GeographicErr) for a UTM easting beyond its range: the throw stays
 * inside io, as TP_ERR_INVALID_ARG with GeographicLib's reason; non-finite input and NULL
 * pointers are refused before any conversion. Outputs are never written. */
TEST(georef_conversion_errors_stay_inside_io)
{
    tp_dem* dem = synth_dem(20, 20, 5.0, 0.01, 45.5, -0.01);
    tp_render_grid* g;
    tp_georef* ref;
    double lat = 1, lon = 2, e = 3, n = 4;
    tp_error err;
    synth_finish(dem);
    g = build_with_crs(dem, "EPSG:4326"); /* warped to WGS84 UTM 31N: GeographicLib's UTMUPS */
    ref = grid_georef(g);
    memset(&err, 0, sizeof err);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_proj_to_geo(ref, 1e12, 5e6, &lat, &lon, &err));
    EXPECT_CONTAINS(err.message, "Easting");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_proj_to_geo(ref, NAN, 5e6, &lat, &lon, &err));
    EXPECT_CONTAINS(err.message, "not a position");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_proj_to_geo(ref, 5e5, INFINITY, &lat, &lon, NULL));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_proj_to_geo(NULL, 5e5, 5e6, &lat, &lon, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_proj_to_geo(ref, 5e5, 5e6, NULL, &lon, &err));
    EXPECT_EQ_DBL(1, lat);
    EXPECT_EQ_DBL(2, lon);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_georef_geo_to_proj(ref, 45, 5, &e, NULL, &err));
    EXPECT_CONTAINS(err.message, "tp_georef_geo_to_proj");
    EXPECT_EQ_DBL(3, e);
    EXPECT_EQ_DBL(4, n);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

/* tp_render_grid_terrain_desc(NULL) is a desc without heights, which the core refuses. */
TEST(terrain_desc_of_null_grid_is_refused)
{
    tp_terrain_desc d = tp_render_grid_terrain_desc(NULL, 17, TP_FIT_PAD);
    tp_terrain* t = NULL;
    EXPECT_TRUE(d.heights == NULL);
    EXPECT_EQ_INT(17, d.patch_size);
    EXPECT_TRUE(tp_terrain_create(&d, &t, NULL) != TP_OK);
    EXPECT_TRUE(t == NULL);
}

/* 180.3E and 179.7W are the same place: the same (E, N) in the antimeridian scene's zone. */
TEST(longitude_beyond_180_same_position)
{
    tp_dem* dem = antimeridian_dem();
    tp_render_grid* g = build_with_crs(dem, "EPSG:4326");
    tp_georef* ref = grid_georef(g);
    double e1, n1, e2, n2;
    EXPECT_OK(tp_georef_geo_to_proj(ref, 65.5, 180.3, &e1, &n1, NULL));
    EXPECT_OK(tp_georef_geo_to_proj(ref, 65.5, -179.7, &e2, &n2, NULL));
    EXPECT_NEAR(e2, e1, 1e-6);
    EXPECT_NEAR(n2, n1, 1e-6);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

#endif /* TP_TEST_NO_IO */

TP_TEST_MAIN(TESTS)
