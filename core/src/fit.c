/* fit.c - resampling a grid to (r * 2^n + 1) x (s * 2^n + 1) posts (TP_FIT_RESAMPLE).
 *
 * The first and last posts keep their positions, so the georeference changes only by the
 * spacing (see terrain.c). Bilinear interpolation; a new post is nodata if any source post with
 * a non-zero weight is nodata, and filled if any such post is filled. */
#include "terrain_int.h"

#include <stdlib.h>

tp_status tp__fit_resample(const tp_allocator* a, const float* src, const uint8_t* src_filled,
                           int w, int h, int nw, int nh, float** out, uint8_t** out_filled,
                           tp_error* err)
{
    if (w < 2 || h < 2)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "fit resample: expected at least 2x2 samples, got %dx%d (use pad)", w, h);
    float* dst = tp__alloc(a, (size_t)nw * (size_t)nh, sizeof *dst);
    uint8_t* dfill = src_filled ? tp__calloc(a, (size_t)nw * (size_t)nh, 1) : NULL;
    if (!dst || (src_filled && !dfill)) {
        tp__free(a, dst);
        tp__free(a, dfill);
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "fit resample: out of memory");
    }
    double sx = (double)(w - 1) / (double)(nw - 1), sy = (double)(h - 1) / (double)(nh - 1);
    for (int j = 0; j < nh; j++) {
        double v = j * sy;
        int y0 = (int)v;
        if (y0 > h - 2)
            y0 = h - 2;
        double fy = v - y0;
        for (int i = 0; i < nw; i++) {
            double u = i * sx;
            int x0 = (int)u;
            if (x0 > w - 2)
                x0 = w - 2;
            double fx = u - x0;
            double wgt[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
            size_t at[4] = {(size_t)y0 * w + x0, (size_t)y0 * w + x0 + 1,
                            (size_t)(y0 + 1) * w + x0, (size_t)(y0 + 1) * w + x0 + 1};
            double z = 0;
            int nodata = 0, filled = 0;
            for (int c = 0; c < 4; c++) {
                if (wgt[c] == 0)
                    continue;
                float s = src[at[c]];
                if (!isfinite(s))
                    nodata = 1;
                else
                    z += wgt[c] * s;
                if (src_filled && src_filled[at[c]])
                    filled = 1;
            }
            size_t o = (size_t)j * nw + i;
            dst[o] = nodata ? NAN : (float)z;
            if (dfill)
                dfill[o] = (uint8_t)filled;
        }
    }
    *out = dst;
    *out_filled = dfill;
    return TP_OK;
}
