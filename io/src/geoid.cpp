/*
 * geoid.cpp - the EGM96 geoid's undulation through PROJ's vertical grid (see tp_io/geoid.h).
 */
#include "io_util.hpp"
#include "tp_io.h"

#include <cmath>
#include <proj.h>
#include <string>

using tpio::fail;

struct tp_geoid {
    PJ_CONTEXT* ctx = nullptr;
    PJ* op = nullptr; /* EPSG:4979 (lon, lat, h) -> EPSG:4326+5773 (lon, lat, EGM96 height) */
    std::string name;
};

void tp_geoid_close(tp_geoid* g)
{
    if (!g)
        return;
    if (g->op)
        proj_destroy(g->op);
    if (g->ctx)
        proj_context_destroy(g->ctx);
    delete g;
}

tp_status tp_geoid_open(tp_geoid** out, tp_error* err)
{
    if (!out)
        return fail(err, TP_ERR_INVALID_ARG, "tp_geoid_open: NULL out");
    try {
        tp_geoid* g = new tp_geoid;
        g->ctx = proj_context_create();
        PJ* op = proj_create_crs_to_crs(g->ctx, "EPSG:4979", "EPSG:4326+5773", nullptr);
        /* a probe: the undulation near (45N, 2E) is about +50 m; a missing grid gives 0 */
        double n_probe = NAN;
        if (op) {
            PJ* norm = proj_normalize_for_visualization(g->ctx, op);
            proj_destroy(op);
            op = norm;
        }
        std::string used;
        if (op) {
            PJ_COORD c = proj_coord(2.0, 45.0, 0.0, 0.0);
            c = proj_trans(op, PJ_FWD, c);
            n_probe = -c.xyz.z;
            if (PJ* last = proj_trans_get_last_used_operation(op)) {
                const char* nm = proj_get_name(last);
                used = nm ? nm : "";
                proj_destroy(last);
            }
        }
        if (!op || !std::isfinite(n_probe) || std::fabs(n_probe) < 1.0) {
            if (op)
                proj_destroy(op);
            tp_geoid_close(g);
            return fail(err, TP_ERR_BACKEND,
                        "no EGM96 geoid grid for PROJ (us_nga_egm96_15, Debian's proj-data "
                        "ships it as /usr/share/proj/egm96_15.gtx; PROJ_DATA names the folder "
                        "PROJ reads): ellipsoidal heights cannot be computed");
        }
        g->op = op;
        g->name = "EGM96 through PROJ's grid us_nga_egm96_15 (15 arc-minutes, bilinear)" +
                  (used.empty() ? std::string() : ": " + used);
        *out = g;
        return TP_OK;
    } catch (...) {
        return fail(err, TP_ERR_OUT_OF_MEMORY, "out of memory opening the geoid");
    }
}

const char* tp_geoid_name(const tp_geoid* g) { return g ? g->name.c_str() : ""; }

tp_status tp_geoid_undulation(tp_geoid* g, size_t n, const double* lat_deg, const double* lon_deg,
                              double* n_m, tp_error* err)
{
    if (!g || (n && (!lat_deg || !lon_deg || !n_m)))
        return fail(err, TP_ERR_INVALID_ARG, "tp_geoid_undulation: bad arguments");
    for (size_t i = 0; i < n; i++) {
        PJ_COORD c = proj_coord(lon_deg[i], lat_deg[i], 0.0, 0.0);
        c = proj_trans(g->op, PJ_FWD, c);
        if (!std::isfinite(c.xyz.z))
            return fail(err, TP_ERR_INVALID_ARG, "no geoid undulation at %.9g, %.9g", lat_deg[i],
                        lon_deg[i]);
        n_m[i] = -c.xyz.z; /* EGM96 height of a point on the ellipsoid is -N */
    }
    return TP_OK;
}
