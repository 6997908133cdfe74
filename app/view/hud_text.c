/* hud_text.c - the overlay's words and their wrapping (see hud_text.h). */
#include "hud_text.h"

#include "hud.h"
#include "hud_lines.h"
#include "pick.h"
#include "position.h"
#include "tp_geo.h"
#include "view_shadows.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void tp_view_measure_now(const tp_view_scene* v, const tp_camera* cam, tp_measured_error* m)
{
    tp_view_scene_measure(v, cam, TP_STORE_MEASURE_POSTS_HUD, &m->max_m, &m->rms_m, &m->max_px,
                          &m->rms_px, &m->how);
    m->valid = 1;
}

void tp_view_position_parts(const tp_georef* g, double e, double n, char latlon[48], char utm[48],
                            char mgrs[TP_POSITION_MGRS_SPACED_SIZE])
{
    double lat, lon, ue, un;
    int zone, northp;
    char m[TP_MGRS_SIZE];
    latlon[0] = utm[0] = mgrs[0] = '\0';
    if (tp_georef_proj_to_geo(g, e, n, &lat, &lon, NULL) != TP_OK)
        return;
    snprintf(latlon, 48, "%.5f%c %.5f%c", fabs(lat), lat >= 0 ? 'N' : 'S', fabs(lon),
             lon >= 0 ? 'E' : 'W');
    char zname[TP_ZONE_TEXT_SIZE] = "";
    if (tp_geo_to_utmups(lat, lon, &zone, &northp, &ue, &un, NULL) != TP_OK ||
        tp_zone_format(zone, northp, TP_ZONE_STYLE_SHORT, zname, sizeof zname, NULL) != TP_OK)
        return; /* lat/lon only */
    snprintf(utm, 48, "%s %.0f %.0f", zname, ue, un);
    if (tp_mgrs_forward(zone, northp, ue, un, lat, 5, m, sizeof m, NULL) == TP_OK)
        tp_position_mgrs_spaced(m, mgrs, TP_POSITION_MGRS_SPACED_SIZE); /* "31T CH 76651 00831" */
}

void tp_view_position_text(const tp_georef* g, double e, double n, char* out, size_t cap)
{
    char latlon[48], utm[48], mgrs[TP_POSITION_MGRS_SPACED_SIZE];
    tp_view_position_parts(g, e, n, latlon, utm, mgrs);
    if (!utm[0])
        snprintf(out, cap, "%s", latlon);
    else
        snprintf(out, cap, "%s  UTM %s  MGRS %s", latlon, utm, mgrs);
}

/* The legend of the filled-void tint: what filled the voids and how many samples. A DEM read
 * whole knows (its render grid); a store says it in its notes (the line cmd_build writes:
 * "voids ... filled by interpolation ...: N samples (marked per sample)") and marks each filled
 * sample in its nodes' filled bits (format 4), which the renderer tints. */
static void voids_text(const tp_view_scene* v, char* out, size_t cap)
{
    out[0] = '\0';
    if (v->dem && v->dem->grid) {
        const tp_render_grid* g = v->dem->grid;
        if (g->filled_samples == 0)
            return;
        if (g->filled_from_samples)
            snprintf(out, cap, "\ntint: voids filled from a second source, shifted onto the ground "
                               "(%zu samples; %zu interpolated)",
                     g->filled_from_samples, g->filled_samples - g->filled_from_samples);
        else
            snprintf(out, cap, "\ntint: voids filled by interpolation (%zu samples)",
                     g->filled_samples);
        return;
    }
    const char* notes = v->store ? v->store->info.header.notes : NULL;
    const char* line = notes ? strstr(notes, "filled ") : NULL;
    const char* count = line ? strstr(line, "): ") : NULL;
    unsigned long long n = 0;
    if (!count || sscanf(count + 3, "%llu", &n) != 1 || n == 0)
        return;
    snprintf(out, cap, "\ntint: %llu samples filled %s", n,
             strncmp(line, "filled from", 11) == 0 ? "from a second source, shifted onto the ground"
                                                    : "by interpolation");
}

/* The default lines: what a user on the ground needs (hud_lines.h). */
static void ground_lines(tp_view_scene* v, const tp_camera* cam, const tp_hud_state* st, char* out,
                         size_t cap)
{
    char latlon[48], utm[48], mgrs[TP_POSITION_MGRS_SPACED_SIZE] = "";
    double g[3], x, y, yaw, pitch, ex = st->exaggeration > 0 ? st->exaggeration : 1;
    tp_camera_get_pose(cam, &yaw, &pitch);
    tp_view_scene_world_to_grid(v, cam->position[0], cam->position[1], &x, &y);
    tp_hud_ground hg = {.eye_m = cam->position[2],
                        .heading_deg = yaw,
                        .pitch_deg = pitch,
                        .grid_m = st->grid_m,
                        .orbit = st->orbit,
                        .speed_mps = st->speed_mps,
                        .frozen = st->frozen,
                        .exaggeration = ex,
                        .details = st->details};
    hg.above_m = cam->position[2] - tp_view_scene_ground_height(v, x, y) * ex;
    hg.m_per_px =
        tp_view_metres_per_pixel(v, cam, cam->viewport_w_px / 2.0, cam->viewport_h_px / 2.0, g);
    hg.centre = !isnan(hg.m_per_px) || tp_view_pick_centre(v, cam, g);
    if (hg.centre) {
        tp_view_position_parts(v->georef, g[0], g[1], latlon, utm, mgrs);
        hg.centre_mgrs = mgrs;
        hg.centre_latlon = latlon;
        hg.centre_e = g[0], hg.centre_n = g[1], hg.centre_elev_m = g[2];
    }
    tp_hud_ground_text(&hg, out, cap);
}

/* The engineering lines (TP_HUD_DETAILS_KEY; all of it is in --stats-json too): frame times,
 * counts, levels, the store's streaming, the LoD and its error, the full positions. */
static void detail_lines(tp_view_scene* v, const tp_camera* cam, const tp_lod_params* lod,
                         const frame_result* fr, const tp_measured_error* me,
                         const tp_hud_state* st, char* out, size_t cap)
{
    char measured[160] = "";
    if (me && me->valid && !isnan(me->max_m))
        snprintf(measured, sizeof measured, "   measured max %.2f m / %.2f px, RMS %.2f m / %.2f px",
                 me->max_m, me->max_px, me->rms_m, me->rms_px);
    else if (me && me->valid && isnan(me->max_px) && me->how.cut &&
             me->how.cut_error.leaves_skipped == 0) /* nothing of the ground in view */
        snprintf(measured, sizeof measured, "   error: no sample in view");
    else if (me && me->valid && isnan(me->max_px)) /* the measure failed (said on stderr) */
        snprintf(measured, sizeof measured, "   error not measured (see the terminal)");
    else if (me && me->valid && me->how.cut && me->how.cut_error.per_node &&
             me->how.cut_error.leaves) /* a store, sampled */
        snprintf(measured, sizeof measured,
                 "   measured max %.2f px, RMS %.2f px (%.0f%% of the leaves)", me->max_px,
                 me->rms_px,
                 100.0 * (double)me->how.cut_error.leaves_sampled / (double)me->how.cut_error.leaves);
    else if (me && me->valid)
        snprintf(measured, sizeof measured, "   measured max %.2f px, RMS %.2f px", me->max_px,
                 me->rms_px);
    char pos[256], ground[320] = "";
    double g[3];
    tp_view_position_text(v->georef, cam->position[0], cam->position[1], pos, sizeof pos);
    if (tp_view_pick_centre(v, cam, g)) {
        char gp[256];
        tp_view_position_text(v->georef, g[0], g[1], gp, sizeof gp);
        snprintf(ground, sizeof ground, "centre  %s   elevation %.1f m", gp[0] ? gp : "(no CRS)",
                 g[2]);
    } else {
        snprintf(ground, sizeof ground, "centre  (sky)");
    }
    char levels[128] = "";
    size_t at = 0;
    for (int k = 0; k <= v->n && at < sizeof levels; k++)
        at += (size_t)snprintf(levels + at, sizeof levels - at, " %d", fr->core.patches_per_level[k]);
    char lod_text[128];
    if (lod->mode == TP_LOD_ERROR)
        snprintf(lod_text, sizeof lod_text, "error, tau %.3g px", lod->tau_px > 0 ? lod->tau_px : 1);
    else if (lod->mode == TP_LOD_DISTANCE)
        snprintf(lod_text, sizeof lod_text, "%s, mindist %.0f m, maxdist %.0f m, exp %.3g",
                 lod->sphere_tree ? "distance (sphere tree)" : "distance", lod->mindist_m,
                 lod->maxdist_m, lod->exponent > 0 ? lod->exponent : 1);
    else
        snprintf(lod_text, sizeof lod_text, "full resolution");
    if (fr->pgm_cols) /* the patch LoD does not draw: the pyramid level is per vertex */
        snprintf(lod_text, sizeof lod_text, "per vertex (pyramid level from Eq. 3)");
    char store_line[400] = "", bound[160];
    tp_hud_bound hb = {.kind = TP_HUD_BOUND_M,
                       .max = fr->core.bound_max_error_m,
                       .rms_m = fr->core.bound_rms_error_m};
    if (fr->store) {
        snprintf(store_line, sizeof store_line,
                 "\nstore: %d nodes drawn (%d substituted)   resident %.1f MB   %d loads pending",
                 fr->nodes_drawn, fr->substituted, fr->stream.resident_bytes / 1e6,
                 fr->stream.pending);
        if (fr->imagery) {
            size_t n = strlen(store_line);
            snprintf(store_line + n, sizeof store_line - n,
                     "\nimagery: levels %d.. sampled   GPU %.0f MB   RAM %.0f MB   %d blocks "
                     "pending   upload %.2f ms (F3: off)",
                     fr->clip.first_level, fr->clip.gpu_bytes / 1e6, fr->clip.cache_bytes / 1e6,
                     fr->clip.pending, fr->clip.upload_ms);
        }
        hb = (tp_hud_bound){.kind = lod->mode == TP_LOD_ERROR ? TP_HUD_BOUND_PX : TP_HUD_BOUND_NONE,
                            .max = fr->bound_max_px,
                            .near_nodes = fr->bound_near_nodes};
    } else if (fr->pgm_cols) {
        snprintf(store_line, sizeof store_line,
                 "\nrenderer: pgm %dx%d   (Persistent Grid Mapping: the LoD options do not apply)",
                 fr->pgm_cols, fr->pgm_rows);
        hb.kind = TP_HUD_BOUND_NONE;
    }
    tp_hud_bound_text(&hb, bound, sizeof bound);
    char counts[160];
    if (fr->pgm_cols)
        snprintf(counts, sizeof counts, "grid of %d x %d vertices in screen space", fr->pgm_cols,
                 fr->pgm_rows);
    else
        snprintf(counts, sizeof counts, "%d %s drawn, %d culled   per level k=0..%d:%s",
                 fr->render.patches_drawn, fr->store ? "nodes" : "patches",
                 fr->core.culled_patches, v->n, levels);
    snprintf(out, cap,
             "%.1f fps   CPU %.2f ms (select %.2f, upload %.2f)   draw %.2f ms   GPU %.1f MB\n"
             "%zu triangles   %d draw calls   %s%s\n"
             "LoD %s%s   %s%s\n"
             "camera  %s   height %.1f m\n"
             "%s\n"
             "heights as in the DEM (SRTM/DTED: EGM96 geoid)",
             st->fps, fr->select_ms + fr->render.upload_ms, fr->select_ms, fr->render.upload_ms,
             fr->render.draw_ms, fr->render.gpu_bytes / 1e6, fr->core.triangles,
             fr->render.draw_calls, counts, store_line, lod_text, st->frozen ? " (frozen)" : "",
             bound, measured, pos[0] ? pos : "(no CRS: local metres)", cam->position[2], ground);
}

/* Appends "\n" and line to out (when line is not empty). */
static void add_line(char* out, size_t cap, const char* line, const char* suffix)
{
    if (!line || !line[0])
        return;
    size_t at = strlen(out);
    snprintf(out + at, cap - at, "\n%s%s", line, suffix);
}

void tp_view_hud_text(tp_view_scene* v, const tp_camera* cam, const tp_lod_params* lod,
                      const frame_result* fr, const tp_measured_error* me, const tp_hud_state* st,
                      char* out, size_t cap)
{
    ground_lines(v, cam, st, out, cap);
    /* what the user turned on or must know to read the picture: one line each */
    char voids[192];
    voids_text(v, voids, sizeof voids);
    add_line(out, cap, voids[0] == '\n' ? voids + 1 : voids, "");
    add_line(out, cap, st->layers, "");
    add_line(out, cap, st->sun, " (PgUp/PgDn: +/-15 min)");
    char shadows[160];
    tp_view_shadows_text(fr, shadows, sizeof shadows);
    add_line(out, cap, shadows, "");
    if (st->details) {
        char details[2048];
        detail_lines(v, cam, lod, fr, me, st, details, sizeof details);
        add_line(out, cap, details, "");
    }
}

static float width_of(const char* s, size_t n)
{
    char buf[1024];
    n = n < sizeof buf - 1 ? n : sizeof buf - 1;
    memcpy(buf, s, n);
    buf[n] = '\0';
    float w, h;
    tp_hud_measure(buf, &w, &h);
    return w;
}

/* Appends s[0..n) to out at *at (cut to cap). */
static void put(char* out, size_t cap, size_t* at, const char* s, size_t n)
{
    while (n-- && *at + 1 < cap)
        out[(*at)++] = *s++;
    out[*at] = '\0';
}

/* The end of the break unit starting at s (before the next run of `gap` spaces, or eol). */
static const char* unit_end(const char* s, const char* eol, int gap)
{
    for (const char* p = s; p < eol; p++) {
        int run = 0;
        while (p + run < eol && p[run] == ' ')
            run++;
        if (run >= gap && p > s)
            return p;
        p += run > 0 ? run - 1 : 0;
    }
    return eol;
}

size_t tp_hud_wrap(const char* text, float max_w, char* out, size_t cap)
{
    static const char indent[] = "    ";
    size_t at = 0;
    out[0] = '\0';
    for (const char* line = text; *line;) {
        const char* eol = strchr(line, '\n');
        if (!eol)
            eol = line + strlen(line);
        /* greedy: fields (3 spaces) first; a field too wide alone breaks between words (1);
         * a word wider than the line is not split */
        const char* p = line;
        int first = 1;
        while (p < eol) {
            if (!first)
                put(out, cap, &at, indent, sizeof indent - 1);
            float used = first ? 0 : width_of(indent, sizeof indent - 1);
            int placed = 0;
            for (int gap = 3; gap >= 1 && !placed; gap -= 2) {
                const char* q = p;
                while (q < eol) {
                    const char* e = unit_end(q, eol, gap);
                    float w = width_of(q, (size_t)(e - q));
                    if (placed && used + w > max_w)
                        break;
                    if (!placed && used + w > max_w && gap > 1)
                        break; /* this field alone is too wide: words */
                    put(out, cap, &at, q, (size_t)(e - q));
                    used += w;
                    placed = 1;
                    q = e;
                }
                p = q;
            }
            while (p < eol && *p == ' ')
                p++;
            first = 0;
            put(out, cap, &at, "\n", 1);
        }
        if (p == line) /* an empty line stays */
            put(out, cap, &at, "\n", 1);
        line = *eol ? eol + 1 : eol;
    }
    if (at > 0 && out[at - 1] == '\n')
        out[--at] = '\0';
    return at;
}
