/* hud_lines.c - the HUD's words from a frame's figures (see hud_lines.h). */
#include "hud_lines.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void tp_hud_length_text(double m, char* out, size_t cap)
{
    if (!isfinite(m))
        snprintf(out, cap, "-");
    else if (fabs(m) >= 1000)
        snprintf(out, cap, "%.3g km", m / 1000);
    else
        snprintf(out, cap, "%.3g m", m);
}

/* Appends printf text at *at (cut to cap). */
#define PUT(...)                                                                                   \
    do {                                                                                           \
        if (*at < cap) {                                                                           \
            int n_ = snprintf(out + *at, cap - *at, __VA_ARGS__);                                  \
            *at = n_ < 0 ? *at : *at + (size_t)n_ < cap ? *at + (size_t)n_ : cap - 1;              \
        }                                                                                          \
    } while (0)

static void centre_line(const tp_hud_ground* g, char* out, size_t cap, size_t* at)
{
    if (!g->centre) {
        PUT("centre: sky (no ground in the middle of the view)");
        return;
    }
    const int mgrs = g->centre_mgrs && g->centre_mgrs[0];
    const int ll = g->centre_latlon && g->centre_latlon[0];
    PUT("centre ");
    if (mgrs)
        PUT("%s   ", g->centre_mgrs);
    if (ll)
        PUT("%s   ", g->centre_latlon);
    if (!mgrs && !ll)
        PUT("E %.0f N %.0f (local)   ", g->centre_e, g->centre_n);
    PUT("elevation %.0f m", g->centre_elev_m);
}

static void eye_line(const tp_hud_ground* g, char* out, size_t cap, size_t* at)
{
    PUT("eye %.0f m", g->eye_m);
    if (isnan(g->above_m))
        PUT(" (not over the DEM)");
    else
        PUT(", %.0f m above ground", g->above_m);
    double hd = fmod(g->heading_deg, 360);
    hd = hd < 0 ? hd + 360 : hd;
    PUT("   heading %.0f deg   pitch %.0f deg", hd >= 359.5 ? 0 : hd, g->pitch_deg);
}

static void mode_line(const tp_hud_ground* g, char* out, size_t cap, size_t* at)
{
    char len[32];
    if (g->m_per_px > 0 && isfinite(g->m_per_px)) {
        if (g->m_per_px >= 1000)
            PUT("scale %.3g km/px", g->m_per_px / 1000);
        else if (g->m_per_px < 1)
            PUT("scale %.2g m/px", g->m_per_px);
        else
            PUT("scale %.*f m/px", g->m_per_px < 10 ? 1 : 0, g->m_per_px);
    } else {
        PUT("scale -");
    }
    if (g->grid_m > 0) {
        tp_hud_length_text(g->grid_m, len, sizeof len);
        PUT("   grid %s", len);
    }
    if (g->orbit)
        PUT("   ORBIT");
    else if (g->speed_mps > 0)
        PUT("   FLY %.0f m/s", g->speed_mps);
    else
        PUT("   FLY");
    if (g->exaggeration > 0 && g->exaggeration != 1)
        PUT("   heights x%.3g", g->exaggeration);
    if (g->frozen)
        PUT("   LoD frozen");
    PUT("   %s %s   ? keys", TP_HUD_DETAILS_KEY, g->details ? "hide details" : "details");
}

size_t tp_hud_ground_text(const tp_hud_ground* g, char* out, size_t cap)
{
    size_t a = 0, *at = &a;
    if (cap == 0)
        return 0;
    out[0] = '\0';
    centre_line(g, out, cap, at);
    PUT("\n");
    eye_line(g, out, cap, at);
    PUT("\n");
    mode_line(g, out, cap, at);
    return a;
}

void tp_hud_bound_text(const tp_hud_bound* b, char* out, size_t cap)
{
    if (b->kind == TP_HUD_BOUND_NONE) {
        snprintf(out, cap, "no error bound");
        return;
    }
    if (!isfinite(b->max)) { /* not expected (tp_cut_node.bound_px is finite): said plainly */
        snprintf(out, cap, "error bound unbounded");
        return;
    }
    if (b->kind == TP_HUD_BOUND_M) {
        snprintf(out, cap, "error bound max %.2f m, RMS %.2f m", b->max, b->rms_m);
        return;
    }
    size_t a = 0, *at = &a;
    out[0] = '\0';
    PUT("error bound max %.*f px", b->max < 100 ? 2 : 0, b->max);
    if (b->near_nodes > 0)
        PUT(" (%d node%s at the eye: bounded in front of the near plane)", b->near_nodes,
            b->near_nodes == 1 ? "" : "s");
}
