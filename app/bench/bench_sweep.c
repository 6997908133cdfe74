/* bench_sweep.c - the configurations of `bench --sweep`, their families and Pareto fronts, and
 * the plot's points (see bench.h). Every family runs on the same path, frames and cameras, and
 * its error is measured on the drawn geometry: the patch renderer's by tp_selection_measure_*
 * (vertex moving) or tp_stitch_add_error (vertex adding), PGM's by tp_pgm_measure_error, the
 * store's cut's (lattice or TIN nodes: bench_sweep_store.c) by tp_cut_measure_error. */
#include "bench.h"

#include "cli.h"
#include "renderer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* The grid: distance mode in patch widths (W = 2^n sample spacings), error mode in px. */
static const double sweep_mindist_w[] = {1, 4};
static const double sweep_maxdist_w[] = {12, 24, 48, 96};
static const double sweep_exp[] = {0.5, 1, 2};
static const double sweep_tau[] = {0.5, 1, 2, 4, 8, 16};
/* PGM: the grids of Livny, Kogan & El-Sana's Table 1 (cols x rows), then two square ones. */
static const int sweep_pgm[][2] = {{150, 600},  {200, 800}, {300, 900}, {600, 600},
                                   {400, 1600}, {300, 300}, {430, 430}};
#define COUNT(a) ((int)(sizeof(a) / sizeof *(a)))

tp_bench_family tp_bench_family_of(const config_result* c)
{
    if (c->store)
        return c->store == 2 ? TP_FAMILY_STORE_TIN : TP_FAMILY_STORE;
    if (c->pgm_cols)
        return TP_FAMILY_PGM;
    if (c->lod.mode == TP_LOD_FULL)
        return TP_FAMILY_FULL;
    if (c->lod.mode == TP_LOD_ERROR)
        return c->stitch_add ? TP_FAMILY_ERROR_ADD : TP_FAMILY_ERROR;
    return c->stitch_add ? TP_FAMILY_DISTANCE_ADD : TP_FAMILY_DISTANCE;
}

const char* tp_bench_family_name(tp_bench_family f)
{
    static const char* const names[TP_FAMILY_COUNT] = {
        "full", "distance", "error", "distance+add", "error+add", "pgm", "store", "store+tin"};
    return f >= 0 && f < TP_FAMILY_COUNT ? names[f] : "?";
}

void tp_bench_label(config_result* c)
{
    const tp_lod_params* lp = &c->lod;
    const char* add = c->stitch_add ? "+add" : "";
    if (c->store)
        snprintf(c->label, sizeof c->label, "%s tau=%g", c->store == 2 ? "store+tin" : "store",
                 lp->tau_px);
    else if (c->pgm_cols)
        snprintf(c->label, sizeof c->label, "pgm %dx%d", c->pgm_cols, c->pgm_rows);
    else if (lp->mode == TP_LOD_FULL)
        snprintf(c->label, sizeof c->label, "full");
    else if (lp->mode == TP_LOD_ERROR)
        snprintf(c->label, sizeof c->label, "error%s tau=%g", add, lp->tau_px);
    else
        snprintf(c->label, sizeof c->label, "distance%s %.0f/%.0f/%g", add, lp->mindist_m,
                 lp->maxdist_m, lp->exponent);
}

config_result* tp_bench_sweep_configs(const bench_run* b, const tp_lod_params* base, int* count,
                                      int* best)
{
    const bench_options* o = b->o;
    tp_lod_params def = {.mode = TP_LOD_DISTANCE};
    tp_lod_params_resolve(b->sc->terrain, &def, &def, NULL);
    double patch_w = def.maxdist_m / 24; /* the core's default maxdist is 24 patch widths */
    int pgm = o->vs.pgm_grid_count ? o->vs.pgm_grid_count : COUNT(sweep_pgm);
    int n = 1 + COUNT(sweep_mindist_w) * COUNT(sweep_maxdist_w) * COUNT(sweep_exp) +
            COUNT(sweep_tau) + 1 + 1 + COUNT(sweep_tau) + pgm + 2 * COUNT(sweep_tau);
    config_result* c = calloc((size_t)n, sizeof *c);
    if (!c)
        return NULL;
    int k = 0;
    c[k].lod = *base;
    c[k++].lod.mode = TP_LOD_FULL;
    for (int a = 0; a < COUNT(sweep_mindist_w); a++)
        for (int d = 0; d < COUNT(sweep_maxdist_w); d++)
            for (int e = 0; e < COUNT(sweep_exp); e++) {
                c[k].lod = *base;
                c[k].lod.mode = TP_LOD_DISTANCE;
                c[k].lod.mindist_m = sweep_mindist_w[a] * patch_w;
                c[k].lod.maxdist_m = sweep_maxdist_w[d] * patch_w;
                c[k++].lod.exponent = sweep_exp[e];
            }
    *best = -1;
    for (int t = 0; t < COUNT(sweep_tau); t++) {
        c[k].lod = *base;
        c[k].lod.mode = TP_LOD_ERROR;
        c[k].lod.tau_px = sweep_tau[t];
        if (sweep_tau[t] == base->tau_px)
            *best = k;
        k++;
    }
    if (*best < 0) { /* --tau not in the grid: one more */
        c[k].lod = *base;
        c[k].lod.mode = TP_LOD_ERROR;
        *best = k++;
    }
    /* --stitch add: the run's distance parameters, then every tau of the grid */
    c[k].lod = *base;
    c[k].lod.mode = TP_LOD_DISTANCE;
    c[k++].stitch_add = 1;
    for (int t = 0; t < COUNT(sweep_tau); t++) {
        c[k].lod = *base;
        c[k].lod.mode = TP_LOD_ERROR;
        c[k].lod.tau_px = sweep_tau[t];
        c[k++].stitch_add = 1;
    }
    tp_render_settings rs; /* --stitch-add-draw (else the renderer's default) */
    tp_render_settings_default(&rs);
    for (int i = 0; i < k; i++)
        c[i].stitch_add_five = o->stitch_add_draw ? o->stitch_add_draw == 2 : rs.stitch_add_five;
    for (int g = 0; g < pgm; g++, k++) {
        c[k].lod = *base;
        c[k].pgm_cols = o->vs.pgm_grid_count ? o->vs.pgm_grid[g][0] : sweep_pgm[g][0];
        c[k].pgm_rows = o->vs.pgm_grid_count ? o->vs.pgm_grid[g][1] : sweep_pgm[g][1];
    }
    /* the DEM's store through its cut, error mode: lattice nodes, then TIN nodes */
    for (int m = 1; m <= 2; m++)
        for (int t = 0; t < COUNT(sweep_tau); t++, k++) {
            c[k].lod = *base;
            c[k].lod.mode = TP_LOD_ERROR;
            c[k].lod.tau_px = sweep_tau[t];
            c[k].lod.sphere_tree = 0;
            c[k].store = m;
        }
    for (int i = 0; i < k; i++)
        tp_bench_label(&c[i]);
    *count = k;
    return c;
}

void tp_bench_mark_pareto(config_result* c, int nc)
{
    for (int i = 0; i < nc; i++) {
        tp_bench_family f = tp_bench_family_of(&c[i]);
        c[i].pareto = f != TP_FAMILY_FULL;
        for (int k = 0; k < nc && c[i].pareto; k++)
            if (k != i && tp_bench_family_of(&c[k]) == f && c[k].fps_median >= c[i].fps_median &&
                c[k].max_px <= c[i].max_px &&
                (c[k].fps_median > c[i].fps_median || c[k].max_px < c[i].max_px))
                c[i].pareto = 0;
    }
}

int tp_bench_sweep_plot(const config_result* c, int nc, const char* png, const char* title)
{
    tp_bench_point* pts = calloc((size_t)(nc > 1 ? nc : 1), sizeof *pts);
    if (!pts) {
        tp_cli_error("out of memory");
        return 0;
    }
    for (int k = 1; k < nc; k++)
        pts[k - 1] = (tp_bench_point){
            tp_bench_family_of(&c[k]), c[k].lod.tau_px, c[k].pgm_cols, c[k].pgm_rows,
            c[k].fps_median,           c[k].max_px,     c[k].rms_px,   c[k].pareto};
    int ok = tp_bench_plot(pts, nc - 1, png, title, c[0].fps_median);
    free(pts);
    return ok;
}
