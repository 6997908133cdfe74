/* build_rows.c - the render grid's rows as a store build reads them (see build_rows.h). */
#include "build_rows.h"

#include "cli.h"
#include "progress.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void tp_build_rows_band(const tp_build_rows* br, int r, int* y0, int* count)
{
    const int skip = r > 0 ? 1 : 0;
    const int first = r * br->ps + skip, last = r * br->ps + br->ps;
    const int read_to = last < br->height - 1 ? last : br->height - 1;
    *y0 = first;
    *count = read_to >= first ? read_to - first + 1 : 0;
}

tp_status tp_build_rows_read(tp_build_rows* br, int y0, int count, float* heights,
                             uint8_t* filled, tp_error* err)
{
    const size_t n = (size_t)count * br->width, at = (size_t)y0 * br->width;
    if (br->held) {
        memcpy(heights, br->held + at, n * sizeof *heights);
        if (filled)
            memcpy(filled, br->held_filled + at, n);
        return TP_OK;
    }
    return tp_mosaic_read_rows_filled(br->m, y0, count, heights, n, filled, err);
}

tp_status tp_build_rows_range(tp_build_rows* br, int bands, size_t hold_bytes, int quiet,
                              float* rows, uint8_t* filled, tp_build_range* out, tp_error* err)
{
    const size_t samples = (size_t)br->width * br->height;
    tp_build_rows_release(br);
    float* held = NULL;
    uint8_t* held_filled = NULL;
    if (samples * (sizeof(float) + (br->fill ? 1 : 0)) <= hold_bytes) {
        held = malloc(samples * sizeof *held);
        held_filled = br->fill ? malloc(samples) : NULL;
        if (!held || (br->fill && !held_filled)) { /* read twice instead */
            free(held), free(held_filled);
            held = NULL, held_filled = NULL;
        }
    }
    float lo = INFINITY, hi = -INFINITY;
    size_t valid = 0;
    int integral = 1;
    tp_progress pr;
    tp_progress_start(&pr, !quiet, "build", "range");
    tp_status st = TP_OK;
    for (int r = 0; r < bands && st == TP_OK; r++) {
        int y0, n;
        tp_build_rows_band(br, r, &y0, &n);
        if (n == 0)
            break;
        st = tp_build_rows_read(br, y0, n, rows, br->fill ? filled : NULL, err);
        if (st != TP_OK)
            break;
        const size_t count = (size_t)n * br->width;
        for (size_t i = 0; i < count; i++) {
            float v = rows[i];
            valid += v == v;
            lo = v < lo ? v : lo; /* NaN compares false: skipped */
            hi = v > hi ? v : hi;
            integral = integral && (v != v || v == floorf(v));
        }
        if (held) {
            const size_t at = (size_t)y0 * br->width;
            memcpy(held + at, rows, count * sizeof *rows);
            if (held_filled)
                memcpy(held_filled + at, filled, count);
        }
        tp_progress_update(&pr, y0 + n, br->height, (double)(y0 + n) * br->width);
        if (tp_interrupted())
            st = tp_error_set(err, TP_ERR_IO, "interrupted");
    }
    if (st != TP_OK) {
        free(held), free(held_filled);
        return st;
    }
    br->held = held, br->held_filled = held_filled;
    *out = (tp_build_range){.lo = lo, .hi = hi, .valid = valid, .integral = integral};
    return TP_OK;
}

void tp_build_rows_release(tp_build_rows* br)
{
    free(br->held);
    free(br->held_filled);
    br->held = NULL;
    br->held_filled = NULL;
}
