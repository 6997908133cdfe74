/* bench_path.c - the benchmark's camera paths: low, high and orbit flights over the DEM, or
 * the cameras of a --path-file (see bench.h). */
#include "bench.h"

#include "camera_pose.h"
#include "cli.h"

#include "tp_io.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEG (3.14159265358979323846 / 180.0)

/* The path's extent: the DEM's corner posts, centre and size. */
static void path_frame(const tp_scene* sc, double* e0, double* n0, double* e1, double* n1,
                       double* size)
{
    const tp_terrain_info* in = &sc->info;
    tp_terrain_grid_to_world(sc->terrain, 0, 0, e0, n0);
    tp_terrain_grid_to_world(sc->terrain, in->src_width - 1, in->src_height - 1, e1, n1);
    *size = fmax(fabs(*e1 - *e0), fabs(*n1 - *n0));
}

double tp_bench_path_length(const tp_scene* sc, const bench_options* o)
{
    double e0, n0, e1, n1, size;
    path_frame(sc, &e0, &n0, &e1, &n1, &size);
    if (!strcmp(o->path_name, "high"))
        return 0.8 * fabs(e1 - e0);
    if (!strcmp(o->path_name, "orbit"))
        return 2 * 3.14159265358979323846 * 0.45 * size;
    return 0.9 * fabs(e1 - e0);
}

/* The camera at parameter a (0 .. 1) of the named path. */
static void path_camera(const tp_scene* sc, const bench_options* o, double a, tp_camera* cam)
{
    const tp_terrain_info* in = &sc->info;
    double e0, n0, e1, n1, size;
    path_frame(sc, &e0, &n0, &e1, &n1, &size);
    double ce = (e0 + e1) / 2, cn = (n0 + n1) / 2;
    if (!strcmp(o->path_name, "high")) {
        double e = e0 + (0.1 + 0.8 * a) * (e1 - e0), nn = fmin(n0, n1) - 0.15 * size;
        tp_camera_pose(e, nn, in->max_height_m + 0.35 * size, 0, -35, o->vs.fov_deg, o->vs.w, o->vs.h, cam);
    } else if (!strcmp(o->path_name, "orbit")) {
        double ang = 2 * 3.14159265358979323846 * a, r = 0.45 * size;
        double e = ce - r * sin(ang), nn = cn - r * cos(ang), h = in->max_height_m + 0.2 * size;
        double pitch = -atan2(h - (in->min_height_m + in->max_height_m) / 2, r) / DEG;
        tp_camera_pose(e, nn, h, ang / DEG, pitch, o->vs.fov_deg, o->vs.w, o->vs.h, cam);
    } else { /* low: across the middle row, 60 m above the ground, looking ahead */
        double e = e0 + (0.05 + 0.9 * a) * (e1 - e0), x, y;
        tp_terrain_world_to_grid(sc->terrain, e, cn, &x, &y);
        double g = tp_terrain_height_at(sc->terrain, x, y);
        tp_camera_pose(e, cn, (isnan(g) ? in->max_height_m : g) + 60, 90, -10, o->vs.fov_deg, o->vs.w,
                       o->vs.h, cam);
    }
}

int tp_bench_read_path_file(const tp_scene* sc, const bench_options* o, tp_camera** out, int* count)
{
    tp_error err;
    if (tp_input_check(o->path_file, "a camera path (text)", 0, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return 0;
    }
    FILE* f = fopen(o->path_file, "r");
    if (!f) {
        tp_cli_error("%s: cannot open: %s", o->path_file, strerror(errno));
        return 0;
    }
    int cap = 64, n = 0, line_no = 0;
    tp_camera* cams = malloc((size_t)cap * sizeof *cams);
    char line[512];
    while (cams && fgets(line, sizeof line, f)) {
        line_no++;
        char* s = line;
        while (*s == ' ' || *s == '\t')
            s++;
        if (*s == '#' || *s == '\n' || *s == '\0')
            continue;
        int proj = !strncmp(s, "proj ", 5);
        if (proj)
            s += 5;
        if (!strncmp(s, "--camera-geo ", 13))
            s += 13;
        double v[5];
        if (sscanf(s, "%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4]) != 5) {
            tp_cli_error("%s: line %d: expected LAT,LON,H,YAW,PITCH", o->path_file, line_no);
            free(cams);
            fclose(f);
            return 0;
        }
        if (n == cap) {
            tp_camera* more = realloc(cams, (size_t)(cap *= 2) * sizeof *cams);
            if (!more)
                break;
            cams = more;
        }
        if (!tp_camera_from_option(sc, !proj, v, o->vs.fov_deg, o->vs.w, o->vs.h, &cams[n], "bench")) {
            free(cams);
            fclose(f);
            return 0;
        }
        n++;
    }
    fclose(f);
    if (!cams || n == 0) {
        tp_cli_error("%s: no camera in the file", o->path_file);
        free(cams);
        return 0;
    }
    *out = cams;
    *count = n;
    return 1;
}

int tp_bench_frame_camera(const bench_run* b, int i, tp_camera* cam, tp_camera* lead)
{
    if (b->cams) {
        *cam = b->cams[i];
        return 0;
    }
    if (b->fixed) {
        *cam = *b->fixed;
        return 0;
    }
    double a = (i + 0.5) / b->frames;
    path_camera(b->sc, b->o, a, cam);
    if (b->lead_da <= 0)
        return 0;
    path_camera(b->sc, b->o, a - b->lead_da, lead);
    return 1;
}
