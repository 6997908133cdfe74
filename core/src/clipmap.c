/* clipmap.c - clip windows over an image pyramid and per-polygon texture levels (tp_core.h,
 * "Clip windows"). */
#include "tp_clipmap.h"

#include <math.h>
#include <string.h>

tp_clip_window tp_clip_window_centred(double cx, double cy, int block, int s)
{
    tp_clip_window w;
    w.s = s;
    w.bx0 = (int64_t)floor(cx / block - s / 2.0 + 0.5);
    w.by0 = (int64_t)floor(cy / block - s / 2.0 + 0.5);
    return w;
}

int tp_clip_slot(int64_t b, int s)
{
    int64_t m = b % s;
    return (int)(m < 0 ? m + s : m);
}

int tp_clip_window_contains(const tp_clip_window* w, int64_t bx, int64_t by)
{
    return bx >= w->bx0 && bx < w->bx0 + w->s && by >= w->by0 && by < w->by0 + w->s;
}

/* Every block of the row (vertical = 0) or column [a, b) at index c inside the window and
 * resident. */
static int line_ok(const tp_clip_window* w, int vertical, int64_t c, int64_t a, int64_t b,
                   tp_clip_resident_fn resident, void* user)
{
    for (int64_t i = a; i < b; i++) {
        int64_t bx = vertical ? c : i, by = vertical ? i : c;
        if (!tp_clip_window_contains(w, bx, by) || !resident(user, bx, by))
            return 0;
    }
    return 1;
}

int tp_clip_valid_rect(const tp_clip_window* w, double cx, double cy, int block,
                       tp_clip_resident_fn resident, void* user, int64_t rect[4])
{
    int64_t x0 = (int64_t)floor(cx / block), y0 = (int64_t)floor(cy / block);
    if (!tp_clip_window_contains(w, x0, y0) || !resident(user, x0, y0))
        return 0;
    int64_t x1 = x0 + 1, y1 = y0 + 1;
    int open[4] = {1, 1, 1, 1}; /* east, south, west, north can still grow */
    while (open[0] || open[1] || open[2] || open[3]) {
        if (open[0] && (open[0] = line_ok(w, 1, x1, y0, y1, resident, user)))
            x1++;
        if (open[1] && (open[1] = line_ok(w, 0, y1, x0, x1, resident, user)))
            y1++;
        if (open[2] && (open[2] = line_ok(w, 1, x0 - 1, y0, y1, resident, user)))
            x0--;
        if (open[3] && (open[3] = line_ok(w, 0, y0 - 1, x0, x1, resident, user)))
            y0--;
    }
    rect[0] = x0;
    rect[1] = y0;
    rect[2] = x1;
    rect[3] = y1;
    return 1;
}

int tp_texture_level(float texels_per_pixel, int max_level)
{
    if (!(texels_per_pixel >= 1.0f)) /* below 1, or NaN */
        return 0;
    uint32_t bits;
    memcpy(&bits, &texels_per_pixel, sizeof bits);
    int e = (int)((bits >> 23) & 0xff) - 127; /* floor(log2) of a normal float >= 1 */
    return e > max_level ? max_level : e;
}

int tp_patch_texture_level(double distance_m, double focal_px, double texel_m, int previous,
                           int max_level)
{
    double ratio = distance_m / (focal_px * texel_m);
    int level = tp_texture_level((float)ratio, max_level);
    /* coarser than last frame only once clearly past the boundary */
    if (previous >= 0 && level > previous && previous < max_level &&
        tp_texture_level((float)(ratio / 1.125), max_level) <= previous)
        return previous;
    return level;
}
