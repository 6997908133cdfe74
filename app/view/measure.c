/* measure.c - the measuring tool (see measure.h). */
#include "measure.h"

#include "tp_geo.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int tp_measure(const tp_georef* g, const double e[2], const double n[2], const double h[2],
               tp_measurement* out)
{
    memset(out, 0, sizeof *out);
    double de = e[1] - e[0], dn = n[1] - n[0];
    out->grid_distance_m = hypot(de, dn);
    out->grid_bearing_deg = fmod(atan2(de, dn) * 180 / 3.14159265358979323846 + 360, 360);
    out->height_m[0] = h[0];
    out->height_m[1] = h[1];
    out->height_diff_m = h[1] - h[0];
    if (!tp_georef_has_geo(g)) {
        for (int i = 0; i < 2; i++)
            out->lat_deg[i] = out->lon_deg[i] = NAN;
        out->distance_m = out->grid_distance_m;
        out->true_bearing_deg = out->grid_bearing_deg;
        return 1;
    }
    for (int i = 0; i < 2; i++)
        if (tp_georef_proj_to_geo(g, e[i], n[i], &out->lat_deg[i], &out->lon_deg[i], NULL) != TP_OK)
            return 0;
    double azi1, azi2;
    if (tp_geodesic_inverse(out->lat_deg[0], out->lon_deg[0], out->lat_deg[1], out->lon_deg[1],
                            &azi1, &azi2, &out->distance_m, NULL) != TP_OK)
        return 0;
    out->true_bearing_deg = fmod(azi1 + 360, 360);
    return 1;
}

void tp_measurement_text(const tp_measurement* m, char* out, size_t cap)
{
    snprintf(out, cap,
             "distance %.3f m (geodesic; %.3f m on the grid), bearing %.2f deg true / %.2f deg "
             "grid, height difference %+.1f m",
             m->distance_m, m->grid_distance_m, m->true_bearing_deg, m->grid_bearing_deg,
             m->height_diff_m);
}
