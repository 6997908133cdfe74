/*
 * render_grid.cpp - tp_render_grid_build: a DEM as read becomes the metric grid that is tiled
 * and drawn. See tp_io.h for the rules; the choices are explained in docs/georeference.md.
 *
 * GDAL does the warping (GDALWarp, the library form of gdalwarp) and the void filling
 * (GDALFillNodata); PROJ (through OGRCoordinateTransformation) maps posts between CRSs to
 * measure the warp error; GeographicLib picks the UTM/UPS zone.
 */
#include "crs.hpp"
#include "gdal_util.hpp"
#include "render_grid.hpp"
#include "void_fill.hpp"
#include "tp_io.h"

#include <GeographicLib/UTMUPS.hpp>
#include <gdal_alg.h>
#include <gdal_utils.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <exception>
#include <vector>

namespace {

using tpio::fail;

struct Grid {
    int w = 0, h = 0;
    std::vector<float> z;
};

/* Target CRS for a warp: the WGS84 UTM zone (or UPS) of (lat, lon). */
int utm_epsg(double lat, double lon, int* zone, int* northp)
{
    *zone = GeographicLib::UTMUPS::StandardZone(lat, lon);
    *northp = lat >= 0;
    return tpio::utmups_epsg(*zone, *northp);
}

/* Finest post spacing (metres, target CRS) of the source grid: a one-column and a one-row step
 * measured at the corners and the centre of the extent. */
double finest_spacing(OGRCoordinateTransformation* ct, const double gt[6], int w, int h)
{
    double best = INFINITY;
    const double at[5][2] = {{0, 0}, {w - 1.0, 0}, {0, h - 1.0}, {w - 1.0, h - 1.0},
                             {(w - 1) / 2.0, (h - 1) / 2.0}};
    for (const auto& p : at) {
        double cx = std::min(p[0], std::max(0.0, w - 2.0)), cy = std::min(p[1], std::max(0.0, h - 2.0));
        double x[3], y[3];
        const double pts[3][2] = {{cx, cy}, {cx + 1, cy}, {cx, cy + 1}};
        for (int i = 0; i < 3; i++) {
            x[i] = gt[0] + (pts[i][0] + 0.5) * gt[1];
            y[i] = gt[3] + (pts[i][1] + 0.5) * gt[5];
        }
        int ok[3] = {0, 0, 0};
        if (!ct->Transform(3, x, y, nullptr, ok) || !ok[0] || !ok[1] || !ok[2])
            continue;
        double dcol = std::hypot(x[1] - x[0], y[1] - y[0]), drow = std::hypot(x[2] - x[0], y[2] - y[0]);
        best = std::min(best, std::min(dcol, drow));
    }
    return best;
}

} // namespace

namespace {

struct GridDeleter {
    void operator()(tp_render_grid* g) const { tp_render_grid_destroy(g); }
};

/* A north-up grid without a CRS whose cells are under 0.1 and whose every edge lies within
 * +-180 / +-90 is in degrees: in metres or feet it would be a few centimetres wide. */
bool plainly_geographic(const tp_dem* dem)
{
    const double* t = dem->geotransform;
    double x0 = t[0], x1 = t[0] + dem->width * t[1], y0 = t[3], y1 = t[3] + dem->height * t[5];
    return t[2] == 0 && t[4] == 0 && std::fabs(t[1]) < 0.1 && std::fabs(t[5]) < 0.1 &&
           std::fabs(x0) <= 180 && std::fabs(x1) <= 180 && std::fabs(y0) <= 90 &&
           std::fabs(y1) <= 90;
}

void add_warning(std::string& w, const std::string& line)
{
    if (!w.empty())
        w += "\n";
    w += line;
}

/* Largest scale error (|k - 1|, spherical approximation) of the zone chosen for a geographic DEM
 * over its posts (the edges, and inside where TM's scale peaks), and where: TM scale k0 / sqrt(1 - (cos(lat) sin(dlon))^2) with dlon from
 * the central meridian, UPS k0 * 2 / (1 + sin|lat|). UTM itself keeps within 0.1%. */
double zone_scale_error(const tp_dem* dem, int zone, double* at_lat, double* at_lon)
{
    const double* t = dem->geotransform;
    const double d2r = M_PI / 180.0, k0 = zone == 0 ? 0.994 : 0.9996;
    const double cm = zone == 0 ? 0.0 : -183.0 + 6.0 * zone;
    double worst = 0;
    auto visit_at = [&](double lon, double lat) {
        double k = zone == 0 ? k0 * 2.0 / (1.0 + std::sin(std::fabs(lat) * d2r))
                             : k0 / std::sqrt(std::max(1e-12, 1.0 - std::pow(std::cos(lat * d2r) *
                                                                                 std::sin(std::remainder(lon - cm, 360.0) * d2r),
                                                                             2)));
        if (std::fabs(k - 1.0) > worst)
            worst = std::fabs(k - 1.0), *at_lat = lat, *at_lon = lon;
    };
    auto visit = [&](double c, double r) {
        visit_at(t[0] + (c + 0.5) * t[1], t[3] + (r + 0.5) * t[5]);
    };
    for (int c = 0; c < dem->width; c++)
        visit(c, 0), visit(c, dem->height - 1);
    for (int r = 0; r < dem->height; r++)
        visit(0, r), visit(dem->width - 1, r);
    /* TM's scale grows with |sin(dlon)| and falls with |lat|: over a DEM more than ~174 degrees
     * wide its largest value is inside, 90 degrees from the central meridian at the latitude
     * nearest the equator (a global grid's edges, 180 degrees away, scale by almost nothing). */
    if (zone != 0) {
        const double lon0 = t[0] + 0.5 * t[1], lon1 = t[0] + (dem->width - 0.5) * t[1];
        const double lat_a = t[3] + 0.5 * t[5], lat_b = t[3] + (dem->height - 0.5) * t[5];
        const double lat_near = std::min(std::max(0.0, std::min(lat_a, lat_b)), std::max(lat_a, lat_b));
        for (int turn = -3; turn <= 3; turn++) {
            const double lon = cm + 90.0 + 180.0 * turn; /* every meridian 90 degrees away */
            if (lon >= std::min(lon0, lon1) && lon <= std::max(lon0, lon1))
                visit_at(lon, lat_near);
        }
    }
    return worst;
}

/* The extent GDALWarp will give the warped grid (GDALSuggestedWarpOutput2 over the source's
 * edges, as gdalwarp does): min x, min y, max x, max y in the target CRS. A dataset without
 * bands is enough: nothing is read. */
bool warp_extent(const tp_dem* dem, const double gt[6], const OGRSpatialReference& src,
                 const std::string& t_srs, double ext[4])
{
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    if (!mem)
        return false;
    tpio::Dataset ds(mem->Create("", dem->width, dem->height, 0, GDT_Float32, nullptr));
    if (!ds)
        return false;
    ds->SetGeoTransform(const_cast<double*>(gt));
    ds->SetSpatialRef(&src);
    std::string dst = "DST_SRS=" + t_srs;
    const char* topt[] = {dst.c_str(), nullptr};
    void* tr = GDALCreateGenImgProjTransformer2(GDALDataset::ToHandle(ds.get()), nullptr,
                                                const_cast<char**>(topt));
    if (!tr)
        return false;
    double ogt[6];
    int px = 0, ln = 0;
    CPLErr e = GDALSuggestedWarpOutput2(GDALDataset::ToHandle(ds.get()), GDALGenImgProjTransform,
                                        tr, ogt, &px, &ln, ext, 0);
    GDALDestroyGenImgProjTransformer(tr);
    return e == CE_None && std::isfinite(ext[0]) && std::isfinite(ext[2]) && ext[2] > ext[0] &&
           ext[3] > ext[1];
}

/* A CRS to suggest when one zone cannot hold the DEM: polar stereographic near a pole, else a
 * world projection in metres. *what says what it is. */
const char* suggested_crs(double lat_min, double lat_max, const char** what)
{
    if (lat_min > 45)
        return *what = "NSIDC polar stereographic north", "EPSG:3413";
    if (lat_max < -45)
        return *what = "Antarctic polar stereographic", "EPSG:3031";
    return *what = "Equal Earth, or a regional projected CRS", "EPSG:8857";
}

} // namespace

/* The render grid's CRS, spacing and size for dem (heights unused): see render_grid.hpp. */
tp_status tpio::render_grid_plan(const tp_dem* dem, const tp_grid_options* opt, GridPlan* plan,
                                 tp_error* err)
{
    tpio::register_drivers();
    tpio::QuietGdal quiet;
    tp_grid_options o = opt ? *opt : tp_grid_options{};
    std::string& warnings = plan->warnings;
    OGRSpatialReference& src = plan->src;
    OGRSpatialReference& dst = plan->dst;

    src.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    bool has_crs = false;
    if (o.crs && *o.crs) {
        if (src.SetFromUserInput(o.crs) != OGRERR_NONE)
            return fail(err, TP_ERR_INVALID_ARG, "CRS '%s' is not one GDAL/PROJ knows", o.crs);
        has_crs = true;
    } else if (dem->crs_wkt && *dem->crs_wkt) {
        if (src.importFromWkt(dem->crs_wkt) != OGRERR_NONE)
            return fail(err, TP_ERR_BAD_DATA, "the DEM's CRS could not be read");
        has_crs = true;
    } else if (dem->has_geotransform && plainly_geographic(dem)) {
        /* an ASCII grid in degrees without its .prj: as metres it would be 0.0008 m posts */
        src.importFromEPSG(4326);
        has_crs = true;
        const double* t = dem->geotransform;
        add_warning(warnings,
                    CPLSPrintf("no CRS, but the cell size %.9g and the extent (x %.9g .. %.9g, y "
                               "%.9g .. %.9g) are plainly degrees: taken as EPSG:4326 (WGS 84); "
                               "give --crs CRS (or a .prj beside the file) to override",
                               std::fabs(t[1]), t[0], t[0] + dem->width * t[1],
                               t[3] + dem->height * t[5], t[3]));
    }

    double gt[6];
    std::memcpy(gt, dem->geotransform, sizeof gt);
    dst.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    bool use_as_is = !has_crs || (src.IsProjected() && std::fabs(src.GetLinearUnits() - 1.0) < 1e-12);
    plan->has_crs = has_crs;
    plan->warp = !use_as_is;

    if (use_as_is) {
        plan->width = dem->width, plan->height = dem->height;
        if (has_crs)
            dst = src;
        else if (dem->has_geotransform) /* images without one were described by the user */
            add_warning(warnings, "no CRS: coordinates taken as metres (give --crs EPSG:N to set "
                                  "one, e.g. --crs EPSG:4326 for degrees)");
    } else {
        if (src.IsGeographic()) {
            /* Geographic rasters must stay on the globe: their posts (sample centres), that is;
             * a global grid with posts at +-90 has its pixel edges beyond. */
            double lat_a = gt[3] + 0.5 * gt[5], lat_b = gt[3] + (dem->height - 0.5) * gt[5];
            if (std::fabs(lat_a) > 90 + 1e-9 || std::fabs(lat_b) > 90 + 1e-9)
                return fail(err, TP_ERR_INVALID_ARG,
                            "posts at latitudes %.9g .. %.9g reach beyond +-90 degrees", lat_b,
                            lat_a);
        }
        /* The zone of the centre, for the whole scene. */
        OGRSpatialReference wgs84 = tpio::crs_wgs84();
        std::unique_ptr<OGRCoordinateTransformation> to_geo(
            OGRCreateCoordinateTransformation(&src, &wgs84));
        if (!to_geo)
            return fail(err, TP_ERR_BACKEND, "no transformation from the DEM's CRS to WGS84: %s",
                        tpio::gdal_message().c_str());
        double lon = gt[0] + dem->width / 2.0 * gt[1], lat = gt[3] + dem->height / 2.0 * gt[5];
        if (!to_geo->Transform(1, &lon, &lat))
            return fail(err, TP_ERR_BACKEND, "the DEM's centre has no WGS84 position: %s",
                        tpio::gdal_message().c_str());
        lon = std::remainder(lon, 360.0); /* a centre past the antimeridian, e.g. 180.5 */
        int zone, northp, epsg = utm_epsg(lat, lon, &zone, &northp);
        dst.importFromEPSG(epsg);
        std::unique_ptr<OGRCoordinateTransformation> ct(OGRCreateCoordinateTransformation(&src, &dst));
        if (!ct)
            return fail(err, TP_ERR_BACKEND, "no transformation to EPSG:%d: %s", epsg,
                        tpio::gdal_message().c_str());
        double res = finest_spacing(ct.get(), gt, dem->width, dem->height);
        if (!std::isfinite(res) || res <= 0)
            return fail(err, TP_ERR_BACKEND, "could not measure the DEM's post spacing in EPSG:%d",
                        epsg);
        std::string t_srs = "EPSG:" + std::to_string(epsg);
        const double* sg = dem->geotransform;

        /* One zone must hold the DEM sensibly: a geographic DEM whose posts the zone would scale
         * by more than 5% (UTM keeps within 0.1%) is refused, not drawn distorted. */
        if (src.IsGeographic()) {
            double k_lat = 0, k_lon = 0, k_err = zone_scale_error(dem, zone, &k_lat, &k_lon);
            if (k_err > 0.05) {
                double lat0 = sg[3] + (dem->height - 0.5) * sg[5], lat1 = sg[3] + 0.5 * sg[5];
                double lon0 = sg[0] + 0.5 * sg[1], lon1 = sg[0] + (dem->width - 0.5) * sg[1];
                const char* what = "";
                const char* crs = suggested_crs(std::min(lat0, lat1), std::max(lat0, lat1), &what);
                /* near 90 degrees from the meridian the scale has no useful bound */
                const std::string scale = k_err < 10.0 ? CPLSPrintf("up to %.0f%%", 100.0 * k_err)
                                                       : std::string("more than 1000%");
                return fail(err, TP_ERR_BAD_DATA,
                            "the DEM's posts span lon %.6g .. %.6g, lat %.6g .. %.6g: %s, the "
                            "zone of its centre, would scale it by %s (at lat %.4g, lon %.4g; "
                            "UTM keeps within 0.1%%), so one UTM/UPS zone cannot hold it; "
                            "reproject it first, e.g. 'gdalwarp -t_srs %s IN OUT.tif' (%s), or "
                            "cut it into smaller pieces",
                            lon0, lon1, std::min(lat0, lat1), std::max(lat0, lat1),
                            zone == 0 ? (northp ? "UPS north (EPSG:32661)" : "UPS south (EPSG:32761)")
                                      : CPLSPrintf("UTM zone %d%s (EPSG:%d)", zone, northp ? "N" : "S", epsg),
                            scale.c_str(), k_lat, k_lon, crs, what);
            }
        }

        /* The grid GDALWarp will make at that spacing must stay near the source's size: the
         * finest spacing of a DEM whose columns converge (near a pole) or of very anisotropic
         * posts would make millions of samples from a few thousand. Beyond 4x the source's
         * samples, posts as many as the source's, spread evenly over the warped extent. */
        double ext[4];
        if (!warp_extent(dem, gt, src, t_srs, ext))
            return fail(err, TP_ERR_BACKEND, "warp to EPSG:%d: no output extent: %s", epsg,
                        tpio::gdal_message().c_str());
        const double src_samples = (double)dem->width * dem->height;
        double pw = std::ceil((ext[2] - ext[0]) / res), ph = std::ceil((ext[3] - ext[1]) / res);
        const double bound = std::max(4.0 * src_samples, 4096.0);
        if (pw * ph > bound) {
            double coarse = std::sqrt((ext[2] - ext[0]) * (ext[3] - ext[1]) / src_samples);
            add_warning(warnings,
                        CPLSPrintf("warping to EPSG:%d at the finest post spacing %.3g m would "
                                   "make a %.0fx%.0f grid (%.3g times the DEM's %dx%d samples): "
                                   "posts %.6g m apart instead (as many samples as the DEM)",
                                   epsg, res, pw, ph, pw * ph / src_samples, dem->width,
                                   dem->height, coarse));
            res = coarse;
            pw = std::ceil((ext[2] - ext[0]) / res), ph = std::ceil((ext[3] - ext[1]) / res);
        }
        plan->width = (int)std::min(pw, 2147483647.0), plan->height = (int)std::min(ph, 2147483647.0);
        plan->epsg = epsg;
        plan->res = res;
        plan->t_srs = t_srs;
        plan->resampling = o.resampling;
    }
    return TP_OK;
}

double tpio::grid_finest_spacing(OGRCoordinateTransformation* ct, const double gt[6], int w, int h)
{
    return finest_spacing(ct, gt, w, h);
}

bool tpio::grid_warp_extent(const tp_dem* dem, const OGRSpatialReference& src,
                            const std::string& t_srs, double ext[4])
{
    return warp_extent(dem, dem->geotransform, src, t_srs, ext);
}

std::vector<std::string> tpio::render_grid_warp_args(const GridPlan& p, const char* format)
{
    const std::string tr = CPLSPrintf("%.17g", p.res);
    const char* resampling = p.resampling == TP_RESAMPLING_CUBIC ? "cubic" : "bilinear";
    /* -et 0: exact transformations for every post. GDAL's default (0.125 px) interpolates
     * along each row of a warp chunk, so the heights would depend on how the warp is chunked
     * (whole in memory here, block by block in a warped VRT read in bands): one grid, one
     * answer. */
    return {"-t_srs", p.t_srs, "-tr", tr, tr, "-r", resampling, "-et", "0", "-dstnodata", "nan",
            "-ot", "Float32", "-of", format};
}

void tpio::mask_outside_hull(OGRCoordinateTransformation& back, bool geographic,
                             const double sgt[6], int sw, int sh, const double gt[6], int w,
                             int y0, int rows, float* z)
{
    std::vector<double> ex(w), ny(w);
    std::vector<int> inside(w);
    const double lon_mid = sgt[0] + sw / 2.0 * sgt[1];
    for (int r = 0; r < rows; r++) {
        for (int c = 0; c < w; c++) {
            ex[c] = gt[0] + (c + 0.5) * gt[1];
            ny[c] = gt[3] + (y0 + r + 0.5) * gt[5];
        }
        back.Transform(w, ex.data(), ny.data(), nullptr, inside.data());
        for (int c = 0; c < w; c++) {
            if (geographic) /* longitudes come back in [-180, 180]: unwrap near the DEM's */
                ex[c] += 360.0 * std::round((lon_mid - ex[c]) / 360.0);
            double u = (ex[c] - sgt[0]) / sgt[1] - 0.5, v = (ny[c] - sgt[3]) / sgt[5] - 0.5;
            const double tol = 1e-6;
            if (!inside[c] || !(u >= -tol && v >= -tol && u <= sw - 1 + tol && v <= sh - 1 + tol))
                z[(size_t)r * w + c] = NAN;
        }
    }
}

namespace {

/* The rendered surface against every valid source post of dem (ct: the DEM's CRS to the
 * render CRS; grid on geotransform gt): g's warp errors. */
void measure_warp(const tp_dem* dem, OGRCoordinateTransformation* ct, const Grid& grid,
                  const double gt[6], tp_render_grid* g)
{
    double mx = 0, sum = 0;
    size_t count = 0;
    std::vector<double> xs(dem->width), ys(dem->width);
    std::vector<int> ok(dem->width);
    for (int r = 0; r < dem->height; r++) {
        for (int c = 0; c < dem->width; c++) {
            xs[c] = dem->geotransform[0] + (c + 0.5) * dem->geotransform[1];
            ys[c] = dem->geotransform[3] + (r + 0.5) * dem->geotransform[5];
        }
        ct->Transform(dem->width, xs.data(), ys.data(), nullptr, ok.data());
        for (int c = 0; c < dem->width; c++) {
            float s = dem->heights[(size_t)r * dem->width + c];
            if (!ok[c] || std::isnan(s))
                continue;
            /* the rendered surface: the core's triangle split */
            double z = tp_grid_height_at(grid.z.data(), grid.z.size(), grid.w, grid.h,
                                         (xs[c] - gt[0]) / gt[1] - 0.5,
                                         (ys[c] - gt[3]) / gt[5] - 0.5);
            if (std::isnan(z))
                continue;
            double e = std::fabs(z - s);
            mx = std::max(mx, e);
            sum += e * e;
            count++;
        }
    }
    g->warp_max_error_m = mx;
    g->warp_rms_error_m = count ? std::sqrt(sum / count) : 0;
    g->warp_posts = count;
}

/* dem warped by GDAL onto the planned grid (grid, its geotransform into gt), the rim outside
 * the source posts' hull not drawn, and the warp's errors into g. */
tp_status warp_dem(const tp_dem* dem, const tpio::GridPlan& plan, double gt[6], Grid& grid,
                   tp_render_grid* g, tp_error* err)
{
    const OGRSpatialReference& src = plan.src;
    const OGRSpatialReference& dst = plan.dst;
    const int epsg = plan.epsg;
    std::unique_ptr<OGRCoordinateTransformation> ct(OGRCreateCoordinateTransformation(&src, &dst));
    if (!ct)
        return fail(err, TP_ERR_BACKEND, "no transformation to EPSG:%d: %s", epsg,
                    tpio::gdal_message().c_str());
    tpio::Dataset src_ds = tpio::mem_dataset(dem->heights, dem->width, dem->height, gt, &src);
    if (!src_ds)
        return fail(err, TP_ERR_BACKEND, "warp: %s", tpio::gdal_message().c_str());
    std::vector<std::string> argv = tpio::render_grid_warp_args(plan, "MEM");
    argv.insert(argv.end(), {"-srcnodata", "nan"});
    std::vector<char*> args;
    for (auto& a : argv)
        args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    GDALWarpAppOptions* wo = GDALWarpAppOptionsNew(args.data(), nullptr);
    GDALDatasetH in = GDALDataset::ToHandle(src_ds.get());
    int usage = 0;
    tpio::Dataset warped(GDALDataset::FromHandle(GDALWarp("", nullptr, 1, &in, wo, &usage)));
    GDALWarpAppOptionsFree(wo);
    if (!warped)
        return fail(err, TP_ERR_BACKEND, "warp to EPSG:%d failed: %s", epsg,
                    tpio::gdal_message().c_str());
    grid.w = warped->GetRasterXSize();
    grid.h = warped->GetRasterYSize();
    grid.z.resize((size_t)grid.w * grid.h);
    warped->GetGeoTransform(gt);
    if (warped->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, grid.w, grid.h, grid.z.data(), grid.w,
                                           grid.h, GDT_Float32, 0, 0, nullptr) != CE_None)
        return fail(err, TP_ERR_BACKEND, "warp: %s", tpio::gdal_message().c_str());
    g->warped = 1;

    /* GDAL's output covers the source pixels' corners, half a post beyond the outermost
     * posts, where bilinear resampling only repeats the edge: that rim is outside the data
     * (posts are points: the data spans their hull), so it is not drawn. */
    std::unique_ptr<OGRCoordinateTransformation> back(OGRCreateCoordinateTransformation(&dst, &src));
    if (!back)
        return fail(err, TP_ERR_BACKEND, "no transformation back from EPSG:%d: %s", epsg,
                    tpio::gdal_message().c_str());
    tpio::mask_outside_hull(*back, src.IsGeographic(), dem->geotransform, dem->width,
                            dem->height, gt, grid.w, 0, grid.h, grid.z.data());
    measure_warp(dem, ct.get(), grid, gt, g);
    return TP_OK;
}

/* The --fill-from source (fill_from) warped onto the render grid (grid's size on gt, in the
 * render CRS crs_wkt) into other, in metres; its unit's warning added to warnings. */
tp_status read_fill_source(const char* fill_from, const double gt[6], const Grid& grid,
                           const std::string& crs_wkt, std::vector<float>& other,
                           std::string& warnings, tp_error* err)
{
    /* the second source on the render grid, checked even when nothing is to be filled */
    tpio::Dataset ods;
    tpio::ZUnit unit;
    if (const tp_status st = tpio::fill_source_open(fill_from, gt, grid.w, grid.h, crs_wkt, "MEM",
                                                    "", &ods, &unit, err))
        return st;
    other.resize(grid.z.size());
    if (ods->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, grid.w, grid.h, other.data(), grid.w,
                                        grid.h, GDT_Float32, 0, 0, nullptr) != CE_None)
        return fail(err, TP_ERR_BACKEND, "--fill-from %s: %s", fill_from,
                    tpio::gdal_message().c_str());
    tpio::fill_source_to_metres(other.data(), other.size(), unit);
    if (!unit.warning.empty())
        add_warning(warnings, unit.warning);
    if (std::none_of(other.begin(), other.end(), [](float v) { return !std::isnan(v); }))
        return fail(err, TP_ERR_BAD_DATA,
                    "--fill-from %s: no data where the DEM lies (every sample warped onto "
                    "the DEM's grid is nodata)",
                    fill_from);
    return TP_OK;
}

/* plan_w/plan_h not NULL: only plan, returning the render grid's size without warping. */
tp_status build(const tp_dem* dem, const tp_grid_options* opt, tp_render_grid** out, tp_error* err,
                int* plan_w = nullptr, int* plan_h = nullptr)
{
    tpio::register_drivers();
    tpio::QuietGdal quiet;
    tp_grid_options o = opt ? *opt : tp_grid_options{};
    const int fill_max = o.fill_max_px == 0 ? INT_MAX : o.fill_max_px; /* < 0: nothing */
    tpio::GridPlan plan;
    if (const tp_status st = tpio::render_grid_plan(dem, opt, &plan, err))
        return st;
    if (plan_w) {
        *plan_w = plan.width, *plan_h = plan.height;
        return TP_OK;
    }
    std::string warnings = plan.warnings;
    const OGRSpatialReference& dst = plan.dst;
    const bool has_crs = plan.has_crs;
    std::unique_ptr<tp_render_grid, GridDeleter> g(
        static_cast<tp_render_grid*>(std::calloc(1, sizeof(tp_render_grid))));
    if (!g)
        return fail(err, TP_ERR_OUT_OF_MEMORY, "render grid: out of memory");
    g->utm_zone = -1;
    Grid grid;
    double gt[6];
    std::memcpy(gt, dem->geotransform, sizeof gt);
    if (!plan.warp) {
        grid.w = dem->width;
        grid.h = dem->height;
        grid.z.assign(dem->heights, dem->heights + (size_t)dem->width * dem->height);
    } else {
        if (const tp_status st = warp_dem(dem, plan, gt, grid, g.get(), err))
            return st;
    }

    if (has_crs) {
        const char* name = dst.GetName();
        std::snprintf(g->crs_name, sizeof g->crs_name, "%s", name ? name : "unnamed CRS");
        g->epsg = tpio::crs_epsg(dst);
        g->wgs84 = tpio::crs_on_wgs84(dst);
        g->utm_zone = tpio::crs_utmups_zone(dst, &g->northp);
    } else {
        std::snprintf(g->crs_name, sizeof g->crs_name, "local metres (no CRS)");
    }

    tpio::FillSpec spec;
    spec.fill_max = fill_max;
    std::vector<float> other;
    if (o.fill_from && *o.fill_from) {
        if (const tp_status st =
                read_fill_source(o.fill_from, gt, grid,
                                 has_crs ? tpio::crs_wkt2(dst) : std::string(), other, warnings,
                                 err))
            return st;
        spec.other = other.data();
    }
    std::vector<uint8_t> filled;
    tpio::VoidCounts voids;
    tp_status st = tpio::fill_voids(grid.z.data(), grid.w, grid.h, gt, spec, true, true, filled,
                                    &voids, err);
    if (st != TP_OK)
        return st;
    g->outside_samples += voids.outside;
    g->large_void_samples += voids.large;
    g->filled_samples += voids.filled;
    g->filled_from_samples += voids.from_other;

    size_t n = (size_t)grid.w * grid.h;
    g->width = grid.w;
    g->height = grid.h;
    std::memcpy(g->geotransform, gt, sizeof gt);
    g->spacing_m = std::min(std::fabs(gt[1]), std::fabs(gt[5]));
    g->heights = static_cast<float*>(std::malloc(n * sizeof(float)));
    g->filled = static_cast<uint8_t*>(std::malloc(n));
    g->crs_wkt = tpio::dup_c(has_crs ? tpio::crs_wkt2(dst) : std::string());
    g->warnings = tpio::dup_c(warnings);
    if (!g->heights || !g->filled || !g->crs_wkt || !g->warnings)
        return fail(err, TP_ERR_OUT_OF_MEMORY, "render grid: out of memory for %dx%d samples",
                    grid.w, grid.h);
    std::memcpy(g->heights, grid.z.data(), n * sizeof(float));
    std::memcpy(g->filled, filled.data(), n);
    *out = g.release();
    return TP_OK;
}

} // namespace

extern "C" tp_status tp_render_grid_build(const tp_dem* dem, const tp_grid_options* options,
                                          tp_render_grid** out, tp_error* err)
{
    if (!dem || !out || !dem->heights)
        return fail(err, TP_ERR_INVALID_ARG, "render grid: dem and out must not be NULL");
    try {
        return build(dem, options, out, err);
    } catch (...) {
        return tpio::caught(err, "render grid");
    }
}

extern "C" tp_status tp_render_grid_plan(const tp_dem* dem, const tp_grid_options* options,
                                         int* width, int* height, tp_error* err)
{
    if (!dem || !width || !height)
        return fail(err, TP_ERR_INVALID_ARG, "render grid: dem, width and height must not be NULL");
    try {
        return build(dem, options, nullptr, err, width, height);
    } catch (...) {
        return tpio::caught(err, "render grid");
    }
}

/* Only free() here and plain field copies below: nothing can throw. */
extern "C" void tp_render_grid_destroy(tp_render_grid* grid)
{
    if (!grid)
        return;
    std::free(grid->heights);
    std::free(grid->filled);
    std::free(grid->crs_wkt);
    std::free(grid->warnings);
    std::free(grid);
}

extern "C" tp_terrain_desc tp_render_grid_terrain_desc(const tp_render_grid* grid, int patch_size,
                                                       tp_fit fit)
{
    tp_terrain_desc d{};
    d.patch_size = patch_size;
    d.fit = fit;
    if (!grid) /* as tp_dem_terrain_desc: a desc tp_terrain_create refuses */
        return d;
    d.heights = grid->heights;
    d.height_count = (size_t)grid->width * grid->height;
    d.width = grid->width;
    d.height = grid->height;
    std::memcpy(d.geotransform, grid->geotransform, sizeof d.geotransform);
    d.filled = grid->filled;
    d.filled_count = d.height_count;
    return d;
}
