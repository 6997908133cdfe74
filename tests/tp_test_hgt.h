/*
 * tp_test_hgt.h - a crop of the real SRTM tile N42E001.hgt for the tree and cut tests, read
 * directly (raw big-endian int16, 1201 x 1201, row 0 north, -32768 = void) so that core tests
 * need no io library. Include after tp_test.h.
 */
#ifndef TP_TEST_HGT_H
#define TP_TEST_HGT_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

/* A w x h crop at (x0, y0) of N42E001.hgt (voids NaN), or NULL when the file is missing. */
static float* load_hgt(int x0, int y0, int w, int h)
{
    char path[1024];
    if (!tp_test_data_path(path, sizeof path, "TP_SHARED_DATA_DIR", "N42E001.hgt"))
        return NULL;
    FILE* f = fopen(path, "rb");
    if (!f)
        return NULL;
    unsigned char* raw = malloc((size_t)1201 * 1201 * 2);
    size_t got = raw ? fread(raw, 1, (size_t)1201 * 1201 * 2, f) : 0;
    fclose(f);
    if (got != (size_t)1201 * 1201 * 2) {
        free(raw);
        return NULL;
    }
    float* out = malloc((size_t)w * h * sizeof *out);
    for (int y = 0; out && y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = ((size_t)(y0 + y) * 1201 + (size_t)(x0 + x)) * 2;
            int16_t v = (int16_t)((raw[i] << 8) | raw[i + 1]);
            out[(size_t)y * w + x] = v == -32768 ? NAN : (float)v;
        }
    free(raw);
    return out;
}

#endif /* TP_TEST_HGT_H */
