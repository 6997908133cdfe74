/*
 * render_grid.hpp - the render grid's plan (CRS, post spacing, size) and warp, shared by
 * tp_render_grid_build (one DEM in memory) and the mosaic read in bands (mosaic.cpp), so that
 * one DEM gives the same grid and the same heights either way. Private to io/.
 */
#pragma once

#include "tp_io.h"

#include <ogr_spatialref.h>

#include <string>
#include <vector>

namespace tpio {

struct GridPlan {
    bool has_crs = false;          /* the grid has a CRS (dst) */
    bool warp = false;             /* warped from src to dst; else used as it is */
    OGRSpatialReference src, dst;  /* the DEM's CRS (or --crs), the render CRS */
    int epsg = 0;                  /* warp: the UTM/UPS zone's EPSG code */
    double res = 0;                /* warp: post spacing (m) */
    std::string t_srs;             /* warp: "EPSG:N" */
    tp_resampling resampling = TP_RESAMPLING_DEFAULT;
    int width = 0, height = 0;     /* of the render grid */
    std::string warnings;          /* '\n'-separated */
};

/* Plans the render grid of dem: only its size, geotransform, CRS and has_geotransform are
 * read (heights may be NULL). Fails as tp_render_grid_plan. */
tp_status render_grid_plan(const tp_dem* dem, const tp_grid_options* options, GridPlan* plan,
                           tp_error* err);

/* GDALWarp's arguments for a planned warp, output format `format` ("MEM", "VRT"); the source's
 * nodata is the caller's to add. */
std::vector<std::string> render_grid_warp_args(const GridPlan& plan, const char* format);

/* Sets to NaN the samples of rows y0 .. y0+rows-1 of a warped grid (geotransform gt, w columns;
 * z holds those rows) that lie outside the hull of the source's posts (sgt, sw x sh): GDAL's
 * output reaches half a post beyond them, where it only repeats the edge. back: render CRS ->
 * source CRS. */
void mask_outside_hull(OGRCoordinateTransformation& back, bool geographic, const double sgt[6],
                       int sw, int sh, const double gt[6], int w, int y0, int rows, float* z);

/* Finest post spacing (metres, ct's target CRS) of a w x h grid with geotransform gt, measured at
 * its corners and centre; INFINITY when none converts. */
double grid_finest_spacing(OGRCoordinateTransformation* ct, const double gt[6], int w, int h);

/* The extent (min x, min y, max x, max y) GDALWarp gives dem's grid in t_srs; false if none. */
bool grid_warp_extent(const tp_dem* dem, const OGRSpatialReference& src, const std::string& t_srs,
                      double ext[4]);

} // namespace tpio
