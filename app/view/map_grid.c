/* map_grid.c - the grid labels' text (see map_grid.h). */
#include "map_grid.h"

#include "position.h"
#include "tp_geo.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Whether (e, n) of the render CRS is (e, n) of UTM zone `zone` (0: UPS), hemisphere northp. */
static int is_zone(const tp_georef* georef, double e, double n, int zone, int northp)
{
    double lat, lon, lat2, lon2;
    if (tp_georef_proj_to_geo(georef, e, n, &lat, &lon, NULL) != TP_OK ||
        tp_geo_from_utmups(zone, northp, e, n, &lat2, &lon2, NULL) != TP_OK)
        return 0;
    double dlon = fmod(fabs(lon - lon2), 360);
    dlon = fmin(dlon, 360 - dlon);
    double dn = (lat - lat2) * 111320.0, de = dlon * 111320.0 * cos(lat * 3.14159265358979323846 / 180);
    return hypot(de, dn) < TP_MAP_GRID_MATCH_M;
}

double tp_map_grid_spacing(double base_m, double m_per_px)
{
    double s = base_m;
    for (int k = 0; k < TP_MAP_GRID_MAX_STEPS; k++) {
        if (m_per_px > 0 && s >= TP_MAP_GRID_MIN_PX * m_per_px) /* false for NaN */
            break;
        s *= 10;
    }
    return s;
}

void tp_map_grid_init(tp_map_grid* g, const tp_georef* georef, const double gt[6], int width,
                      int height, double spacing_m)
{
    memset(g, 0, sizeof *g);
    /* plain: kilometres with as many decimals as the spacing needs (1500 m: 4501.5) */
    while (g->decimals < 3 && fmod(spacing_m, 1000 / pow(10, g->decimals)) != 0)
        g->decimals++;
    /* MGRS: digits per coordinate, 1000 m: 2 ("76"), 100 m: 3, 10 km: 1, 100 km: 0 */
    g->digits = 5;
    for (int p = 0; p <= 5; p++)
        if (fmod(spacing_m, pow(10, 5 - p)) == 0) {
            g->digits = p;
            break;
        }
    double e = gt[0] + width / 2.0 * gt[1], n = gt[3] + height / 2.0 * gt[5], lat, lon;
    int zone, northp;
    double ue, un;
    if (!georef || !tp_georef_has_geo(georef) ||
        tp_georef_proj_to_geo(georef, e, n, &lat, &lon, NULL) != TP_OK ||
        tp_geo_to_utmups(lat, lon, &zone, &northp, &ue, &un, NULL) != TP_OK)
        return;
    /* the standard zone of the centre, its neighbours (a render grid kept in one zone across a
     * zone edge), the other hemisphere (near the equator), UPS */
    const int cand[][2] = {{zone, northp}, {zone - 1, northp}, {zone + 1, northp},
                           {zone, !northp}, {0, northp}};
    for (size_t i = 0; i < sizeof cand / sizeof cand[0]; i++) {
        int z = cand[i][0] == 61 ? 1 : cand[i][0] == -1 ? 60 : cand[i][0];
        if ((zone == 0) != (z == 0) && i < 4)
            continue; /* UTM neighbours of a UPS point, or the reverse */
        if (is_zone(georef, e, n, z, cand[i][1])) {
            g->kind = TP_MAP_GRID_MGRS;
            g->zone = z;
            g->northp = cand[i][1];
            return;
        }
    }
}

static void plain(const tp_map_grid* g, double e, double n, char* square, char* digits)
{
    square[0] = '\0';
    snprintf(digits, 32, "%.*fE %.*fN", g->decimals, e / 1000, g->decimals, n / 1000);
}

void tp_map_grid_label(const tp_map_grid* g, double e, double n, char* square, char* digits)
{
    if (g->kind != TP_MAP_GRID_MGRS) {
        plain(g, e, n, square, digits);
        return;
    }
    /* MGRS truncates: a line at 476000 computed as 475999.9999999 would read 75 */
    char mgrs[TP_MGRS_SIZE], spaced[TP_POSITION_MGRS_SPACED_SIZE];
    if (tp_mgrs_forward(g->zone, g->northp, e + 1e-3, n + 1e-3, NAN, g->digits, mgrs, sizeof mgrs,
                        NULL) != TP_OK ||
        !tp_position_mgrs_spaced(mgrs, spaced, sizeof spaced)) {
        plain(g, e, n, square, digits);
        return;
    }
    /* "31T CH 76 00": the square is the first two fields */
    char* sp = strchr(spaced, ' ');
    sp = sp ? strchr(sp + 1, ' ') : NULL;
    if (!sp) { /* 100 km spacing: the square alone */
        snprintf(square, 16, "%.15s", spaced);
        digits[0] = '\0';
        return;
    }
    *sp = '\0';
    snprintf(square, 16, "%.15s", spaced);
    snprintf(digits, 32, "%.31s", sp + 1);
}
